#!/bin/bash
# Lockstep cost of autopilots in the coordinator's clock (issue 14; docs/performance.md,
# "Autopilots"): fleets of N test_autopilot robots, each climbing to 10 m and flying to a
# waypoint with MAVLink telemetry at 10 Hz on the radio, speaking ArduPilot's JSON protocol
# (400 Hz frames) or PX4's simulator MAVLink (250 Hz HIL_SENSOR), and for comparison the same N
# flockers (native protocol, one state per 10 ms iteration). Per run: STF (wall time per virtual
# time of the loop) and, for the autopilots, the wall cost per frame (JSON frame or HIL_SENSOR
# answered).
#
#   sudo bench/autopilots/fleet.sh [BUILD=build] [SECONDS=10] [RUNS=3] [SIZES="4 16 64"]
set -euo pipefail
build=${1:-build} seconds=${2:-10} runs=${3:-3} sizes=${4:-"4 16 64"}
out=$(mktemp -d /tmp/sitlnet-autopilots-XXXXXX)
trap 'rm -rf "$out"' EXIT

scenario() {  # KIND N FILE: robots on a 10 m grid
  python3 - "$1" "$2" "$3" "$seconds" <<'PY'
import sys
kind, n, path, seconds = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
side = int(n ** 0.5 + 0.999)
with open(path, "w") as f:
    f.write(f'name: "apbench"\naddresses {{ wlan_subnet: "10.66.0.0/16" ctl_subnet: "10.67.0.0/16" }}\n')
    for i in range(n):
        x, y = 10 * (i % side), 10 * (i // side)
        if kind == "json":
            f.write(f'robot {{ name: "r{i}" position_m {{ x: {x} y: {y} z: 0.2 }} ardupilot_json_port: 9002 '
                    f'image: "test_autopilot" args: ["--json-port", "9002", "--waypoint", "{x + 20},{y}", '
                    f'"--telemetry", "10.66.255.255:14550"] }}\n')
        elif kind == "px4":
            f.write(f'robot {{ name: "r{i}" position_m {{ x: {x} y: {y} z: 0.2 }} px4_sim_port: 4560 '
                    f'image: "test_autopilot" args: ["--px4-port", "4560", "--waypoint", "{x + 20},{y}", '
                    f'"--telemetry", "10.66.255.255:14550"] }}\n')
        else:
            f.write(f'robot {{ name: "r{i}" position_m {{ x: {x} y: {y} z: 0.2 }} image: "flocker" '
                    f'args: ["--target", "{x + 1000},{y}"] }}\n')
    f.write(f"timing {{ duration_ms: {seconds * 1000} pacing: PACING_LOCKSTEP }}\n")
PY
}

echo "kind,robots,run,stf_mean,loop_s,frames,us_per_frame"
for run in $(seq 1 "$runs"); do
  for n in $sizes; do
    for kind in json px4 flocker; do
      scenario "$kind" "$n" "$out/s.textproto"
      rm -rf "$out/run"
      if ! "$build/bin/sitlnet" run "$out/s.textproto" --out "$out/run" --no-progress > "$out/log" 2>&1; then
        echo "run failed ($kind, $n robots): $(tail -3 "$out/log")" >&2
        failed=$(grep -o 'robot "r[0-9]*"' "$out/log" | head -1 | cut -d'"' -f2)
        [ -n "$failed" ] && { echo "robots/$failed.log:" >&2; cat "$out/run/robots/$failed.log" >&2; }
        exit 1
      fi
      python3 - "$out/run/summary.json" "$kind" "$n" "$run" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
kind, n, run = sys.argv[2], int(sys.argv[3]), sys.argv[4]
def frames_of(r):
    if kind == "json":
        return r["physics"].get("json_frames", 0)
    if kind == "px4":
        return (r["physics"].get("px4") or {}).get("actuator_controls", 0)
    return 0
frames = sum(frames_of(r) for r in s["robots"])
loop_s = s["resources"]["loop_s"]
per_frame = f"{loop_s / frames * 1e6:.2f}" if frames else ""
print(f'{kind},{n},{run},{s["metrics"]["stf"]["mean"]:.4f},{loop_s:.3f},{frames},{per_frame}')
PY
    done
  done
done
