#!/usr/bin/env bash
# What `--set robot_count=N` changes in scripts/reproduce-paper's fleet-size figure (Fig. 5):
# there a fleet of N flies among the arrows of bench/scale's layout for the largest fleet (128
# robots, 32 arrows), where bench/scale/run.sh gave it only its own (ceil(N/4) arrows). Runs
# both, lockstep, 10 s, for N in COUNTS, ROUNDS times in ABBA order (own, first-N, first-N, own,
# ...), and prints the medians of metrics.stf.mean, t_phy_ms and t_net_ms per layout and N.
#
#   sudo bench/sweep/robot_count_layout.sh [--build DIR] [--counts "1 4 16"] [--rounds 3]
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build="$root/build"
counts="1 4 16"
rounds=3
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --counts) counts=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    *) echo "usage: $0 [--build DIR] [--counts \"1 4 16\"] [--rounds N]" >&2; exit 2 ;;
  esac
done
sitlnet="$build/bin/sitlnet"
work=$(mktemp -d /tmp/sitlnet-robot-count-XXXXXX)
"$root/bench/scale/gen_scenario.py" 128 "$work/fleet128.textproto"
for n in $counts; do "$root/bench/scale/gen_scenario.py" "$n" "$work/own$n.textproto"; done
echo "# $(date -u) $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
# One run as a one-point sweep (seed = round): the metrics come from its points.csv.
run() {  # run LAYOUT N ROUND
  local scenario=$work/own$2.textproto count=()
  if [ "$1" = first_n_of_128 ]; then scenario=$work/fleet128.textproto; count=(--set "robot_count=$2"); fi
  "$sitlnet" sweep "$scenario" --out "$work/$1-$2" --jobs 1 --seeds "1-$3" "${count[@]}" \
    --set timing.pacing=PACING_LOCKSTEP --set timing.duration_ms=10000 --metric metrics.stf.mean \
    --metric metrics.t_phy_ms.mean --metric metrics.t_net_ms.mean > "$work/$1-$2.log" 2>&1 ||
    { echo "$0: sweep failed: $work/$1-$2.log" >&2; exit 1; }
}
for round in $(seq 1 "$rounds"); do
  for n in $counts; do
    if [ $((round % 2)) = 1 ]; then order="own first_n_of_128"; else order="first_n_of_128 own"; fi
    for layout in $order; do run "$layout" "$n" "$round"; done
  done
done
echo "# end $(date -u), load $(cut -d' ' -f1-3 /proc/loadavg)"
python3 - "$work" $counts <<'PY'
import csv, statistics, sys
work, counts = sys.argv[1], sys.argv[2:]
print("robots,layout,runs,stf_mean,t_phy_ms,t_net_ms")
for n in counts:
    for layout in ("own", "first_n_of_128"):
        rows = [r for r in csv.DictReader(open(f"{work}/{layout}-{n}/points.csv")) if r["status"] == "ok"]
        med = lambda c: statistics.median(float(r[c]) for r in rows)
        print(f"{n},{layout},{len(rows)},{med('metrics.stf.mean'):.4f},"
              f"{med('metrics.t_phy_ms.mean'):.4f},{med('metrics.t_net_ms.mean'):.4f}")
PY
