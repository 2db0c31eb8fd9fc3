#!/bin/bash
# How evenly a full host slows a realtime fleet's autopilots (issue 46, item 6;
# docs/performance.md, "Realtime: the spread of the autopilots' rates"). RUNS realtime runs of N
# idle autopilots of each kind, SECONDS each; per run, from summary.json's autopilot_rate
# (docs/run.md, "Autopilot rates"): the lowest, median and highest ratio of an autopilot's
# achieved rate to its nominal one, their spread (highest - lowest), and the iteration lag p99.
#
#   bench/autopilots/rate_spread.sh [BUILD=build] [SECONDS=20] [RUNS=3] [N=8]
#       (KINDS="px4 arducopter" by default; SITLNET_PX4_DIR, SITLNET_ARDUPILOT_DIR as for
#       real_fleet.sh; WEIGHTS=equal: each robot in a cpu cgroup of equal weight,
#       equal_cpu_weights.sh)
set -euo pipefail
build=${1:-build} seconds=${2:-20} runs=${3:-3} n=${4:-8}
here=$(dirname "$0")
out=$(mktemp -d /tmp/sitlnet-rate-spread-XXXXXX)
trap 'rm -rf "$out"' EXIT
echo "weights,kind,robots,run,lowest,median,highest,spread,lag_p99_ms,load1"
for run in $(seq 1 "$runs"); do
  for kind in ${KINDS:-px4 arducopter}; do
    python3 "$here/fleet_scenario.py" "$kind" "$n" "$out/s.textproto" "$seconds" REALTIME
    load=$(cut -d' ' -f1 /proc/loadavg)
    rm -rf "$out/run"
    if [[ ${WEIGHTS:-} == equal ]]; then
      "$here/equal_cpu_weights.sh" rabench "$n" > /dev/null 2>&1 &
    fi
    if ! "$build/bin/sitlnet" run "$out/s.textproto" --out "$out/run" --no-progress > "$out/log" 2>&1; then
      echo "${WEIGHTS:-default},$kind,$n,$run,failed,,,,,$load"
      tail -2 "$out/log" >&2
      continue
    fi
    python3 - "$out/run/summary.json" "$kind" "$n" "$run" "$load" "${WEIGHTS:-default}" <<'PY'
import json, statistics, sys
s = json.load(open(sys.argv[1]))
kind, n, run, load, weights = sys.argv[2:7]
ratios = sorted(r["autopilot_rate"]["ratio"] for r in s["robots"] if r.get("autopilot_rate"))
if not ratios:
    print(f"{weights},{kind},{n},{run},no autopilot answered,,,,,{load}")
    sys.exit(0)
print(f"{weights},{kind},{n},{run},{ratios[0]:.3f},{statistics.median(ratios):.3f},{ratios[-1]:.3f},"
      f"{ratios[-1] - ratios[0]:.3f},{s['metrics']['lag_ms']['p99']:.2f},{load}")
PY
    wait  # equal_cpu_weights.sh ends with the scenario's cgroups
  done
done
