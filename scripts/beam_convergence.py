#!/usr/bin/python3
"""Mesh-convergence tables and Newton histories for the beam benchmarks (docs/verification.md).

Runs the fibrane CLI on edited copies of examples/beam-rollup.yaml and examples/bathe-bolourchi.yaml
(degree 2..4, 4..64 elements, maximal continuity) and prints Markdown tables of the tip errors and
Newton iteration counts. The Newton residual histories come from the test binary (test_model,
BeamBenchmarks.NewtonHistoriesOfLastSteps prints them), because the CLI reports only per-step counts.

Usage: scripts/beam_convergence.py [build-dir]   (default: build-beamver; needs targets fibrane, test_model)
"""
import csv
import math
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
BUILD = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "build-beamver"
FIBRANE = BUILD / "app" / "fibrane"
TEST_MODEL = BUILD / "tests" / "test_model"
DEGREES = (2, 3, 4)
ELEMENTS = (4, 8, 16, 32, 64)
BEND_REFERENCE = (47.151, 15.685, 53.469)  # inextensible Kirchhoff rod (docs/verification.md)


def run_case(example, degree, elements, workdir):
    """Runs an edited copy of an example; returns (rows of history.csv, completed flag)."""
    text = (ROOT / "examples" / example).read_text()
    text, n = re.subn(r"refine: \{degree: \d+, continuity: \d+, elements: \d+\}",
                      f"refine: {{degree: {degree}, continuity: {degree - 1}, elements: {elements}}}", text)
    assert n == 1, "refine line not found in " + example
    text = text.replace("output: {", "output: {vtk: false, ")
    # The Newton tolerance is relative to the external load, but the round-off level of the residual grows
    # with the internal forces (EA / element length): at 64 elements it exceeds 1e-9 of the bend's load
    # step. 1e-7 keeps every run above round-off and moves the tip by < 1e-5.
    text = re.sub(r"tolerance: [^,}]*, ", "", text)
    text = re.sub(r"steps: \{", "steps: {tolerance: 1e-7, ", text)
    case = workdir / f"{pathlib.Path(example).stem}-p{degree}-n{elements}.yaml"
    case.write_text(text)
    out = workdir / case.stem
    proc = subprocess.run([str(FIBRANE), "run", "-q", "--threads", "1", str(case), "-o", str(out)],
                          capture_output=True, text=True)
    history = out / "history.csv"
    if not history.exists():
        return [], False
    with history.open() as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    return rows, proc.returncode == 0 and abs(rows[-1]["t"] - 1.0) < 1e-9


def at_time(rows, t):
    return next((r for r in rows if abs(r["t"] - t) < 1e-9), None)


def rollup_table(workdir):
    L = 10.0
    print("| degree | elements | error at M/2 / L | error at M / L | Newton iterations (8 steps) |")
    print("|---|---|---|---|---|")
    for p in DEGREES:
        for n in ELEMENTS:
            rows, ok = run_case("beam-rollup.yaml", p, n, workdir)
            half, full = at_time(rows, 0.5), at_time(rows, 1.0)
            if not ok or half is None or full is None:
                print(f"| {p} | {n} | failed | failed | - |")
                continue
            e_half = math.hypot(half["tip_x"], half["tip_z"] - 2 * L / math.pi) / L
            e_full = math.hypot(full["tip_x"], full["tip_z"]) / L
            its = int(sum(r["iterations"] for r in rows))
            print(f"| {p} | {n} | {e_half:.2e} | {e_full:.2e} | {its} |")


def bend_table(workdir):
    print("| degree | elements | tip x | tip y | tip z | max deviation from (47.151, 15.685, 53.469) "
          "| Newton iterations (8 steps) |")
    print("|---|---|---|---|---|---|---|")
    for p in DEGREES:
        for n in ELEMENTS:
            rows, ok = run_case("bathe-bolourchi.yaml", p, n, workdir)
            if not ok:
                print(f"| {p} | {n} | failed | | | | |")
                continue
            tip = (rows[-1]["tip_x"], rows[-1]["tip_y"], rows[-1]["tip_z"])
            dev = max(abs(a - b) for a, b in zip(tip, BEND_REFERENCE))
            its = int(sum(r["iterations"] for r in rows))
            print(f"| {p} | {n} | {tip[0]:.4f} | {tip[1]:.4f} | {tip[2]:.4f} | {dev:.4f} | {its} |")


def newton_histories():
    proc = subprocess.run([str(TEST_MODEL), "--gtest_filter=BeamBenchmarks.NewtonHistoriesOfLastSteps"],
                          capture_output=True, text=True, cwd=ROOT)
    runs = {}
    for line in proc.stdout.splitlines():
        m = re.match(r"newton (\S+) t=(\S+) it=(\d+) \|r\|=(\S+) \|dq\|=(\S+)", line)
        if m:
            runs.setdefault((m[1], m[2]), []).append((int(m[3]), float(m[4]), float(m[5])))
    for (example, t), its in runs.items():
        print(f"\n{example}, last step to t = {t} (from the converged previous step, no predictor):\n")
        print("| iteration | residual norm | update norm |")
        print("|---|---|---|")
        for k, r, dq in its:
            print(f"| {k} | {r:.3e} | {dq:.3e} |")


def main():
    with tempfile.TemporaryDirectory(prefix="beam-convergence-") as tmp:
        work = pathlib.Path(tmp)
        print("## Roll-up (examples/beam-rollup.yaml)\n")
        rollup_table(work)
        print("\n## Bathe-Bolourchi 45-degree bend (examples/bathe-bolourchi.yaml)\n")
        bend_table(work)
    print("\n## Newton histories")
    newton_histories()


if __name__ == "__main__":
    main()
