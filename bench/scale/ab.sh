#!/bin/bash
# A/B of two builds on the end-to-end scale scenario (docs/performance.md, "How to measure").
#
#   sudo bench/scale/ab.sh OLD_BUILD[:IMAGES] NEW_BUILD[:IMAGES] [ROUNDS] [OUT]
#
# A build may name an images folder ($SITLNET_IMAGES for its runs), so that one build can be
# compared with itself under other manifests, e.g. with the sandbox off (docs/performance.md,
# "Robot sandbox": bench/scale/unconfined_images.sh makes such a folder).
# Runs `sitlnet run` of 16 robots (lockstep, 20 s) and 64 robots (lockstep, 10 s) from each
# build in turn, the order reversed every round (ABBA: a noisy minute on a shared host falls on
# both), seeds 1..ROUNDS (default 8), one row per run into OUT/runs.csv (extract.py, with a
# first column "tree"), then prints the medians and new/old ratios. Each run tears itself down.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
[ $# -ge 2 ] || { echo "usage: $0 OLD_BUILD[:IMAGES] NEW_BUILD[:IMAGES] [ROUNDS] [OUT]" >&2; exit 2; }
old=$1 new=$2 rounds=${3:-8}
out=${4:-/tmp/sitlnet-ab-$(date -u +%Y%m%d-%H%M%S)}
mkdir -p "$out"
for n in 16 64; do "$here/gen_scenario.py" "$n" "$out/scale$n.textproto"; done
"$here/extract.py" --header | sed 's/^/tree,/' > "$out/runs.csv"
for round in $(seq 1 "$rounds"); do
  order="old new"; [ $((round % 2)) = 0 ] && order="new old"
  for tree in $order; do
    spec=$([ "$tree" = old ] && echo "$old" || echo "$new")
    bin=${spec%%:*}/bin
    images=$([[ $spec == *:* ]] && echo "${spec#*:}" || true)
    for point in "16 20" "64 10"; do
      read -r n seconds <<< "$point"
      dir="$out/$tree-$n-$round"
      load1=$(cut -d' ' -f1 /proc/loadavg)
      start=$(date +%s%N)
      env ${images:+SITLNET_IMAGES="$images"} "$bin/sitlnet" run "$out/scale$n.textproto" --out "$dir" --pacing lockstep \
        --duration "$seconds" --seed "$round" --no-progress > "$dir.log" 2>&1
      wall=$(awk -v a="$start" -v b="$(date +%s%N)" 'BEGIN { printf "%.3f", (b - a) / 1e9 }')
      echo "$tree,$("$here/extract.py" "$dir" "$n" lockstep "$round" "$wall" "$load1")" >> "$out/runs.csv"
      rm -rf "$dir"
    done
  done
done
python3 - "$out/runs.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for n in ("16", "64"):
    for col in ("stf_mean", "t_phy_ms", "t_net_ms", "t_overhead_ms"):
        v = {t: [float(r[col]) for r in rows if r["tree"] == t and r["robots"] == n] for t in ("old", "new")}
        o, w = statistics.median(v["old"]), statistics.median(v["new"])
        print(f"{n} robots {col}: old {o:.4f} new {w:.4f} new/old {w / o:.3f} "
              f"(old {min(v['old']):.3f}-{max(v['old']):.3f}, new {min(v['new']):.3f}-{max(v['new']):.3f})")
PY
echo "runs: $out/runs.csv"
