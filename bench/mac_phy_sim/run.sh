#!/bin/bash
# Builds and runs the mac_phy_sim benchmark (Release), prints the Markdown
# table for docs/performance.md and, if gnuplot is installed, draws
# docs/mac_phy_sim_cost.svg (cost per transmission vs n).
# Usage: bench/mac_phy_sim/run.sh [build-dir] [--runs N] [--seconds S]
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$repo/build-bench}
shift || true
cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build" -j2 --target mac_phy_sim_bench > /dev/null
csv=$(mktemp)
trap 'rm -f "$csv"' EXIT
echo "host: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at start"
"$build/bin/mac_phy_sim_bench" --csv "$csv" "$@"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg) at end"
if command -v gnuplot > /dev/null; then
  grep '^saturation' "$csv" | cut -d, -f2- > "$csv.sat"
  gnuplot <<GNUPLOT
set terminal svg size 640,400 font "sans,11"
set output "$repo/docs/mac_phy_sim_cost.svg"
set datafile separator ","
set title "mac_phy_sim saturation (802.11a 54 Mb/s, 1500 B): cost vs stations"
set xlabel "stations n"
set ylabel "CPU us per transmission"
set y2label "CPU us per transmission per station"
set y2tics
set ytics nomirror
set key left top
set grid
plot "$csv.sat" using 1:4 with linespoints title "CPU us per transmission" axes x1y1, \
     "$csv.sat" using 1:5 with linespoints title "CPU us per transmission per station" axes x1y2
GNUPLOT
  rm -f "$csv.sat"
  echo "wrote docs/mac_phy_sim_cost.svg"
fi
