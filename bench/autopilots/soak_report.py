#!/usr/bin/env python3
"""soak.sh's verdict from its folder OUT (MINUTES long): missions flown, memory growth per
process (median RSS over the first 5 minutes against the last 5), the iteration lag p99 of the
first and last 5 minutes, and fault lines.

  soak_report.py OUT MINUTES
"""
import collections
import csv
import glob
import json
import re
import statistics
import sys

WINDOW_S = 300
FAULT = re.compile(r"Hz < |stale|failsafe|preflight fail|timeout|lost|error", re.IGNORECASE)
BOOT_NOISE = re.compile(r"Parameter \S+ not found|LED: open|ensure port \d+ is not blocked")


def p99(values):
    values = sorted(values)
    return values[int(0.99 * (len(values) - 1))] if values else float("nan")


def main():
    out, minutes = sys.argv[1], float(sys.argv[2])
    missions = sorted(glob.glob(f"{out}/mission.*.log"), key=lambda p: int(p.split(".")[-2]))
    flown = [m for m in missions if "ERROR" not in open(m).read()]
    print(f"missions started {len(missions)}, without a GCS error {len(flown)}")

    by_process = collections.defaultdict(list)
    last_s = 0
    for row in csv.DictReader(open(f"{out}/samples.csv")):
        t = int(row["wall_s"])
        last_s = max(last_s, t)
        by_process[(row["robot"], row["pid"], row["comm"])].append((t, int(row["rss_kib"])))
    worst = []
    for key, samples in by_process.items():
        first = [r for t, r in samples if t < WINDOW_S]
        last = [r for t, r in samples if t >= last_s - WINDOW_S]
        if len(first) < 3 or len(last) < 3 or samples[0][0] > 60:
            continue  # started late or ended early: no long-lived process to judge
        a, b = statistics.median(first), statistics.median(last)
        worst.append(((b - a) / a * 100, key, a, b))
    worst.sort(reverse=True)
    print(f"memory: {len(worst)} long-lived processes; growth first-5-min to last-5-min median RSS:")
    for growth, (robot, pid, comm), a, b in worst[:8]:
        print(f"  {robot} {comm} ({pid}): {a / 1024:.1f} -> {b / 1024:.1f} MiB, {growth:+.2f} %")
    print(f"  over 5 %: {sum(1 for w in worst if w[0] > 5)}")

    rows = list(csv.DictReader(open(f"{out}/run/metrics.csv")))
    t0 = int(rows[0]["start_ns"])
    span = (int(rows[-1]["start_ns"]) - t0) / 1e9
    first = [int(r["lag_ns"]) / 1e6 for r in rows if (int(r["start_ns"]) - t0) / 1e9 < WINDOW_S]
    last = [int(r["lag_ns"]) / 1e6 for r in rows if (int(r["start_ns"]) - t0) / 1e9 >= span - WINDOW_S]
    print(f"lag p99: first 5 min {p99(first):.2f} ms, last 5 min {p99(last):.2f} ms "
          f"(whole run {json.load(open(out + '/run/summary.json'))['metrics']['lag_ms']['p99']:.2f} ms)")

    faults = collections.Counter()
    for log in glob.glob(f"{out}/run/robots/*.log"):
        for line in open(log, errors="replace"):
            if FAULT.search(line) and not BOOT_NOISE.search(line):
                faults[(log.split("/")[-1], line.strip()[:100])] += 1
    for m in missions:
        for line in open(m, errors="replace"):
            if ("TEXT" in line and FAULT.search(line)) or line.startswith("ERROR"):
                faults[(m.split("/")[-1], re.sub(r"t(_ms)?=\S+ ", "", line.strip())[:100])] += 1
    print(f"fault lines: {sum(faults.values())}")
    for (where, line), n in faults.most_common(12):
        print(f"  {n} x {where}: {line}")


if __name__ == "__main__":
    main()
