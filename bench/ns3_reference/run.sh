#!/bin/bash
# The ns-3 side-by-side matrix in one command: installs Debian's libns3-dev
# (ns-3 3.37) if missing, builds bench/ns3_reference, runs every cell in ns-3
# and in mac_phy_sim (5 seeds each side, or a cell's own count: the 3GPP
# shadowing cells run 1000-4000 short seeds; about 40 minutes of one core on the
# 2-core development machine, plus 2-6 minutes per shadowing cell), writes docs/ns3_matrix.csv with its
# provenance and regenerates the table in docs/validation.md (between the
# "ns3-matrix" markers). Needs root (or sudo) for the package installation.
# Usage: bench/ns3_reference/run.sh [build-dir] [seeds] [cell-id-substrings or =ids,...]
#   With a cell filter the CSV goes to <build-dir>/ns3_matrix.csv and the
#   docs are left alone. Other modes of the binary:
#   <build-dir>/bin/ns3_side_by_side refresh docs/ns3_matrix.csv  (recompute
#   the mac_phy_sim columns after a model change, keeping ns-3's), then
#   bench/ns3_reference/update_validation_table.sh <binary> <csv> docs/validation.md;
#   <build-dir>/bin/ns3_side_by_side speed  (ns-3 vs mac_phy_sim timing, n = 5/20/50);
#   bench/ns3_reference/ac_speed.sh  (the same at 802.11ac with 64-MPDU A-MPDUs).
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$repo/build-bench}
seeds=${2:-5}
filter=${3:-}
if ! dpkg -s libns3-dev > /dev/null 2>&1; then
  sudo=$([ "$(id -u)" = 0 ] && echo "" || echo sudo)
  $sudo apt-get install -y --no-install-recommends libns3-dev
fi
cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build" -j2 --target ns3_side_by_side > /dev/null
csv=$build/ns3_matrix.csv
start=$(date -u +%FT%TZ)
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
"$build/bin/ns3_side_by_side" matrix "$csv.rows" "$seeds" "$filter"
{
  echo "# ns-3 side-by-side matrix: ns-3 $(dpkg-query -W -f='${Version}' libns3-dev) (Debian libns3-dev)"
  echo "# vs mac_phy_sim at commit $(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)"
  echo "# command: bench/ns3_reference/run.sh <build> $seeds${filter:+ $filter}" \
       "(ns3_side_by_side matrix <csv> $seeds)"
  echo "# host: $(nproc) cores; started $start, load average $load_start; ended" \
       "$(date -u +%FT%TZ), load average $(cut -d' ' -f1-3 /proc/loadavg)"
  cat "$csv.rows"
} > "$csv"
rm -f "$csv.rows"
[ -n "$filter" ] && exit 0
cp "$csv" "$repo/docs/ns3_matrix.csv"
"$repo/bench/ns3_reference/update_validation_table.sh" "$build/bin/ns3_side_by_side" \
  "$repo/docs/ns3_matrix.csv" "$repo/docs/validation.md"
