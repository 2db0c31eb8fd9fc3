#!/usr/bin/env python3
"""The ratios of an A/B series (ab_lib.sh's runs.csv) against its reference variant.

Usage: ab_summary.py RUNS.csv REFERENCE COLUMN... [--medians COLUMN...]
For each other variant and each COLUMN: the per-round ratios variant/REFERENCE (rounds paired
by the "run" column, the round's seed), their median, and the sign test's confidence interval
for the median ratio (distribution-free: order statistics of the binomial(n, 1/2)), with its
exact confidence level, and how many rounds were above 1. After --medians: each variant's
median of those columns (empty cells skipped).
"""
import csv
import math
import statistics
import sys


def sign_interval(values, confidence=0.95):
    """(low, high, level): the widest-k order-statistic interval whose level >= confidence,
    or the whole range (with its level) when n is too small for that."""
    x = sorted(values)
    n = len(x)
    def tail(k):  # P(Binomial(n, 1/2) <= k - 1)
        return sum(math.comb(n, i) for i in range(k)) / 2 ** n
    k = 1
    while k + 1 <= n // 2 and 1 - 2 * tail(k + 1) >= confidence:
        k += 1
    return x[k - 1], x[n - k], 1 - 2 * tail(k)


def main():
    args = sys.argv[1:]
    medians = args[args.index("--medians") + 1:] if "--medians" in args else []
    if "--medians" in args:
        args = args[:args.index("--medians")]
    path, reference, columns = args[0], args[1], args[2:]
    rows = list(csv.DictReader(open(path)))
    variants = list(dict.fromkeys(r["variant"] for r in rows))
    by = {(r["variant"], r["run"]): r for r in rows}
    for variant in variants:
        if variant == reference:
            continue
        rounds = [run for (v, run) in by if v == variant and (reference, run) in by]
        for column in columns:
            ratios = [float(by[(variant, run)][column]) / float(by[(reference, run)][column])
                      for run in rounds]
            low, high, level = sign_interval(ratios)
            above = sum(r > 1 for r in ratios)
            print(f"{column} {variant}/{reference}: {len(ratios)} rounds, median "
                  f"{statistics.median(ratios):.4f}, {level * 100:.1f} % interval "
                  f"[{low:.4f}, {high:.4f}], {above} above 1; per round "
                  + ", ".join(f"{r:.3f}" for r in ratios))
    for column in medians:
        cells = {v: [float(r[column]) for r in rows if r["variant"] == v and r[column]]
                 for v in variants}
        print(f"{column} medians: " + "; ".join(
            f"{v} {statistics.median(c):.4f} ({min(c):.4f}-{max(c):.4f})"
            for v, c in cells.items() if c))


main()
