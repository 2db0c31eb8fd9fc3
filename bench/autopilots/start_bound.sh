#!/bin/bash
# Whether fleets of the real PX4 start in lockstep (issue 46, item 5; docs/performance.md,
# "The real autopilots"): RUNS runs of N PX4 v1.14.4 through the shipped manifest, each flown 3 s
# of virtual time, with BUSY busy loops beside them. Per run: whether it started, the wall
# seconds from `up` to the clock's start (summary.json's resources.startup_s) and the host's load.
#
#   sudo -E bench/autopilots/start_bound.sh [BUILD=build] [RUNS=10] [SIZES="16 24"] [BUSY=0]
set -euo pipefail
build=${1:-build} runs=${2:-10} sizes=${3:-"16 24"} busy=${4:-0}
: "${SITLNET_PX4_DIR:?point it at a PX4 build (docs/autopilots.md)}"
out=$(mktemp -d /tmp/sitlnet-start-bound-XXXXXX)
busy_pids=()
cleanup() {
  for pid in "${busy_pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  rm -rf "$out"
}
trap cleanup EXIT
for ((i = 0; i < busy; i++)); do
  sh -c 'while :; do :; done' &
  busy_pids+=($!)
done

echo "robots,run,started,startup_s,load1"
for n in $sizes; do
  python3 - "$n" "$out/px$n.textproto" <<'PY'
import sys
n, path = int(sys.argv[1]), sys.argv[2]
side = int(n ** 0.5 + 0.999)
with open(path, "w") as f:
    f.write('name: "sbbench"\naddresses { wlan_subnet: "10.68.0.0/16" ctl_subnet: "10.69.0.0/16" }\n')
    for i in range(n):
        f.write(f'robot {{ name: "r{i}" position_m {{ x: {3 * (i % side)} y: {3 * (i // side)} z: 0.2 }} '
                f'px4_sim_port: 4560 image: "px4" args: ["--sysid", "{i + 1}"] }}\n')
    f.write("timing { duration_ms: 3000 pacing: PACING_LOCKSTEP }\n")
PY
  for ((run = 1; run <= runs; run++)); do
    load=$(cut -d' ' -f1 /proc/loadavg)
    if "$build/bin/sitlnet" run "$out/px$n.textproto" --out "$out/run" > "$out/log" 2>&1; then
      startup=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['resources']['startup_s'])" "$out/run/summary.json")
      echo "$n,$run,yes,$startup,$load"
    else
      echo "$n,$run,no,,$load  # $(grep 'sitlnet run: ' "$out/log" | tail -1)"
    fi
    rm -rf "$out/run"
  done
done
