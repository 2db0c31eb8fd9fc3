#!/bin/bash
# End-to-end scale benchmark of `sitlnet run` (docs/performance.md, "End to end").
#
#   sudo bench/scale/run.sh [--build DIR] [--out DIR] [--plan "N:PACING:RUNS:SECONDS ..."]
#                           [--no-ablation] [--docs DIR]
#
# For every point of the plan: generates the flocking scenario for N robots
# (gen_scenario.py), runs `sitlnet run` RUNS times with seeds 1..RUNS, one run
# at a time, extracts one row per run into OUT/runs.csv (extract.py), then
# writes the medians per point to docs/scale.csv and draws docs/img/scale_*.png
# (plot.gp); --docs DIR writes them to DIR/ and DIR/img/ instead (scripts/reproduce-paper). Each run tears its scenario down itself; the large per-run files
# (pcap, deliveries, trajectories) are deleted after extraction. Then, unless
# --no-ablation, ablation.sh (what the 64-robot lockstep run spends its time on).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build="$root/build"
out="/tmp/sitlnet-scale-$(date -u +%Y%m%d-%H%M%S)"
# Default plan (robots:pacing:runs:simulated seconds), about 15 min on the
# 2-core development machine: fewer runs and shorter flights for 64 and 128
# robots, whose lockstep runs are slower than real time.
plan="1:lockstep:5:60 4:lockstep:5:60 16:lockstep:5:60 32:lockstep:5:30 64:lockstep:3:20 128:lockstep:2:10
      1:realtime:4:20 4:realtime:4:20 16:realtime:4:20 32:realtime:4:20 64:realtime:3:20 128:realtime:2:10"
ablation=1
docs="$root/docs"
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --plan) plan=$2; shift 2 ;;
    --no-ablation) ablation=0; shift ;;
    --docs) docs=$2; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--out DIR] [--plan \"N:PACING:RUNS:SECONDS ...\"] [--no-ablation] [--docs DIR]" >&2; exit 2 ;;
  esac
done
sitlnet="$build/bin/sitlnet"
[ -x "$sitlnet" ] && [ -x "$build/bin/flocker" ] || { echo "$0: build sitlnet and flocker in $build first" >&2; exit 2; }
mkdir -p "$out"
"$here/extract.py" --header > "$out/runs.csv"
echo "# $(date -u) nproc=$(nproc) $(uname -r) plan: $plan" > "$out/machine.txt"
# Round-robin over the points (run 1 of every point, then run 2, ...): the
# host is shared, so a noisy minute spreads over all points instead of
# spoiling one.
max_runs=0
for point in $plan; do
  IFS=: read -r n pacing runs seconds <<< "$point"
  [ -f "$out/scale$n.textproto" ] || "$here/gen_scenario.py" "$n" "$out/scale$n.textproto"
  [ "$runs" -gt "$max_runs" ] && max_runs=$runs
done
for run in $(seq 1 "$max_runs"); do
  for point in $plan; do
    IFS=: read -r n pacing runs seconds <<< "$point"
    [ "$run" -le "$runs" ] || continue
    dir="$out/scale$n-$pacing-$run"
    load1=$(cut -d' ' -f1 /proc/loadavg)
    start=$(date +%s%N)
    status=0
    "$sitlnet" run "$out/scale$n.textproto" --out "$dir" --pacing "$pacing" \
      --duration "$seconds" --seed "$run" --no-progress > "$dir.log" 2>&1 || status=$?
    end=$(date +%s%N)
    wall=$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", (b - a) / 1e9 }')
    echo "$(date -u +%H:%M:%S) n=$n $pacing run $run: ${wall}s wall, exit $status, load $load1"
    if [ -f "$dir/summary.json" ]; then
      "$here/extract.py" "$dir" "$n" "$pacing" "$run" "$wall" "$load1" >> "$out/runs.csv"
    else
      echo "  no summary.json (see $dir.log); taking scale$n down" >&2
      "$sitlnet" down "scale$n" > /dev/null 2>&1 || true
    fi
    rm -f "$dir/medium.pcap" "$dir/deliveries.csv" "$dir/trajectories.csv"
  done
done
cat /proc/loadavg >> "$out/machine.txt"
mkdir -p "$docs/img"
"$here/medians.py" "$out/runs.csv" "$docs/scale.csv"
cp "$out/runs.csv" "$docs/scale_runs.csv"
gnuplot -e "csv='$docs/scale.csv'; outdir='$docs/img'" "$here/plot.gp"
echo "medians: $docs/scale.csv, runs: $docs/scale_runs.csv, plots: $docs/img/scale_*.png, raw: $out"
if [ "$ablation" = 1 ]; then
  "$here/ablation.sh" --build "$build" --out "$out/ablation"
fi
"$here/table.py" "$docs/scale.csv" $([ "$ablation" = 1 ] && echo "$root/docs/scale_ablation.csv")
