#!/bin/bash
# Cost of the table-based error model against NIST (docs/performance.md):
# runs mac_phy_sim_bench on the broadcast rows (64 moving stations among
# obstacles: every reception at its own SNR, so the error model is called)
# with --error-model nist and table in ABBA order, `rounds` times, and prints
# each run's CPU us per transmission; the medians are the result.
# Usage: bench/mac_phy_sim/error_model_ab.sh [build-dir] [rounds] [rows] [seconds]
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$repo/build-bench}
rounds=${2:-2}
rows=${3:-bcast,bcast-fading,hidden}
seconds=${4:-10}
cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build" -j2 --target mac_phy_sim_bench > /dev/null
echo "host: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at start"
for ((r = 0; r < rounds; ++r)); do
  for model in nist table table nist; do
    "$build/bin/mac_phy_sim_bench" --rows "$rows" --runs 1 --seconds "$seconds" \
      --error-model "$model" |
      awk -F'|' -v m="$model" 'NR > 2 { printf "%s |%s| %s\n", m, $2, $6 }'
  done
done
echo "load average $(cut -d' ' -f1-3 /proc/loadavg) at end"
