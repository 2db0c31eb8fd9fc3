#!/bin/bash
# sitlnet's cost per autopilot step, two builds in ABBA order (issue 46, item 3;
# docs/performance.md, "The harness's share per autopilot step"). Each run is one
# harness_per_step.py row; round r runs OLD then NEW if r is odd, NEW then OLD if even, so a
# noisy minute of the shared host falls on both. Prints the rows with the build first, then per
# kind and size the medians of each build and NEW / OLD.
#
#   bench/autopilots/harness_ab.sh OLD_BUILD NEW_BUILD [SECONDS=10] [ROUNDS=3] [SIZES="1 8 16"]
#       (KINDS="test-px4 test-json" by default; px4 and arducopter fly the real autopilots)
set -euo pipefail
old=$1 new=$2 seconds=${3:-10} rounds=${4:-3} sizes=${5:-"1 8 16"}
here=$(dirname "$0")
# shellcheck source=bench/autopilots/abba_rounds.sh
source "$here/abba_rounds.sh"
rows=$(mktemp /tmp/sitlnet-harness-ab-XXXXXX)
work=$(mktemp -d /tmp/sitlnet-harness-ab-XXXXXX)
trap 'rm -rf "$rows" "$work"' EXIT
run() {  # LABEL BUILD KIND N
  rm -rf "$work/run"
  # At least 100 / N virtual seconds: a small fleet of test autopilots runs in a fraction of a
  # second, shorter than perf takes to attach.
  local secs=$(( seconds > 100 / $4 ? seconds : 100 / $4 ))
  python3 "$here/harness_per_step.py" "$2/bin/sitlnet" "$3" "$4" "$secs" "$work/run" |
    sed "s/^/$1,/" | tee -a "$rows"
}
echo "build,kind,robots,stf,answers,syscalls_per_step,switches_per_step,cpu_us_per_step,physics_syscalls_per_step,step_switches_per_step,loop_s"
abba_rounds "$rounds" "$sizes" "${KINDS:-test-px4 test-json}" "$old" "$new"
python3 - "$rows" <<'PY'
import statistics, sys
rows = [line.strip().split(",") for line in open(sys.argv[1]) if line.strip()]
fields = ["stf", "syscalls_per_step", "switches_per_step", "cpu_us_per_step"]
groups = {}
for r in rows:
    groups.setdefault((r[1], int(r[2]), r[0]), []).append([float(r[3]), float(r[5]), float(r[6]), float(r[7])])
print("kind,robots," + ",".join(f"old_{f},new_{f},ratio_{f}" for f in fields) + ",runs")
for kind, n in sorted({(k, n) for k, n, _ in groups}):
    o, w = groups.get((kind, n, "old"), []), groups.get((kind, n, "new"), [])
    if not o or not w:
        continue
    cells = []
    for i in range(len(fields)):
        mo, mw = statistics.median(x[i] for x in o), statistics.median(x[i] for x in w)
        cells.append(f"{mo:.3f},{mw:.3f},{mw / mo if mo else float('nan'):.2f}")
    print(f"{kind},{n}," + ",".join(cells) + f",{len(o)}+{len(w)}")
PY
