#!/usr/bin/env bash
# The sweep's performance goal (issue 48; docs/performance.md, "Sweep: 40 case-study points"):
# with --jobs at its default, a sweep of 40 case-study points should end within 1.2 times
# (40 x one run's wall time / cores). Measures, in one session: one run alone (`sitlnet run`,
# RUNS times), the 40-point sweep (seeds 1-40, --jobs default), then one run alone again (RUNS
# times): the runs before and after bound how far the shared host drifted meanwhile. Prints each
# wall time with the 1-minute load average at its start, then the ratio
#   sweep wall / (40 x median single-run wall / cores)
# with the median of all single runs, and with the fastest and slowest of them (the bounds).
#
#   sudo bench/sweep/forty_points.sh [--build DIR] [--out DIR] [--duration-s S] [--runs N]
#
# The case study is scenarios/arrow_flocking.textproto in lockstep pacing (as scripts/reproduce-
# paper runs it): unpaced, so a run is bound by the CPU and runs at once compete for the cores.
# --duration-s shortens its 200 s flight (default 200: the whole case study, untouched).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build="$root/build"
out="/tmp/sitlnet-forty-$(date -u +%Y%m%d-%H%M%S)"
duration_s=200
runs=2
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --duration-s) duration_s=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--out DIR] [--duration-s S] [--runs N]" >&2; exit 2 ;;
  esac
done
sitlnet="$build/bin/sitlnet"
[ -x "$sitlnet" ] && [ -x "$build/bin/flocker" ] || { echo "$0: build sitlnet and flocker in $build first" >&2; exit 2; }
scenario="$root/scenarios/arrow_flocking.textproto"
cores=$(nproc)  # sched_getaffinity, as the sweep's default --jobs counts
mkdir -p "$out"
echo "kind,index,wall_s,load1_at_start" > "$out/times.csv"

load1() { cut -d' ' -f1 /proc/loadavg; }
now_ns() { date +%s%N; }
seconds_since() { awk -v a="$1" -v b="$(now_ns)" 'BEGIN { printf "%.2f", (b - a) / 1e9 }'; }

single() {  # single INDEX: one run alone, seeds 101, 102, ... (no sweep seed)
  local dir="$out/single$1" load start wall
  load=$(load1)
  start=$(now_ns)
  "$sitlnet" run "$scenario" --out "$dir" --pacing lockstep --duration "$duration_s" \
    --seed $((100 + $1)) --no-progress > "$dir.log" 2>&1 ||
    { echo "$0: run $1 failed: $dir.log" >&2; exit 1; }
  wall=$(seconds_since "$start")
  echo "single,$1,$wall,$load" >> "$out/times.csv"
  echo "one run alone ($1): ${wall} s wall, load $load"
}

echo "# $(date -u) $cores cores, $(uname -r), case study ${duration_s} s lockstep" | tee "$out/machine.txt"
for i in $(seq 1 "$runs"); do single "$i"; done
load=$(load1)
start=$(now_ns)
status=0
"$sitlnet" sweep "$scenario" --out "$out/sweep" --seeds 1-40 \
  --set timing.pacing=PACING_LOCKSTEP --set "timing.duration_ms=$((duration_s * 1000))" \
  > "$out/sweep.log" 2>&1 || status=$?
wall=$(seconds_since "$start")
# Exit 1: a point failed. Its run ended early, so the sweep's wall time is too short to count.
[ "$status" -le 1 ] || { echo "$0: the sweep exited $status: $out/sweep.log" >&2; exit 1; }
failed=$(grep -c ',failed,' "$out/sweep/points.csv" || true)
echo "sweep,40,$wall,$load" >> "$out/times.csv"
echo "the sweep of 40 points, --jobs default ($(sed -n 's/.* \([0-9]*\) at once$/\1/p' "$out/sweep.log" | head -1)): ${wall} s wall, load $load"
for i in $(seq $((runs + 1)) $((2 * runs))); do single "$i"; done
echo "# end $(date -u), load average $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$out/machine.txt"

python3 - "$out/times.csv" "$cores" "$failed" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
cores = int(sys.argv[2])
if int(sys.argv[3]):
    print(f"{sys.argv[3]} of the 40 points failed (points.csv says why): no ratio")
    sys.exit(1)
single = [float(r["wall_s"]) for r in rows if r["kind"] == "single"]
sweep = next(float(r["wall_s"]) for r in rows if r["kind"] == "sweep")
def ratio(one):
    return sweep / (40 * one / cores)
median = statistics.median(single)
print(f"single runs: {', '.join(f'{s:.2f}' for s in single)} s (median {median:.2f})")
print(f"ratio = sweep / (40 x one run / {cores} cores) = {ratio(median):.3f} with the median run; "
      f"{ratio(max(single)):.3f} to {ratio(min(single)):.3f} with the slowest and the fastest "
      f"(goal: at most 1.2)")
PY
