#!/usr/bin/python3
"""Compares two builds of a Google Benchmark program run alternately on the same machine.

    scripts/bench_compare.py OLD_BINARY NEW_BINARY [--rounds 9] [--min-time 0.3] [--filter REGEX]

Runs OLD and NEW in turn `rounds` times (the order swapped every round, so that a drift of the machine's
load hits both alike) and prints, per benchmark, the median CPU time of each and the median over the rounds
of the per-round ratio NEW / OLD (CPU time, and wall time for reference), with the range of the ratios and
the load average (uptime) before and after.
"""
import argparse
import json
import os
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
    old, new = [], []
    for r in range(a.rounds):
        order = [(a.old, old), (a.new, new)] if r % 2 == 0 else [(a.new, new), (a.old, old)]
        for binary, results in order:
            results.append(run(binary, a.min_time, a.filter))
    load_after = os.getloadavg()
    print(f"{a.rounds} rounds; load average before {load_before[0]:.2f} {load_before[1]:.2f} {load_before[2]:.2f}, "
          f"after {load_after[0]:.2f} {load_after[1]:.2f} {load_after[2]:.2f}")
    print(f"| benchmark | old CPU | new CPU | median ratio new/old (CPU) | range | median ratio (wall) |")
    print("|---|---|---|---|---|---|")
    for name in old[0]:
        unit = old[0][name][2]
        cpu = [n[name][0] / o[name][0] for o, n in zip(old, new)]
        wall = [n[name][1] / o[name][1] for o, n in zip(old, new)]
        old_cpu = statistics.median(o[name][0] for o in old)
        new_cpu = statistics.median(n[name][0] for n in new)
        print(f"| {name} | {old_cpu:.3f} {unit} | {new_cpu:.3f} {unit} | {statistics.median(cpu):.3f} | "
              f"{min(cpu):.3f}-{max(cpu):.3f} | {statistics.median(wall):.3f} |")


if __name__ == "__main__":
    main()
