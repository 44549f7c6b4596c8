#!/usr/bin/python3
"""Compares two builds of a Google Benchmark program run alternately on the same machine.

    scripts/bench_compare.py OLD_BINARY NEW_BINARY [--rounds 9] [--min-time 0.3] [--filter REGEX]

For every benchmark (of OLD, matching REGEX), runs it in OLD and in NEW in turn `rounds` times (the order
swapped every round, so that a drift of the machine's load hits both alike) and prints the best (smallest)
CPU time of each and their ratio NEW / OLD, the median over the rounds of the per-round ratio, the range of
those ratios, and the load average before and after. On a shared machine other jobs only ever add time, so
the best of many runs is the steadiest estimate; the median of the paired ratios is the check against it.
"""
import argparse
import json
import os
import re
import statistics
import subprocess


def run(binary, min_time, bench_filter):
    cmd = [binary, f"--benchmark_min_time={min_time}", "--benchmark_format=json"]
    if bench_filter:
        cmd.append(f"--benchmark_filter={bench_filter}")
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return {b["name"]: (b["cpu_time"], b["real_time"], b["time_unit"]) for b in json.loads(out)["benchmarks"]}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("old")
    p.add_argument("new")
    p.add_argument("--rounds", type=int, default=9)
    p.add_argument("--min-time", type=float, default=0.3)
    p.add_argument("--filter", default="")
    a = p.parse_args()
    load_before = os.getloadavg()
    names = list(run(a.old, 0.01, a.filter))
    rows = []
    for name in names:
        only = "^" + re.escape(name) + "$"
        old, new = [], []
        for r in range(a.rounds):
            order = [(a.old, old), (a.new, new)] if r % 2 == 0 else [(a.new, new), (a.old, old)]
            for binary, results in order:
                results.append(run(binary, a.min_time, only)[name])
        rows.append((name, old, new))
    load_after = os.getloadavg()
    print(f"{a.rounds} rounds per benchmark; load average before {load_before[0]:.2f} {load_before[1]:.2f} "
          f"{load_before[2]:.2f}, after {load_after[0]:.2f} {load_after[1]:.2f} {load_after[2]:.2f}")
    print("| benchmark | old best CPU | new best CPU | ratio of best | median paired ratio | range |")
    print("|---|---|---|---|---|---|")
    for name, old, new in rows:
        unit = old[0][2]
        best_old, best_new = min(o[0] for o in old), min(n[0] for n in new)
        paired = [n[0] / o[0] for o, n in zip(old, new)]
        print(f"| {name} | {best_old:.3f} {unit} | {best_new:.3f} {unit} | {best_new / best_old:.3f} | "
              f"{statistics.median(paired):.3f} | {min(paired):.3f}-{max(paired):.3f} |")


if __name__ == "__main__":
    main()
