#!/usr/bin/env python3
"""One row per run of the fleet-size sweeps (scripts/reproduce-paper), as bench/scale's runs.csv.

Usage: fleet_runs.py LOADS.csv SWEEP_DIR/points.csv... > scale_runs.csv
Each points.csv is a sweep over robot_count and timing.pacing with the metrics named below
(--metric). LOADS.csv (sweep,seed,load1): the 1-minute load average when the sweep folder named
`sweep` was started to run that seed. Columns: robots, pacing (lockstep or realtime), run (the
seed), load1, then the metrics, then failure (a point not finished: its status and reason);
bench/scale/medians.py takes the medians per fleet size and pacing.
"""
import csv
import os
import sys

METRICS = [("stf_mean", "metrics.stf.mean"), ("t_phy_ms", "metrics.t_phy_ms.mean"),
           ("t_net_ms", "metrics.t_net_ms.mean"), ("t_overhead_ms", "metrics.t_overhead_ms.mean"),
           ("t_total_ms", "metrics.t_total_ms.mean"), ("overhead_share", "metrics.overhead_share"),
           ("lag_p99_ms", "metrics.lag_ms.p99")]
PACINGS = {"PACING_LOCKSTEP": "lockstep", "PACING_REALTIME": "realtime"}

loads = {(r["sweep"], r["seed"]): r["load1"] for r in csv.DictReader(open(sys.argv[1]))}
out = csv.writer(sys.stdout, lineterminator="\n")
out.writerow(["robots", "pacing", "run", "load1"] + [name for name, _ in METRICS] + ["failure"])
for path in sys.argv[2:]:
    sweep = os.path.basename(os.path.dirname(os.path.abspath(path)))
    for point in csv.DictReader(open(path)):
        failure = "" if point["status"] == "ok" else f"{point['status']} {point['reason']}"
        # A metric summary.json holds as null (a lag in a run that never iterated) is empty here:
        # NaN, which bench/scale/medians.py counts as later than any run, not as zero.
        values = [point[metric] if point[metric] != "" else "nan" for _, metric in METRICS]
        out.writerow([point["robot_count"], PACINGS[point["timing.pacing"]], point["seed"],
                      loads.get((sweep, point["seed"]), "nan")] + values +
                     [failure.replace(",", ";")[:80]])
