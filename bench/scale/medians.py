#!/usr/bin/env python3
"""Medians per (robots, pacing) of runs.csv -> scale.csv (bench/scale/run.sh)."""
import csv
import statistics
import sys

rows = list(csv.DictReader(open(sys.argv[1])))
cols = [c for c in rows[0].keys() if c not in ("robots", "pacing", "run", "failure")]
groups = {}
for row in rows:
    if row["failure"]:
        continue  # a failed run is listed in runs.csv, not counted
    groups.setdefault((int(row["robots"]), row["pacing"]), []).append(row)
with open(sys.argv[2], "w") as out:
    out.write("robots,pacing,runs," + ",".join(cols) + "\n")
    for (n, pacing), group in sorted(groups.items()):
        values = [statistics.median(float(g[c]) for g in group) for c in cols]
        out.write(f"{n},{pacing},{len(group)}," + ",".join(f"{v:.6g}" for v in values) + "\n")
