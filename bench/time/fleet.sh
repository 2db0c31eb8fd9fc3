#!/bin/bash
# How many robots running wall-clock programs (bench/time/wallclock: a 10 Hz UDP broadcaster and
# ping -i 0.1, in dilated time) a realtime run holds with lag p99 < 2 ms, per realtime factor
# (docs/performance.md, "Dilated time"). For each factor in FACTORS, fleets of 16, 32, ..., 256
# robots until one misses; then the smallest factor (halving from 1) at which 256 robots hold.
#
#   sudo bench/time/fleet.sh [BUILD=build] [SECONDS=10] [OUT=/tmp/sitlnet-fleet-...]
#
# One row per run into OUT/runs.csv (bench/scale/extract.py's columns, then factor).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build} seconds=${2:-10}
out=${3:-/tmp/sitlnet-fleet-$(date -u +%Y%m%d-%H%M%S)}
mkdir -p "$out"
"$here/../scale/extract.py" --header | sed 's/$/,factor/' > "$out/runs.csv"

scenario() {  # N FACTOR FILE: robots on a 10 m grid, each pinging the next one.
  python3 - "$1" "$2" "$3" "$here/wallclock/image.textproto" "$seconds" <<'PY'
import sys
n, factor, path, image, seconds = int(sys.argv[1]), sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5])
side = int(n ** 0.5 + 0.999)
with open(path, "w") as f:
    f.write('name: "fleet"\naddresses { wlan_subnet: "10.64.0.0/16" }\n')
    for i in range(n):
        peer = (i + 1) % n + 1
        f.write(f'robot {{ name: "r{i}" position_m {{ x: {10 * (i % side)} y: {10 * (i // side)} z: 0.2 }} '
                f'image: "{image}" args: "10.64.{peer // 256}.{peer % 256}" }}\n')
    f.write(f"timing {{ duration_ms: {seconds * 1000} pacing: PACING_REALTIME realtime_factor: {factor} }}\n")
PY
}

run() {  # N FACTOR -> prints lag p99 (ms), appends the row
  local n=$1 factor=$2 dir="$out/run-$1-$2"
  scenario "$n" "$factor" "$out/fleet.textproto"
  local start load1
  load1=$(cut -d' ' -f1 /proc/loadavg); start=$(date +%s%N)
  "$build/bin/sitlnet" run "$out/fleet.textproto" --out "$dir" --no-progress > "$dir.log" 2>&1 || true
  local wall
  wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.3f", (b - a) / 1e9 }')
  if [ -f "$dir/summary.json" ]; then
    echo "$("$here/../scale/extract.py" "$dir" "$n" realtime 1 "$wall" "$load1"),$factor" >> "$out/runs.csv"
    python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['metrics']['lag_ms']['p99'])" "$dir/summary.json"
  else
    echo "inf"
  fi
  rm -rf "$dir"
}

holds() { awk -v p="$1" 'BEGIN { exit !(p < 2.0) }'; }

for factor in 1 0.5 0.25; do
  largest=0
  for n in 16 32 64 128 256; do
    p99=$(run "$n" "$factor")
    echo "factor $factor, $n robots: lag p99 $p99 ms"
    if holds "$p99"; then largest=$n; else break; fi
  done
  echo "factor $factor: largest fleet holding lag p99 < 2 ms: $largest"
done
factor=1
while :; do
  p99=$(run 256 "$factor")
  echo "256 robots, factor $factor: lag p99 $p99 ms"
  if holds "$p99" || awk -v f="$factor" 'BEGIN { exit !(f <= 1.0 / 64) }'; then break; fi
  factor=$(awk -v f="$factor" 'BEGIN { print f / 2 }')
done
echo "256 robots: smallest factor tried $factor (holds if its p99 above is < 2 ms); rows: $out/runs.csv"
