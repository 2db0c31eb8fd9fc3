#!/bin/bash
# The real autopilots' STF under two builds, in ABBA order (issue 46, item 2; docs/performance.md,
# "The critical path of one iteration"). Each run is one real_fleet.sh row (N idle autopilots of
# one kind, lockstep, SECONDS virtual seconds); round r runs OLD then NEW if r is odd, NEW then
# OLD if even, so a noisy minute of the shared host falls on both. Prints the rows with the
# build first, then per kind and size the median STF of each build, NEW / OLD, and the load
# averages (1 min) the runs started at.
#
#   sudo -E bench/autopilots/real_fleet_ab.sh OLD_BUILD NEW_BUILD [SECONDS=20] [ROUNDS=3] [SIZES=16]
#       (KINDS="px4 arducopter" by default; ARGS as real_fleet.sh's)
set -euo pipefail
old=$1 new=$2 seconds=${3:-20} rounds=${4:-3} sizes=${5:-16}
here=$(dirname "$0")
# shellcheck source=bench/autopilots/abba_rounds.sh
source "$here/abba_rounds.sh"
rows=$(mktemp /tmp/sitlnet-real-fleet-ab-XXXXXX)
trap 'rm -f "$rows"' EXIT
run() {  # LABEL BUILD KIND N
  KINDS=$3 "$here/real_fleet.sh" "$2" "$seconds" 1 "$4" | tail -n +2 | sed "s/^/$1,/" |
    tee -a "$rows"
}
echo "build,kind,robots,run,pacing,stf_mean,loop_s,cpu_s_per_autopilot_per_virtual_s,lag_p99_ms,timing_complaints,load1,min_frames_per_virtual_s"
abba_rounds "$rounds" "$sizes" "${KINDS:-px4 arducopter}" "$old" "$new"
python3 - "$rows" <<'PY'
import statistics, sys
groups = {}
for line in open(sys.argv[1]):
    r = line.strip().split(",")
    if len(r) < 11 or r[5] == "failed":
        continue  # a failed run is in the rows above, not in the medians
    groups.setdefault((r[1], int(r[2])), {}).setdefault(r[0], []).append((float(r[5]), float(r[10])))
print("kind,robots,old_stf,new_stf,new_over_old,old_runs,new_runs,load1_range")
for (kind, n), builds in sorted(groups.items()):
    o, w = builds.get("old", []), builds.get("new", [])
    if not o or not w:
        continue
    mo, mw = statistics.median(s for s, _ in o), statistics.median(s for s, _ in w)
    loads = [l for _, l in o + w]
    print(f"{kind},{n},{mo:.3f},{mw:.3f},{mw / mo:.2f},"
          f"{'/'.join(f'{s:.3f}' for s, _ in o)},{'/'.join(f'{s:.3f}' for s, _ in w)},"
          f"{min(loads):.1f}-{max(loads):.1f}")
PY
