#!/bin/bash
# Installs Debian's libns3-dev (ns-3 3.37) if missing, builds the side-by-side
# benchmark and runs it. Needs root (or sudo) for the package installation.
# Usage: bench/ns3_reference/run.sh [build-dir] [measured seconds per point]
set -euo pipefail
repo=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$repo/build-bench}
seconds=${2:-10}
if ! dpkg -s libns3-dev > /dev/null 2>&1; then
  sudo=$([ "$(id -u)" = 0 ] && echo "" || echo sudo)
  $sudo apt-get install -y --no-install-recommends libns3-dev
fi
cmake -S "$repo" -B "$build" -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build "$build" -j2 --target ns3_side_by_side > /dev/null
echo "host: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at start"
"$build/bin/ns3_side_by_side" "$seconds"
echo "load average $(cut -d' ' -f1-3 /proc/loadavg) at end"
