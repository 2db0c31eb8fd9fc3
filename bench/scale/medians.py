#!/usr/bin/env python3
"""Medians per point of a runs CSV (bench/scale/run.sh, ablation.sh).

Usage: medians.py RUNS.csv OUT.csv [--group COLUMN]
Groups by (robots, pacing), or by COLUMN (ablation.sh: variant) first.
"""
import csv
import math
import statistics
import sys

group_by = sys.argv[4] if sys.argv[3:4] == ["--group"] else None
keys = ([group_by] if group_by else []) + ["robots", "pacing"]
rows = list(csv.DictReader(open(sys.argv[1])))
cols = [c for c in rows[0].keys() if c not in keys + ["run", "failure"]]
groups = {}
for row in rows:
    if row["failure"]:
        continue  # a failed run is listed in the runs CSV, not counted
    key = tuple(int(row[k]) if k == "robots" else row[k] for k in keys)
    groups.setdefault(key, []).append(row)
with open(sys.argv[2], "w") as out:
    out.write(",".join(keys) + ",runs," + ",".join(cols) + "\n")
    # By pacing, then robots: each mode's rows contiguous, so gnuplot draws
    # their lines (a NaN row between points breaks a line).
    order = (lambda item: 0) if group_by else (lambda item: (item[0][1], item[0][0]))
    for key, group in sorted(groups.items(), key=order):
        # statistics.median over a NaN depends on the rows' order: a NaN (a run that never
        # iterated) counts as +inf, later than any run, so the median is defined; a median
        # that is such a run is written as NaN again.
        values = [statistics.median(float(g[c]) if float(g[c]) == float(g[c]) else math.inf
                                    for g in group) for c in cols]
        values = [math.nan if v == math.inf else v for v in values]
        out.write(",".join(str(k) for k in key) + f",{len(group)}," +
                  ",".join(f"{v:.6g}" for v in values) + "\n")
