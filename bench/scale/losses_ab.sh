#!/bin/bash
# Cost of recording lost frames (issue 34, item 1; docs/performance.md, "Loss recording"):
# the same `sitlnet run` with and without `--no-losses`, ABBA (the order reversed every round, so
# a noisy minute on a shared host falls on both), seeds 1..ROUNDS, N flocking robots
# (gen_scenario.py), lockstep, SECONDS simulated. One row per run into OUT/runs.csv (extract.py,
# first column "variant", last the bytes of losses.csv.gz + links.csv and of medium.pcap), then
# the medians and the per-round on/off ratios of the loop's wall time and of sitlnet's CPU.
#
#   sudo bench/scale/losses_ab.sh [BUILD=build] [N=64] [SECONDS=60] [ROUNDS=4] [OUT]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build} n=${2:-64} seconds=${3:-60} rounds=${4:-4}
out=${5:-/tmp/sitlnet-losses-ab-$(date -u +%Y%m%d-%H%M%S)}
mkdir -p "$out"
"$here/gen_scenario.py" "$n" "$out/scale.textproto"
echo "variant,$("$here/extract.py" --header),loss_bytes,pcap_bytes" > "$out/runs.csv"
for round in $(seq 1 "$rounds"); do
  order="on off"; [ $((round % 2)) = 0 ] && order="off on"
  for variant in $order; do
    dir="$out/$variant-$round"
    load1=$(cut -d' ' -f1 /proc/loadavg)
    start=$(date +%s%N)
    "$build/bin/sitlnet" run "$out/scale.textproto" --out "$dir" --pacing lockstep \
      --duration "$seconds" --seed "$round" --no-progress $([ "$variant" = off ] && echo --no-losses) \
      > "$dir.log" 2>&1
    wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.3f", (b - a) / 1e9 }')
    loss_bytes=$( (cat "$dir"/losses.csv.gz "$dir"/links.csv 2>/dev/null || true) | wc -c)  # none when off
    echo "$variant,$("$here/extract.py" "$dir" "$n" lockstep "$round" "$wall" "$load1"),$loss_bytes,$(wc -c < "$dir/medium.pcap")" >> "$out/runs.csv"
    rm -rf "$dir"
  done
done
python3 - "$out/runs.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
def col(variant, name):
    return [float(r[name]) for r in rows if r["variant"] == variant]
for name in ("loop_s", "sitlnet_cpu_s", "loss_bytes", "pcap_bytes"):
    on, off = col("on", name), col("off", name)
    ratios = [a / b for a, b in zip(on, off) if b] if name in ("loop_s", "sitlnet_cpu_s") else []
    print(f"{name}: on {statistics.median(on):.3f} off {statistics.median(off):.3f}"
          + (f"; on/off per round {', '.join(f'{x:.3f}' for x in ratios)}, median {statistics.median(ratios):.3f}" if ratios else ""))
PY
echo "runs: $out/runs.csv"
