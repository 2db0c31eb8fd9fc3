#!/bin/bash
# What the 64-robot lockstep run spends its time on (docs/performance.md,
# "End to end"): the same flight with one cost taken away at a time.
#
#   sudo bench/scale/ablation.sh [--build DIR] [--out DIR] [--runs R] [--seconds S] [--robots N]
#                                [--only NAME,NAME]
#
# Lockstep variants: baseline (defaults: RK4, obstacle culling, 2 physics threads);
# no_culling (SITLNET_PHYSICS_CULL_TILE_M=0: every robot's model holds every obstacle);
# SITLNET_PHYSICS_THREADS=1; SITLNET_PHYSICS_INTEGRATOR=euler; no obstacles
# (gen_scenario.py --no-obstacles); no obstacles + euler. Realtime variants: realtime (as
# run.sh: sitlnet's threads at SCHED_FIFO, its default (10 when measured, 60 now), images normal),
# realtime_normal (--rt-priority 0) and realtime_fifo_all (the whole run under `chrt -f 10`,
# images included: sitlnet leaves an inherited realtime policy alone; about one core for S s).
# Rows in OUT/ablation_runs.csv, medians in docs/scale_ablation.csv. Called by run.sh.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build="$root/build"
out="/tmp/sitlnet-scale-ablation-$(date -u +%Y%m%d-%H%M%S)"
runs=3
seconds=20
n=64
only=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --robots) n=$2; shift 2 ;;
    --only) only=",$2,"; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--out DIR] [--runs R] [--seconds S] [--robots N]" >&2; exit 2 ;;
  esac
done
sitlnet="$build/bin/sitlnet"
mkdir -p "$out"
"$here/gen_scenario.py" "$n" "$out/scale$n.textproto"
"$here/gen_scenario.py" "$n" "$out/scale${n}_noobs.textproto" --no-obstacles
echo "variant,$("$here/extract.py" --header)" > "$out/ablation_runs.csv"
# variant:scenario:threads:integrator:pacing:priority:cull tile (m; "-": default)
variants="baseline:scale$n:2:rk4:lockstep:default:- no_culling:scale$n:2:rk4:lockstep:default:0
          threads1:scale$n:1:rk4:lockstep:default:- euler:scale$n:2:euler:lockstep:default:-
          no_obstacles:scale${n}_noobs:2:rk4:lockstep:default:-
          no_obstacles_euler:scale${n}_noobs:2:euler:lockstep:default:-
          realtime:scale$n:2:rk4:realtime:default:- realtime_normal:scale$n:2:rk4:realtime:normal:-
          realtime_fifo_all:scale$n:2:rk4:realtime:fifo:-"
for run in $(seq 1 "$runs"); do  # round-robin, as run.sh
  for variant in $variants; do
    IFS=: read -r name scenario threads integrator pacing priority cull <<< "$variant"
    [ -z "$only" ] || [[ "$only" == *",$name,"* ]] || continue
    prio=()
    rt=()
    [ "$priority" = fifo ] && prio=(chrt -f 10)
    [ "$priority" = normal ] && rt=(--rt-priority 0)
    cull_env=()
    [ "$cull" = - ] || cull_env=(SITLNET_PHYSICS_CULL_TILE_M="$cull")
    dir="$out/$name-$run"
    load1=$(cut -d' ' -f1 /proc/loadavg)
    start=$(date +%s%N)
    status=0
    env SITLNET_PHYSICS_THREADS="$threads" SITLNET_PHYSICS_INTEGRATOR="$integrator" \
      "${cull_env[@]}" "${prio[@]}" "$sitlnet" run "$out/$scenario.textproto" --out "$dir" \
      --pacing "$pacing" --duration "$seconds" --seed "$run" --no-progress "${rt[@]}" \
      > "$dir.log" 2>&1 || status=$?
    end=$(date +%s%N)
    wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", (b - a) / 1e9 }')
    echo "$(date -u +%H:%M:%S) $name run $run: ${wall}s wall, exit $status, load $load1"
    if [ -f "$dir/summary.json" ]; then
      echo "$name,$("$here/extract.py" "$dir" "$n" "$pacing" "$run" "$wall" "$load1")" >> "$out/ablation_runs.csv"
    else
      "$sitlnet" down "scale$n" > /dev/null 2>&1 || true
    fi
    rm -f "$dir/medium.pcap" "$dir/deliveries.csv" "$dir/trajectories.csv"
  done
done
"$here/medians.py" "$out/ablation_runs.csv" "$root/docs/scale_ablation.csv" --group variant
echo "medians: $root/docs/scale_ablation.csv, raw: $out"
