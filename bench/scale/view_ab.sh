#!/bin/bash
# Cost of a browser watching the live view on the run's own host (issue 34, item 2;
# docs/performance.md, "Live view"): the same `sitlnet run --view` with no browser ("alone") and
# with headless Chromium showing the page until the run ends ("browser",
# view/web/test/watch_page.cjs), ABBA (the order reversed every round, so a noisy minute on a
# shared host falls on both), seeds 1..ROUNDS, N flocking robots (gen_scenario.py), lockstep,
# SECONDS simulated. One row per run into OUT/runs.csv (extract.py; first column "variant", last
# the browser's CPU seconds), then the medians and the per-round browser/alone ratios of the
# loop's wall time and of sitlnet's CPU. The page served is the one built (build/view/web).
#
# NICE (default 0) is the browser's nice value: 19 measures a browser started with `nice -n 19`.
#
#   sudo bench/scale/view_ab.sh [BUILD=build] [N=64] [SECONDS=10] [ROUNDS=4] [OUT] [NICE=0]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
watcher=$here/../../view/web/test/watch_page.cjs
build=${1:-build} n=${2:-64} seconds=${3:-10} rounds=${4:-4}
out=${5:-/tmp/sitlnet-view-ab-$(date -u +%Y%m%d-%H%M%S)} browser_nice=${6:-0}
mkdir -p "$out"
"$here/gen_scenario.py" "$n" "$out/scale.textproto"
echo "variant,$("$here/extract.py" --header),browser_cpu_s" > "$out/runs.csv"
for round in $(seq 1 "$rounds"); do
  order="alone browser"; [ $((round % 2)) = 0 ] && order="browser alone"
  for variant in $order; do
    dir="$out/$variant-$round"
    load1=$(cut -d' ' -f1 /proc/loadavg)
    : > "$dir.log"  # Read below before the run may have opened it.
    start=$(date +%s%N)
    "$build/bin/sitlnet" run "$out/scale.textproto" --out "$dir" --pacing lockstep \
      --duration "$seconds" --seed "$round" --no-progress --view 127.0.0.1:0 > "$dir.log" 2>&1 &
    run=$!
    browser_cpu=""
    if [ "$variant" = browser ]; then
      url=""
      while [ -z "$url" ] && kill -0 "$run" 2>/dev/null; do  # The server binds before the run starts.
        url=$(sed -n 's/^sitlnet run: live view at //p' "$dir.log")
        [ -n "$url" ] || sleep 0.05
      done
      browser_cpu=$(nice -n "$browser_nice" node "$watcher" "$url" | sed -n 's/^browser_cpu_s \([0-9.]*\).*/\1/p')
    fi
    wait "$run"
    wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.3f", (b - a) / 1e9 }')
    echo "$variant,$("$here/extract.py" "$dir" "$n" lockstep "$round" "$wall" "$load1"),$browser_cpu" >> "$out/runs.csv"
    grep "live view:" "$dir.log" >> "$out/cost_lines.txt" || true
    rm -rf "$dir"
  done
done
python3 - "$out/runs.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
def col(variant, name):
    return [float(r[name]) for r in rows if r["variant"] == variant and r[name]]
for name in ("loop_s", "sitlnet_cpu_s"):
    browser, alone = col("browser", name), col("alone", name)
    ratios = [a / b for a, b in zip(browser, alone) if b]
    print(f"{name}: browser {statistics.median(browser):.3f} alone {statistics.median(alone):.3f}; "
          f"browser/alone per round {', '.join(f'{x:.3f}' for x in ratios)}, median {statistics.median(ratios):.3f}")
cpu = col("browser", "browser_cpu_s")
loops = col("browser", "loop_s")
print(f"browser CPU s per run: {', '.join(f'{x:.2f}' for x in cpu)}, median {statistics.median(cpu):.2f}; "
      f"per loop second: median {statistics.median([c / l for c, l in zip(cpu, loops)]):.3f}")
PY
echo "runs: $out/runs.csv"
