#!/usr/bin/env bash
# Soak run (issue 9, docs/security.md "Soak"): N flocking robots (bench/scale's scenario) for S
# simulated seconds, realtime pacing, with sitlnet and the flocker built with AddressSanitizer,
# UBSan and LeakSanitizer (-DSITLNET_SANITIZE=ON). Samples the `sitlnet run` process's open fds
# and RSS every 10 s, then checks: no sanitizer report in the run's or the robots' output, fds
# and RSS not growing, and the medium's counters conserved (per station: sent = sent_ok +
# lost at the retry limit + queue drops + at most the frames still queued at the end).
# Not part of scripts/test (it takes S seconds of wall time and more).
# Usage: sudo tests/integration/soak.sh [SECONDS=600] [ROBOTS=16] [BUILD_DIR=build-asan]
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds="${1:-600}"
robots="${2:-16}"
build="${3:-build-asan}"
out="${SOAK_OUT:-/tmp/sitlnet-soak-$$}"
if [[ ! -x "$build/bin/sitlnet" ]]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSITLNET_SANITIZE=ON >/dev/null
fi
cmake --build "$build" -j2 --target sitlnet flocker >/dev/null
mkdir -p "$out"
# The benchmark's scenario under a name and subnets of its own (a bench run may be up too).
python3 bench/scale/gen_scenario.py "$robots" "$out/soak.textproto"
sed -i -e "s/^name: \"scale$robots\"/name: \"soak$robots\"/" \
  -e 's/10\.93\.0\.0\/24/10.97.0.0\/24/' -e 's/10\.94\.0\.0\/16/10.98.0.0\/16/' "$out/soak.textproto"

# halt_on_error=0: report everything, do not stop at the first finding; LSan runs at exit.
# A small quarantine (default 256 MiB) so that RSS growth shows the program, not ASan filling it.
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=0:abort_on_error=0:quarantine_size_mb=16"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=0"
"$build/bin/sitlnet" run "$out/soak.textproto" --out "$out/run" --duration "$seconds" \
  --pacing realtime 2>"$out/run.stderr" &
run=$!
echo "time_s,fds,rss_kib" >"$out/resources.csv"
start=$(date +%s)
while kill -0 "$run" 2>/dev/null; do
  fds=$(ls "/proc/$run/fd" 2>/dev/null | wc -l)
  rss=$(awk '/^VmRSS/ {print $2}' "/proc/$run/status" 2>/dev/null || true)
  [[ -n "$rss" ]] && echo "$(($(date +%s) - start)),$fds,$rss" >>"$out/resources.csv"
  sleep 10  # a sampling period, not a synchronization
done
status=0
wait "$run" || status=$?
echo "soak: sitlnet run exited with $status after $(($(date +%s) - start)) s; folder $out"
python3 - "$out" <<'PY'
import csv, glob, json, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(out + "/resources.csv")))
# The first samples are start-up (robots starting, buffers growing): compare from 60 s on.
steady = [r for r in rows if int(r["time_s"]) >= 60] or rows
first, last = steady[0], steady[-1]
print(f"soak: fds {rows[0]['fds']} at start, {first['fds']} at {first['time_s']} s, "
      f"{last['fds']} at {last['time_s']} s (max {max(int(r['fds']) for r in rows)})")
print(f"soak: RSS {int(rows[0]['rss_kib']) // 1024} MiB at start, "
      f"{int(first['rss_kib']) // 1024} MiB at {first['time_s']} s, "
      f"{int(last['rss_kib']) // 1024} MiB at {last['time_s']} s")
s = json.load(open(out + "/run/summary.json"))
ok = True
totals = {}
for r in s["robots"]:
    m = r["medium"]
    other = m.get("other", {})
    lost = m["lost"]
    accounted = other.get("sent_ok", 0) + lost.get("retry_limit", 0) + m["queue_drops"]
    pending = m["sent"] - accounted
    for key, value in [("sent", m["sent"]), ("delivered", m["delivered"]),
                       ("queue_drops", m["queue_drops"]), ("sent_ok", other.get("sent_ok", 0)),
                       ("pending_at_end", pending)] + list(lost.items()):
        totals[key] = totals.get(key, 0) + value
    if not 0 <= pending <= 64:  # at most a queue (mac_phy_sim queue_limit_frames) per station
        ok = False
        print(f"soak: robot {r['name']}: sent {m['sent']} != sent_ok + retry_limit + queue_drops "
              f"({accounted}) + a queue")
print("soak: medium totals " + ", ".join(f"{k} {v}" for k, v in totals.items()))
reports = []
for path in [out + "/run.stderr"] + glob.glob(out + "/run/robots/*.log"):
    text = open(path, errors="replace").read()
    for needle in ("ERROR: AddressSanitizer", "ERROR: LeakSanitizer", "runtime error:"):
        if needle in text:
            reports.append(f"{path}: {needle}")
print("soak: sanitizer reports: " + ("; ".join(reports) if reports else "none"))
sys.exit(0 if ok and not reports else 1)
PY
