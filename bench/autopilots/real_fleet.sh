#!/bin/bash
# Lockstep cost of the real autopilots (issue 31, item 5; docs/performance.md, "The real
# autopilots in lock-step"): fleets of N PX4 v1.14.4 or N ArduCopter SITL robots through the
# shipped manifests robot_images/px4 and robot_images/arducopter, idling on the ground (no ground
# station: each autopilot boots, runs its estimator and its MAVLink, and is never armed) for
# SECONDS of virtual time. Per run: STF (wall time per virtual time of the loop, from
# summary.json), the loop's wall seconds, and the CPU seconds of each autopilot's cgroup (user +
# system, every process of the robot) per virtual second, the mean over the fleet.
# The autopilots come from SITLNET_PX4_DIR and SITLNET_ARDUPILOT_DIR, as in the tests.
#
#   sudo -E bench/autopilots/real_fleet.sh [BUILD=build] [SECONDS=20] [RUNS=3] [SIZES="1 4 8"]
set -euo pipefail
build=${1:-build} seconds=${2:-20} runs=${3:-3} sizes=${4:-"1 4 8"}
: "${SITLNET_PX4_DIR:?point it at a PX4 build (docs/autopilots.md)}"
: "${SITLNET_ARDUPILOT_DIR:?point it at an ArduCopter SITL build (docs/autopilots.md)}"
out=$(mktemp -d /tmp/sitlnet-real-autopilots-XXXXXX)
trap 'rm -rf "$out"' EXIT

scenario() {  # KIND N FILE: robots on a 3 m grid
  python3 - "$1" "$2" "$3" "$seconds" <<'PY'
import sys
kind, n, path, seconds = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
side = int(n ** 0.5 + 0.999)
with open(path, "w") as f:
    f.write('name: "rabench"\naddresses { wlan_subnet: "10.68.0.0/16" ctl_subnet: "10.69.0.0/16" }\n')
    for i in range(n):
        x, y = 3 * (i % side), 3 * (i // side)
        link = 'px4_sim_port: 4560 image: "px4"' if kind == "px4" else \
               'ardupilot_json_port: 9002 image: "arducopter"'
        f.write(f'robot {{ name: "r{i}" position_m {{ x: {x} y: {y} z: 0.2 }} {link} '
                f'args: ["--sysid", "{i + 1}"] }}\n')
    f.write(f"timing {{ duration_ms: {seconds * 1000} pacing: PACING_LOCKSTEP }}\n")
PY
}

echo "kind,robots,run,stf_mean,loop_s,cpu_s_per_autopilot_per_virtual_s,load1"
for run in $(seq 1 "$runs"); do
  for n in $sizes; do
    for kind in px4 arducopter; do
      scenario "$kind" "$n" "$out/s.textproto"
      rm -rf "$out/run"
      load=$(cut -d' ' -f1 /proc/loadavg)
      if ! "$build/bin/sitlnet" run "$out/s.textproto" --out "$out/run" --no-progress > "$out/log" 2>&1; then
        # A fleet too large for the host (an autopilot too slow to answer in time) is a result.
        echo "$kind,$n,$run,failed,,,$load"
        echo "run failed ($kind, $n robots): $(grep -m1 'sitlnet run:.*robot' "$out/log" || tail -1 "$out/log")" >&2
        continue
      fi
      python3 - "$out/run/summary.json" "$kind" "$n" "$run" "$seconds" "$load" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
kind, n, run, seconds, load = sys.argv[2], int(sys.argv[3]), sys.argv[4], float(sys.argv[5]), sys.argv[6]
cpu = [r["cgroup"]["cpu_s"] for r in s["robots"] if r.get("cgroup")]
per = f"{sum(cpu) / len(cpu) / seconds:.3f}" if cpu else ""
print(f'{kind},{n},{run},{s["metrics"]["stf"]["mean"]:.4f},{s["resources"]["loop_s"]:.3f},{per},{load}')
PY
    done
  done
done
