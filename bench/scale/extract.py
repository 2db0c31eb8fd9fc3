#!/usr/bin/env python3
"""One CSV row from a `sitlnet run` folder (bench/scale/run.sh).

Usage: extract.py RUN_DIR N PACING RUN WALL_S LOAD1 >> runs.csv
Columns: see HEADER. Frames per second = frames put on the air (sum of the
robots' medium "sent") and delivered, per wall second of the loop and per
simulated second.
"""
import json
import sys

HEADER = ("robots,pacing,run,simulated_s,wall_s,load1,stf_overall,stf_mean,stf_p99,"
          "t_phy_ms,t_net_ms,t_overhead_ms,t_total_ms,overhead_share,lag_p99_ms,"
          "frames_sent,frames_delivered,sent_per_wall_s,sent_per_sim_s,delivered_per_wall_s,"
          "sitlnet_cpu_s,robots_cpu_s,robot_cpu_s_per_robot,cpu_per_sim_s,robot_max_rss_mib,robot_median_rss_mib,"
          "startup_s,loop_s,teardown_s,failure")

if sys.argv[1:] == ["--header"]:
    print(HEADER)
    sys.exit(0)
run_dir, n, pacing, run, wall_s, load1 = sys.argv[1:7]
n, wall_s = int(n), float(wall_s)
s = json.load(open(run_dir + "/summary.json"))
m, r = s["metrics"], s["resources"]
sim = s["simulated_s"] or float("nan")
loop = r["loop_s"] or float("nan")
sent = sum(x["medium"]["sent"] for x in s["robots"])
delivered = sum(x["medium"]["delivered"] for x in s["robots"])
# Teardown: everything after the loop (stop images, outputs and plots, nns down).
teardown = wall_s - r["startup_s"] - r["loop_s"]
failure = (s["failure"] or "").replace(",", ";")[:80]
row = [n, pacing, run, f"{sim:.2f}", f"{wall_s:.2f}", load1, f"{loop / sim:.4f}",
       f"{m['stf']['mean']:.4f}", f"{m['stf']['p99']:.4f}", f"{m['t_phy_ms']['mean']:.4f}",
       f"{m['t_net_ms']['mean']:.4f}", f"{m['t_overhead_ms']['mean']:.4f}",
       f"{m['t_total_ms']['mean']:.4f}", f"{m['overhead_share']:.4f}",
       f"{m['lag_ms']['p99']:.4f}", sent, delivered, f"{sent / loop:.1f}", f"{sent / sim:.1f}",
       f"{delivered / loop:.1f}", f"{r['sitlnet_cpu_s']:.2f}", f"{r['robots_cpu_s']:.2f}",
       f"{r['robots_cpu_s'] / n:.3f}", f"{(r['sitlnet_cpu_s'] + r['robots_cpu_s']) / sim:.3f}",
       f"{r['robot_max_rss_kib'] / 1024:.1f}",
       f"{r['robot_median_rss_kib'] / 1024:.1f}", f"{r['startup_s']:.2f}", f"{loop:.2f}",
       f"{teardown:.2f}", failure]
print(",".join(str(x) for x in row))
