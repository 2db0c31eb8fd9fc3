#!/bin/bash
# The medium at 802.11ac saturation against ns-3 3.37, in one process and run (issue 44,
# Performance; docs/performance.md, "802.11ac with 64-MPDU A-MPDUs"): VHT MCS 9, 80 MHz, long
# guard interval, A-MPDU with best effort's limit at VHT's maximum (1048575 B: 64 MPDUs of
# 1500 B), 1, 5 and 20 senders to one receiver. Prints simulated seconds per wall second of both
# (ABBA rounds, medians) and mac_phy_sim's CPU per delivered MPDU with A-MPDU against aggregation
# off. Installs Debian's libns3-dev if missing (root or sudo).
# Usage: bench/ns3_reference/ac_speed.sh [build-dir] [rounds=3] [measured-seconds=2]
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$repo/build-bench}
rounds=${2:-3}
seconds=${3:-2}
if ! dpkg -s libns3-dev > /dev/null 2>&1; then
  sudo=$([ "$(id -u)" = 0 ] && echo "" || echo sudo)
  $sudo apt-get install -y --no-install-recommends libns3-dev
fi
if [ -f "$build/CMakeCache.txt" ]; then
  cmake -S "$repo" -B "$build" > /dev/null
else
  cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
fi
cmake --build "$build" -j2 --target ns3_side_by_side > /dev/null
echo "host: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at start; sitlnet at" \
  "$(git -C "$repo" rev-parse --short HEAD 2> /dev/null || echo unknown)"
"$build/bin/ns3_side_by_side" speed-ac "$rounds" "$seconds"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg) at end"
