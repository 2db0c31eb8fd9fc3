#!/bin/bash
# The realtime soak of issue 46's goals (docs/performance.md, "Realtime: a 30-minute soak"): a
# mixed fleet of EACH PX4 and EACH ArduCopter with a ground station robot, realtime pacing, for
# MINUTES of wall time, flying one mission after another. A GCS on the host
# (tests/node_mavlink/fleet_gcs.cjs, through `sitlnet run --gcs`) arms every vehicle, takes it to
# 5 m, flies a 4 m square from its home, lands it and waits for every disarm; then the next
# mission starts. Every 30 s soak_sample.py writes each process's resident memory (the run's own
# and every process in a robot's cgroup). At the end soak_report.py prints: missions flown,
# each process's memory growth (median of the first 5 minutes against the last 5), the
# iteration lag p99 of the first and last 5 minutes (metrics.csv), and the fault lines (the
# robots' logs; the vehicles' STATUSTEXTs with "Hz < " or PX4's errors).
#
#   sudo -E bench/autopilots/soak.sh [BUILD=build] [MINUTES=30] [EACH=4]
#       (SITLNET_PX4_DIR, SITLNET_ARDUPILOT_DIR as for real_fleet.sh; SOAK_OUT=DIR keeps the
#       run folder, the samples and the GCS logs there instead of a temporary folder)
set -euo pipefail
build=${1:-build} minutes=${2:-30} each=${3:-4}
: "${SITLNET_PX4_DIR:?point it at a PX4 build (docs/autopilots.md)}"
: "${SITLNET_ARDUPILOT_DIR:?point it at an ArduCopter SITL build (docs/autopilots.md)}"
here=$(cd "$(dirname "$0")" && pwd)
if [[ -n ${SOAK_OUT:-} ]]; then
  out=$SOAK_OUT
  mkdir -p "$out"
else
  out=$(mktemp -d /tmp/sitlnet-soak-XXXXXX)
  trap 'rm -rf "$out"' EXIT
fi
rm -rf "$out/run" "$out"/mission.*.log "$out/samples.csv"

name=soak
python3 "$here/soak_scenario.py" "$each" $(( (minutes + 3) * 60 )) > "$out/soak.textproto"
port=$(python3 -c 'import socket; s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
vehicles=()
for ((i = 1; i <= each; i++)); do vehicles+=("px4:$i"); done
for ((i = each + 1; i <= 2 * each; i++)); do vehicles+=("arducopter:$i"); done

echo "soak: $each PX4 + $each ArduCopter, $minutes min realtime, out $out, load $(cut -d' ' -f1-3 /proc/loadavg)"
"$build/bin/sitlnet" run "$out/soak.textproto" --out "$out/run" --no-progress \
  --gcs "udp:127.0.0.1:$port" > "$out/run.log" 2>&1 &
run_pid=$!
python3 "$here/soak_sample.py" "$run_pid" "$name" 30 > "$out/samples.csv" &
sampler_pid=$!
gcs_pid=
stop() {
  [[ -n $gcs_pid ]] && kill "$gcs_pid" 2>/dev/null || true
  kill -INT "$run_pid" 2>/dev/null || true
  wait "$run_pid" || true
  kill "$sampler_pid" 2>/dev/null || true
  wait "$sampler_pid" 2>/dev/null || true
}
trap 'stop; [[ -z ${SOAK_OUT:-} ]] && rm -rf "$out"' EXIT

end=$(( $(date +%s) + minutes * 60 ))
mission=0
while (( $(date +%s) < end )) && kill -0 "$run_pid" 2>/dev/null; do
  mission=$((mission + 1))
  started=$(date +%s)
  node "$here/../../tests/node_mavlink/fleet_gcs.cjs" "$port" 5 5 4,0/4,4/0,4/0,0 "${vehicles[@]}" \
    > "$out/mission.$mission.log" 2>&1 &
  gcs_pid=$!
  status=0
  wait "$gcs_pid" || status=$?
  gcs_pid=
  echo "mission $mission: exit $status, $(( $(date +%s) - started )) s wall, load $(cut -d' ' -f1 /proc/loadavg)"
done
stop
trap '[[ -z ${SOAK_OUT:-} ]] && rm -rf "$out"' EXIT
python3 "$here/soak_report.py" "$out" "$minutes"
