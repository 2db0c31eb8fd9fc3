#!/bin/bash
# How often PX4 v1.14.4 says its timers stalled in lockstep pacing (issue 42, item 2;
# docs/autopilots-evidence.md, "PX4's HRT thread in lockstep"). Boots RUNS times one PX4 through
# the shipped manifest robot_images/px4 in `sitlnet run`, lockstep pacing, for SECONDS of
# virtual time (PX4's clock is sitlnet's: the same stepping as Px4FlightTest). With FLY=1 a
# node-mavlink ground station also flies it (tests/node_mavlink/fly_px4.cjs: arm, 5 m up, 50 m
# north, land), as Px4FlightTest does; the run then lasts until PX4 disarms or SECONDS end.
# A run counts as starved when robots/<name>.log says "Battery unhealthy" or "Failsafe"
# (PX4's own words when its battery reading is over 5 s old). LOAD=N starts N busy loops
# (`while :; do :; done`) beside it for the whole measurement and stops them by pid at the end.
# Prints one CSV line per run and a total; a starved run's log is kept under KEEP (default
# /tmp/px4-starved-logs).
# The autopilot comes from SITLNET_PX4_DIR, as in the tests.
#
#   sudo -E bench/autopilots/px4_starvation.sh [BUILD=build] [RUNS=50] [SECONDS=40]
#       (env: LOAD=0, FLY=0, KEEP=/tmp/px4-starved-logs)
set -euo pipefail
build=${1:-build} runs=${2:-50} seconds=${3:-40}
load=${LOAD:-0} fly=${FLY:-0} keep=${KEEP:-/tmp/px4-starved-logs}
: "${SITLNET_PX4_DIR:?point it at a PX4 build (docs/autopilots.md)}"
here=$(cd "$(dirname "$0")/../.." && pwd)
sitlnet=$(realpath "$build/bin/sitlnet")
out=$(mktemp -d /tmp/sitlnet-px4-starvation-XXXXXX)
mkdir -p "$keep"
busy=()
cleanup() {
  for pid in "${busy[@]}"; do kill "$pid" 2>/dev/null || true; done
  "$sitlnet" down "$out/s.textproto" > /dev/null 2>&1 || true
  rm -rf "$out"
}
trap cleanup EXIT
for ((i = 0; i < load; i++)); do
  bash -c 'while :; do :; done' &
  busy+=($!)
done

cat > "$out/s.textproto" <<EOF
name: "px4starve"
addresses { wlan_subnet: "10.66.0.0/16" ctl_subnet: "10.67.0.0/16" }
robot { name: "px" position_m { x: 3 y: -2 z: 0.2 } image: "px4" px4_sim_port: 4560 }
timing { duration_ms: $((seconds * 1000)) pacing: PACING_LOCKSTEP }
EOF

starved=0
echo "run,load,fly,starved,wall_s,load1,first_complaint"
for run in $(seq 1 "$runs"); do
  rm -rf "$out/run"
  load1=$(cut -d' ' -f1 /proc/loadavg)
  start=$(date +%s.%N)
  "$sitlnet" run "$out/s.textproto" --out "$out/run" --no-progress > "$out/log" 2>&1 &
  run_pid=$!
  if [[ $fly == 1 ]]; then
    until ip netns list | grep -q '^px4starve-px' || ! kill -0 "$run_pid" 2>/dev/null; do
      sleep 0.1
    done
    "$sitlnet" exec --scenario px4starve px -- node "$here/tests/node_mavlink/fly_px4.cjs" \
      5 50 0 300 > "$out/fly" 2>&1 || true
    kill -INT "$run_pid" 2>/dev/null || true
  fi
  wait "$run_pid" || true
  wall=$(echo "$(date +%s.%N) - $start" | bc)
  log="$out/run/robots/px.log"
  complaint=$(grep -m1 -E 'Battery unhealthy|Failsafe' "$log" 2>/dev/null || true)
  if [[ -n $complaint ]]; then
    starved=$((starved + 1))
    cp "$log" "$keep/px-$(date +%s)-$run.log"
  fi
  if ! grep -q 'Startup script returned successfully' "$log" 2>/dev/null; then
    echo "run $run: PX4 did not boot: $(tail -1 "$out/log")" >&2
  fi
  printf '%d,%d,%d,%d,%.1f,%s,"%s"\n' "$run" "$load" "$fly" "$([[ -n $complaint ]] && echo 1 || echo 0)" \
    "$wall" "$load1" "${complaint//\"/}"
done
echo "starved $starved of $runs (LOAD=$load FLY=$fly SECONDS=$seconds)"
