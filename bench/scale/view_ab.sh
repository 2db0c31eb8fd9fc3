#!/bin/bash
# Cost of the live view (issue 34, item 2; docs/performance.md, "Live view"): the same
# `sitlnet run` (ab_lib.sh: ABBA, seeds 1..ROUNDS, N flocking robots, lockstep, SECONDS
# simulated) in each of VARIANTS:
#   off      no --view
#   alone    --view, no one watching
#   poll     --view, read as the page reads it, without drawing (view/web/test/poll_live.cjs)
#   browser  --view, headless Chromium showing the page until the run ends (watch_page.cjs)
#   nice     as browser, started with `nice -n 19`
#   idle     as browser, in a cgroup of idle CPU (scripts/run-on-idle-cpu)
# One row per run into OUT/runs.csv (extract.py, first column "variant", then the client's CPU
# seconds: the poller's own, or the browser's processes'; the documents served and the server
# threads' CPU milliseconds, from the run's cost line), the server's cost lines into
# OUT/cost_lines.txt, then the per-round ratios to the first variant of the loop's wall time and
# of sitlnet's CPU (ab_summary.py). The page served is the one built (BUILD/view/web).
#
#   sudo bench/scale/view_ab.sh [BUILD=build] [N=64] [SECONDS=10] [ROUNDS=4] [OUT] [VARIANTS="alone browser"]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
source "$here/ab_lib.sh"
web_test=$here/../../view/web/test
run_on_idle_cpu=$here/../../scripts/run-on-idle-cpu
build=${1:-build} n=${2:-64} seconds=${3:-10} rounds=${4:-4}
out=${5:-/tmp/sitlnet-view-ab-$(date -u +%Y%m%d-%H%M%S)} variants=${6:-alone browser}

ab_args() { [ "$1" = off ] || printf '%s\n' --view 127.0.0.1:0; }
ab_while() {  # Prints the client's line (poll_live.cjs, watch_page.cjs).
  local variant=$1 url
  [ "$variant" = off ] || [ "$variant" = alone ] && return 0
  url=$(ab_view_url "$2.log" "$3")
  [ -n "$url" ] || return 0
  case $variant in
    poll) node "$web_test/poll_live.cjs" "$url" ;;
    browser) node "$web_test/watch_page.cjs" "$url" ;;
    nice) nice -n 19 node "$web_test/watch_page.cjs" "$url" ;;
    idle) "$run_on_idle_cpu" node "$web_test/watch_page.cjs" "$url" ;;
  esac || echo "view_ab.sh: the $variant client of $2 failed" >&2
}
ab_after() {  # The client's CPU, then the documents served and the server threads' CPU.
  local client cost
  client=$(sed -n 's/^\(client\|browser\)_cpu_s \([0-9.]*\).*/\2/p' "$2.while")
  cost=$(sed -n 's/.* \([0-9]*\) documents served, \([0-9.]*\) ms CPU on the server.*/\1,\2/p' "$2.log")
  echo "$client,${cost:-,}"
}
ab_series "$build" "$out" "$n" "$seconds" "$rounds" "$variants" client_cpu_s,documents,server_cpu_ms
reference=${variants%% *}
"$here/ab_summary.py" "$out/runs.csv" "$reference" loop_s sitlnet_cpu_s \
  --medians loop_s sitlnet_cpu_s robots_cpu_s client_cpu_s documents server_cpu_ms
echo "runs: $out/runs.csv"
