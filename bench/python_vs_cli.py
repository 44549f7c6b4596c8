#!/usr/bin/env python3
"""The Python module's run of a case against the CLI's: wall time and history, alternating runs.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_vs_cli.py [--case examples/peeling.yaml]
        [--mesh BEAM SHELL_U SHELL_V] [--repeat 3] [--threads N] [--work DIR] [--other-cli FIBRANE]

Each run is a fresh process with the caller's environment: `fibrane run CASE -o DIR [--threads N]` timed
from start to exit, and `fibrane.run(fibrane.Case.from_yaml(CASE), output=DIR, threads=N)` timed around
the call (the interpreter's start-up and `import fibrane`, timed separately, are reported beside it).
--mesh sets the example's element counts (beam, shell u, shell v) in a copy of the case. The histories
must agree exactly (same code, same thread count: bit-identical). Prints a line per run and the ratio of
the median times, module / CLI. --other-cli times another build's CLI in the same rounds (e.g. one without
the module, whose libraries are not position-independent).
"""
import argparse
import os
import pathlib
import resource
import statistics
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
MODULE_RUN = """
import sys, time
start = time.perf_counter()
import fibrane
case = fibrane.Case.from_yaml(sys.argv[1])
imported = time.perf_counter()
result = fibrane.run(case, output=sys.argv[2], threads=int(sys.argv[3]))
done = time.perf_counter()
print(done - imported, imported - start, result.steps)
"""


def timed(command, **kwargs):
    """Runs a command; returns its result, wall time and CPU time (user + system, with its threads)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    done = subprocess.run(command, check=True, **kwargs)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return done, wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def history(directory):
    lines = (pathlib.Path(directory) / "history.csv").read_text().splitlines()
    return lines[0].split(","), [[float(x) for x in line.split(",")] for line in lines[1:]]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--fibrane", default=str(ROOT / "build" / "app" / "fibrane"))
    p.add_argument("--case", default=str(ROOT / "examples" / "peeling.yaml"))
    p.add_argument("--mesh", nargs=3, type=int, metavar=("BEAM", "SHELL_U", "SHELL_V"))
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--threads", type=int, default=0, help="0: all cores (the default of both)")
    p.add_argument("--work", default="results/python-vs-cli")
    p.add_argument("--other-cli", help="another build's fibrane, timed in the same rounds")
    a = p.parse_args()
    work = pathlib.Path(a.work)
    work.mkdir(parents=True, exist_ok=True)
    case = pathlib.Path(a.case)
    if a.mesh:
        text = case.read_text().replace("elements: 100}", f"elements: {a.mesh[0]}}}", 1)
        text = text.replace("elements: [20, 10]", f"elements: [{a.mesh[1]}, {a.mesh[2]}]", 1)
        case = work / case.name
        case.write_text(text)
    threads = ["--threads", str(a.threads)] if a.threads else []
    times = {"cli": [], "module": [], "other": []}
    cpu = {"cli": [], "module": [], "other": []}
    for i in range(a.repeat):
        if a.other_cli:
            _, wall, used = timed([a.other_cli, "run", str(case), "-o", str(work / f"other_{i}"), "--quiet", *threads],
                                  stdout=subprocess.DEVNULL)
            times["other"].append(wall)
            cpu["other"].append(used)
            print(f"run {i}: other CLI {wall:.2f} s ({used:.2f} s CPU)", flush=True)
        out = work / f"cli_{i}"
        _, wall, used = timed([a.fibrane, "run", str(case), "-o", str(out), "--quiet", *threads], stdout=subprocess.DEVNULL)
        times["cli"].append(wall)
        cpu["cli"].append(used)
        out_py = work / f"module_{i}"
        done, _, used = timed([sys.executable, "-c", MODULE_RUN, str(case), str(out_py), str(a.threads)],
                              capture_output=True, text=True)
        line = done.stdout.split()
        times["module"].append(float(line[0]))
        cpu["module"].append(used)
        (names, cli_rows), (names_py, py_rows) = history(out), history(out_py)
        assert names == names_py and len(cli_rows) == len(py_rows), "the histories differ in shape"
        diff = max(abs(x - y) for r, s in zip(cli_rows, py_rows) for x, y in zip(r, s) if x == x or y == y)
        print(f"run {i}: CLI {times['cli'][-1]:.2f} s ({cpu['cli'][-1]:.2f} s CPU), module {times['module'][-1]:.2f} s "
              f"(+ {float(line[1]):.2f} s start-up and import; the process {cpu['module'][-1]:.2f} s CPU), {line[2]} "
              f"steps, history rows {len(cli_rows)}, largest difference {diff:g}", flush=True)
    print(f"median CPU: CLI {statistics.median(cpu['cli']):.2f} s, module process "
          f"{statistics.median(cpu['module']):.2f} s; module / CLI = "
          f"{statistics.median(cpu['module']) / statistics.median(cpu['cli']):.3f}")
    cli, module = statistics.median(times["cli"]), statistics.median(times["module"])
    print(f"median: CLI {cli:.2f} s, module {module:.2f} s; module / CLI = {module / cli:.3f} "
          f"(min: {min(times['module']) / min(times['cli']):.3f})")
    if times["other"]:
        other = statistics.median(times["other"])
        print(f"median: other CLI {other:.2f} s; CLI / other CLI = {cli / other:.3f}; CPU "
              f"{statistics.median(cpu['other']):.2f} s, CLI / other CLI = "
              f"{statistics.median(cpu['cli']) / statistics.median(cpu['other']):.3f}")


if __name__ == "__main__":
    main()
