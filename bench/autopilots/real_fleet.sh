#!/bin/bash
# Cost of the real autopilots (issue 31, item 5; docs/performance.md, "The real autopilots"):
# fleets of N PX4 v1.14.4 or N ArduCopter SITL robots through the shipped manifests
# robot_images/px4 and robot_images/arducopter, idling on the ground (no ground station: each
# autopilot boots, runs its estimator and its MAVLink, and is never armed) for SECONDS of virtual
# time, in PACING lockstep or realtime. Per run, from summary.json: STF (wall time per virtual
# time of the loop), the loop's wall seconds, the CPU seconds of each autopilot's cgroup (user +
# system, every process of the robot) per virtual second, the mean over the fleet, and the lag's
# p99 (realtime: how late iterations started), the slowest autopilot's simulator messages per
# virtual second (in realtime, an autopilot short of CPU runs its loop slower); and the timing
# faults the autopilots report: for PX4 the lines of their logs (stale sensors, preflight
# failures, failsafes); ArduCopter says its own ("Main loop slow (..Hz < ..Hz)", "Gyro 1 rate
# ..Hz < loop ratex1.8 ..Hz") only to a ground station, so each ArduCopter gets a listener
# (tests/node_mavlink/status_texts.cjs) that asks for its pre-arm checks every wall second, and
# the status texts with "Hz < " are counted.
# The autopilots come from SITLNET_PX4_DIR and SITLNET_ARDUPILOT_DIR, as in the tests.
# The flight of a mixed fleet with a ground station is AutopilotFleetTest
# (4 + 4; SITLNET_FLEET_EACH=N for N + N).
#
#   sudo -E bench/autopilots/real_fleet.sh [BUILD=build] [SECONDS=20] [RUNS=3] [SIZES="1 4 8"] \
#       [PACING=lockstep]   (KINDS="px4 arducopter" by default: the kinds flown; ARGS="--lean":
#       every robot's extra args, e.g. the manifests' lean profile)
set -euo pipefail
build=${1:-build} seconds=${2:-20} runs=${3:-3} sizes=${4:-"1 4 8"} pacing=${5:-lockstep}
: "${SITLNET_PX4_DIR:?point it at a PX4 build (docs/autopilots.md)}"
: "${SITLNET_ARDUPILOT_DIR:?point it at an ArduCopter SITL build (docs/autopilots.md)}"
out=$(mktemp -d /tmp/sitlnet-real-autopilots-XXXXXX)
trap 'rm -rf "$out"' EXIT

scenario() {  # KIND N FILE: robots on a 3 m grid, each with the args in ARGS (e.g. --lean)
  # shellcheck disable=SC2086  # ARGS: words
  python3 "$(dirname "$0")/fleet_scenario.py" "$1" "$2" "$3" "$seconds" "${pacing^^}" ${ARGS:-}
}

# One status_texts.cjs per ArduCopter of the run RUN_PID (robots r0..rN-1, system ids 1..N), in
# the robot's namespace, once its log says its MAVLink server listens; output to
# $out/status_texts.<i>. Polls: a benchmark, not a test.
listen_to_arducopters() {
  local n=$1 run_pid=$2 i
  for ((i = 0; i < n; i++)); do
    until grep -qs 'SERIAL0 on TCP port 5760' "$out/run/robots/r$i.log"; do
      kill -0 "$run_pid" 2>/dev/null || return 0
      sleep 0.1
    done
    ip netns exec "rabench-r$i" node "$(dirname "$0")/../../tests/node_mavlink/status_texts.cjs" \
      127.0.0.1 5760 $((i + 1)) > "$out/status_texts.$i" 2>&1 &
  done
}

echo "kind,robots,run,pacing,stf_mean,loop_s,cpu_s_per_autopilot_per_virtual_s,lag_p99_ms,timing_complaints,load1,min_frames_per_virtual_s"
for run in $(seq 1 "$runs"); do
  for n in $sizes; do
    for kind in ${KINDS:-px4 arducopter}; do
      scenario "$kind" "$n" "$out/s.textproto"
      rm -rf "$out/run" "$out"/status_texts.*
      load=$(cut -d' ' -f1 /proc/loadavg)
      "$build/bin/sitlnet" run "$out/s.textproto" --out "$out/run" --no-progress > "$out/log" 2>&1 &
      run_pid=$!
      [[ $kind == arducopter ]] && listen_to_arducopters "$n" "$run_pid"
      if ! wait "$run_pid"; then
        # A fleet too large for the host (an autopilot too slow to answer in time) is a result.
        echo "$kind,$n,$run,$pacing,failed,,,,,$load,"
        echo "run failed ($kind, $n robots): $(grep -m1 'sitlnet run:.*robot' "$out/log" || tail -1 "$out/log")" >&2
        continue
      fi
      # PX4's one boot-time "Preflight Fail: ekf2 missing data" before its startup script returned
      # is its own (px4_flight_test.cc, Complaints) and not counted.
      wait  # the listeners exit when their autopilot's connection closes
      if [[ $kind == arducopter ]]; then
        complaints=$(cat "$out"/status_texts.* 2>/dev/null | grep -c 'Hz < ' || true)
        grep -h 'Hz < ' "$out"/status_texts.* 2>/dev/null | sort -u -k3 | head -5 >&2 || true
      else
      complaints=$(awk 'FNR == 1 { booted = 0 } /Startup script returned successfully/ { booted = 1 }
        !booted && /Preflight Fail: ekf2 missing data/ { next }
        tolower($0) ~ /stale|preflight fail|failsafe/ { n++; print FILENAME ": " $0 > "/dev/stderr" }
        END { print n + 0 }' "$out"/run/robots/*.log 2> >(sort -u -k2 | head -5 >&2))
      fi
      python3 - "$out/run/summary.json" "$kind" "$n" "$run" "$seconds" "$load" "$pacing" "$complaints" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
kind, n, run, seconds, load = sys.argv[2], int(sys.argv[3]), sys.argv[4], float(sys.argv[5]), sys.argv[6]
pacing, complaints = sys.argv[7], sys.argv[8]
cpu = [r["cgroup"]["cpu_s"] for r in s["robots"] if r.get("cgroup")]
per = f"{sum(cpu) / len(cpu) / seconds:.3f}" if cpu else ""
m = s["metrics"]
# The slowest autopilot's rate: JSON frames (ArduCopter: 1000 per virtual second when it keeps
# its loop rate) or PX4 actuator controls (250: one per HIL_SENSOR).
def frames(r):
    p = r.get("physics") or {}
    return (p.get("px4") or {}).get("actuator_controls", 0) if kind == "px4" else p.get("json_frames", 0)
slowest = min(frames(r) for r in s["robots"]) / seconds
print(f'{kind},{n},{run},{pacing},{m["stf"]["mean"]:.4f},{s["resources"]["loop_s"]:.3f},{per},'
      f'{m["lag_ms"]["p99"]:.3f},{complaints},{load},{slowest:.0f}')
PY
    done
  done
done
