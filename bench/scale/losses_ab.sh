#!/bin/bash
# Cost of recording lost frames (issue 34, item 1; docs/performance.md, "Loss recording"):
# the same `sitlnet run` with and without `--no-losses` (ab_lib.sh: ABBA, seeds 1..ROUNDS,
# N flocking robots, lockstep, SECONDS simulated). One row per run into OUT/runs.csv (extract.py,
# first column "variant", last the bytes of losses.csv.gz + links.csv and of medium.pcap), then
# the medians and the per-round on/off ratios of the loop's wall time and of sitlnet's CPU.
#
#   sudo bench/scale/losses_ab.sh [BUILD=build] [N=64] [SECONDS=60] [ROUNDS=4] [OUT]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/ab_lib.sh"
build=${1:-build} n=${2:-64} seconds=${3:-60} rounds=${4:-4}
out=${5:-/tmp/sitlnet-losses-ab-$(date -u +%Y%m%d-%H%M%S)}

ab_args() { [ "$1" = off ] && echo --no-losses || true; }
ab_while() { :; }
ab_after() {  # The loss files are none when off.
  echo "$( (cat "$2"/losses.csv.gz "$2"/links.csv 2>/dev/null || true) | wc -c),$(wc -c < "$2/medium.pcap")"
}
ab_series "$build" "$out" "$n" "$seconds" "$rounds" "on off" loss_bytes,pcap_bytes
"$here/ab_summary.py" "$out/runs.csv" off loop_s sitlnet_cpu_s --medians loop_s loss_bytes pcap_bytes
echo "runs: $out/runs.csv"
