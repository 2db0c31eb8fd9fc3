#!/usr/bin/env python3
"""Numbers of one case-study run (scripts/reproduce-paper, Fig. 6), as one JSON line.

Usage: fig6.py RUN_DIR
From connectivity.csv and trajectories.csv of a `sitlnet run` of
scenarios/arrow_flocking.textproto: the longest stretch with more than one
connected component and when it started and ended, the components at the end,
on which side of the shaft each robot passed, when all robots were past the
arrow, and the closest pair of airborne robots. The pass/fail checks of the
same behaviour are tests/integration/case_study_test.cc's.
"""
import csv
import json
import math
import sys

SHAFT_MIDDLE_X_M = 60  # scenarios/arrow_flocking.textproto: shaft from x = 30 to 90 m.
ARROW_END_X_M = 90
AIRBORNE_Z_M = 5

run = sys.argv[1]
samples = [(float(r["time_s"]), int(r["components"]))
           for r in csv.DictReader(open(run + "/connectivity.csv"))]
longest = (0.0, None, None)
start = None
previous = None
for time_s, components in samples:
    if components > 1:
        if start is None:
            start = previous if previous is not None else time_s
        if time_s - start > longest[0]:
            longest = (time_s - start, start, time_s)
    else:
        start = None
    previous = time_s

positions = {}  # time -> robot -> (x, y, z)
for r in csv.DictReader(open(run + "/trajectories.csv")):
    positions.setdefault(float(r["time_s"]), {})[int(r["robot"])] = (
        float(r["x_m"]), float(r["y_m"]), float(r["z_m"]))
sides, past_s, closest = {}, None, math.inf
for time_s in sorted(positions):
    robots = positions[time_s]
    for robot, (x, y, _) in robots.items():
        if robot not in sides and x >= SHAFT_MIDDLE_X_M:
            sides[robot] = "north" if y > 0 else "south"
    if past_s is None and robots and all(x > ARROW_END_X_M for x, _, _ in robots.values()):
        past_s = time_s
    if robots and all(z > AIRBORNE_Z_M for _, _, z in robots.values()):
        points = list(robots.values())
        for i in range(len(points)):
            for j in range(i + 1, len(points)):
                closest = min(closest, math.dist(points[i][:2], points[j][:2]))

print(json.dumps({
    "max_components": max(c for _, c in samples),
    "longest_split_s": round(longest[0], 1),
    "split_from_s": longest[1],
    "split_to_s": longest[2],
    "components_at_end": samples[-1][1],
    "shaft_sides": sorted(set(sides.values())),
    "all_past_arrow_s": past_s,
    "closest_pair_m": round(closest, 2),
    "simulated_s": samples[-1][0],
}))
