#!/usr/bin/env python3
"""Markdown tables of docs/scale.csv and docs/scale_ablation.csv (docs/performance.md).

Usage: table.py docs/scale.csv [docs/scale_ablation.csv]
"""
import csv
import sys


def f(value, digits):
    return f"{float(value):.{digits}f}"


rows = list(csv.DictReader(open(sys.argv[1])))
print("| robots | pacing | runs | load | STF mean | STF p99 | T_phy ms | T_net ms | T_overhead ms "
      "| overhead share | lag p99 ms | frames sent/s | frames delivered/s | sitlnet CPU s per sim s "
      "| robot CPU ms per sim s | robot RSS MiB (median/max) | start-up s | teardown s |")
print("|" + " --- |" * 19)
for r in sorted(rows, key=lambda r: (r["pacing"], int(r["robots"]))):
    sim = float(r["simulated_s"])
    lag = f(r["lag_p99_ms"], 2) if r["pacing"] == "realtime" else "–"
    print(f"| {r['robots']} | {r['pacing']} | {r['runs']} | {f(r['load1'], 1)} "
          f"| {f(r['stf_mean'], 3)} | {f(r['stf_p99'], 3)} | {f(r['t_phy_ms'], 2)} "
          f"| {f(r['t_net_ms'], 2)} | {f(r['t_overhead_ms'], 3)} "
          f"| {100 * float(r['overhead_share']):.1f} % | {lag} | {f(r['sent_per_wall_s'], 0)} "
          f"| {f(r['delivered_per_wall_s'], 0)} | {float(r['sitlnet_cpu_s']) / sim:.3f} "
          f"| {1000 * float(r['robot_cpu_s_per_robot']) / sim:.1f} "
          f"| {f(r['robot_median_rss_mib'], 1)}/{f(r['robot_max_rss_mib'], 1)} "
          f"| {f(r['startup_s'], 2)} | {f(r['teardown_s'], 2)} |")
if len(sys.argv) > 2:
    print()
    print("| variant (64 robots) | pacing | runs | load | STF mean | STF p99 | T_phy ms | T_net ms "
          "| T_overhead ms | lag p99 ms | sitlnet CPU s per sim s | robots CPU s per sim s |")
    print("|" + " --- |" * 12)
    for r in csv.DictReader(open(sys.argv[2])):
        sim = float(r["simulated_s"])
        lag = f(r["lag_p99_ms"], 2) if r["pacing"] == "realtime" else "–"
        print(f"| {r['variant']} | {r['pacing']} | {r['runs']} | {f(r['load1'], 1)} "
              f"| {f(r['stf_mean'], 3)} | {f(r['stf_p99'], 3)} | {f(r['t_phy_ms'], 2)} "
              f"| {f(r['t_net_ms'], 2)} | {f(r['t_overhead_ms'], 3)} | {lag} "
              f"| {float(r['sitlnet_cpu_s']) / sim:.3f} | {float(r['robots_cpu_s']) / sim:.3f} |")
