#!/bin/bash
# The manifests' lean profile against their default (issue 46, item 4; docs/performance.md,
# "The lean profile"): idle lockstep fleets of N PX4 or N ArduCopter through real_fleet.sh, the
# two profiles in ABBA order (round r runs default then lean if r is odd, lean then default if
# even), so that a noisy minute of the shared host falls on both. Prints real_fleet.sh's rows
# with the profile first, then per kind and size the medians (STF, CPU per autopilot) and the
# lean / default ratio of the STF medians.
#
#   bench/autopilots/lean_ab.sh [BUILD=build] [SECONDS=10] [ROUNDS=3] [SIZES="8 16 24"]
set -euo pipefail
build=${1:-build} seconds=${2:-10} rounds=${3:-3} sizes=${4:-"8 16 24"}
here=$(dirname "$0")
rows=$(mktemp /tmp/sitlnet-lean-ab-XXXXXX)
trap 'rm -f "$rows"' EXIT
run() {  # PROFILE KIND N
  local args=""
  [[ $1 == lean ]] && args="--lean"
  # real_fleet.sh's stderr: only why a run failed.
  ARGS=$args KINDS=$2 "$here/real_fleet.sh" "$build" "$seconds" 1 "$3" lockstep \
    2> >(grep 'run failed' >&2) |
    tail -n +2 | sed "s/^/$1,/" | tee -a "$rows"
}
echo "profile,kind,robots,run,pacing,stf_mean,loop_s,cpu_s_per_autopilot_per_virtual_s,lag_p99_ms,timing_complaints,load1,min_frames_per_virtual_s"
for r in $(seq 1 "$rounds"); do
  for n in $sizes; do
    for kind in ${KINDS:-px4 arducopter}; do
      if (( r % 2 )); then run default "$kind" "$n"; run lean "$kind" "$n"
      else run lean "$kind" "$n"; run default "$kind" "$n"; fi
    done
  done
done
python3 - "$rows" <<'PY'
import statistics, sys
rows = [line.strip().split(",") for line in open(sys.argv[1]) if line.strip()]
groups = {}
for r in rows:
    if r[5] == "failed":
        groups.setdefault((r[1], int(r[2]), r[0]), []).append(None)
        continue
    groups.setdefault((r[1], int(r[2]), r[0]), []).append((float(r[5]), float(r[7] or 0), r[10]))
print("kind,robots,default_stf_median,lean_stf_median,lean_over_default,default_cpu,lean_cpu,runs,failed,loads")
for kind, n in sorted({(k, n) for k, n, _ in groups}):
    d = [x for x in groups.get((kind, n, "default"), []) if x]
    l = [x for x in groups.get((kind, n, "lean"), []) if x]
    failed = sum(x is None for p in ("default", "lean") for x in groups.get((kind, n, p), []))
    if not d or not l:
        print(f"{kind},{n},,,,,,{len(d)}+{len(l)},{failed},")
        continue
    ds, ls = statistics.median(x[0] for x in d), statistics.median(x[0] for x in l)
    loads = " ".join(x[2] for x in d + l)
    print(f"{kind},{n},{ds:.3f},{ls:.3f},{ls / ds:.2f},{statistics.median(x[1] for x in d):.3f},"
          f"{statistics.median(x[1] for x in l):.3f},{len(d)}+{len(l)},{failed},{loads}")
PY
