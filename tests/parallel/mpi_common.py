#!/usr/bin/env python3
"""What the distributed-run tests (tests/parallel/mpi_*.py) share: the coarse-mesh cases, running fibrane
under mpiexec, reading history.csv and summary.json, and comparing histories column by column.

compare(): the same steps, Newton iterations and limit-point flags, and every other column within the
tolerance of the reference column's largest magnitude (relative). The components of a vector (columns
NAME_x, NAME_y, NAME_z) share one scale, the largest magnitude of the three: a component that vanishes by
symmetry (the peeling example's net interaction force in y) holds round-off only. `residual`, the
converged residual (round-off of each assembly, not a result), is not compared.
"""
import argparse
import csv
import json
import os
import pathlib
import shutil
import subprocess
import sys

NAME = pathlib.Path(sys.argv[0]).stem  # the test, for messages
TOLERANCE = 1e-8
EXACT = ("step", "iterations", "limit_point")
SKIPPED = ("residual",)

# name: (example, edits, serial solver). `auto` factorises by CHOLMOD's supernodal LL^T while the tangent
# is positive definite: the bending example's whole coarse path, and the peeling example's up to pull-off,
# beyond which the tangent has a negative eigenvalue and `auto` (in builds with PETSc, without sequential
# MUMPS) takes CHOLMOD's LDL^T. `cholmod` alone cannot follow the peeling path there: the arc-length
# method's bordered fallback then takes other steps. The bending model (point moments) cannot promise a
# symmetric tangent, and `cholmod` refuses it; `auto` probes the symmetry.
CASES = {
    "peeling": ("peeling.yaml", [
        ("elements: [20, 10]", "elements: [6, 4]"),
        ("elements: 100", "elements: 20"),
        ("ds: 0.02, ds_max: 0.5", "ds: 0.01, ds_max: 0.4"),
        ("output: {directory: out/peeling, vtk_every: 5}", "output: {vtk: false}"),
    ], "auto"),
    "bending": ("bending.yaml", [
        ("elements: [100, 100]", "elements: [10, 10]"),
        ("elements: 400", "elements: 40"),
        ("output: {directory: out/bending, vtk_every: 5}", "output: {vtk: false}"),
    ], "auto"),
}


def driver_arguments(description, extra=None):
    """The options every driver takes (--fibrane, --mpiexec, --examples, --work; `extra(parser)` adds its
    own). --work is emptied and made. Returns (arguments, fibrane, work), the paths resolved."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--fibrane", required=True, type=pathlib.Path)
    p.add_argument("--mpiexec", required=True)
    p.add_argument("--examples", required=True, type=pathlib.Path)
    p.add_argument("--work", required=True, type=pathlib.Path)
    if extra:
        extra(p)
    a = p.parse_args()
    fibrane, work = a.fibrane.resolve(), a.work.resolve()
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    return a, fibrane, work


def case_text(examples, name):
    """The example's text with the coarse-mesh edits and the serial solver in its steps."""
    file, edits, solver = CASES[name]
    text = (examples / file).read_text()
    for old, new in edits + [("\nsteps:\n", f"\nsteps:\n  solver: {solver}\n")]:
        if old not in text:
            raise SystemExit(f"{NAME}: '{old}' not found in {file}")
        text = text.replace(old, new, 1)
    return text


def read_history(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, data = rows[0], rows[1:]
    return {h: [float(r[k]) for r in data] for k, h in enumerate(header)}


def mpi_environment():
    """OpenMPI's settings for the tests: as root (CI containers), more processes than cores."""
    return dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1",
               OMPI_MCA_mpi_yield_when_idle="1")


def run(command, cwd, log):
    env = mpi_environment()
    with open(log, "w") as out:
        code = subprocess.run(command, cwd=cwd, env=env, stdout=out, stderr=subprocess.STDOUT).returncode
    if code != 0:
        sys.stdout.write(pathlib.Path(log).read_text())
        raise SystemExit(f"{NAME}: {' '.join(map(str, command))} exited with {code}")


def summary(directory):
    with open(directory / "summary.json") as f:
        return json.load(f)


def scales(serial):
    """The comparison scale of every column: its largest magnitude, shared by a vector's components."""
    largest = {c: max(abs(v) for v in values) for c, values in serial.items()}
    out = dict(largest)
    for column in serial:
        if column[-2:] in ("_x", "_y", "_z"):
            parts = [column[:-1] + c for c in "xyz"]
            if all(p in serial for p in parts):
                out[column] = max(largest[p] for p in parts)
    return {c: (v if v > 0 else 1.0) for c, v in out.items()}


def compare(serial, other, label, tolerance=TOLERANCE, skipped=()):
    """Lines describing every disagreement of `other` with the reference `serial` (empty: they agree);
    the columns in `skipped` are not compared."""
    problems = []
    if set(serial) != set(other):
        return [f"{label}: columns differ: {sorted(set(serial) ^ set(other))}"]
    if len(serial["step"]) != len(other["step"]):
        return [f"{label}: {len(other['step'])} rows, serial {len(serial['step'])}"]
    worst = 0.0
    scale_of = scales(serial)
    for column, values in serial.items():
        if column in SKIPPED or column in skipped:
            continue
        if column in EXACT:
            if values != other[column]:
                problems.append(f"{label}: column {column} differs")
            continue
        scale = scale_of[column]
        difference = max(abs(a - b) for a, b in zip(values, other[column])) / scale
        worst = max(worst, difference)
        if not difference <= tolerance:
            problems.append(f"{label}: column {column} differs by {difference:.3g} of its largest magnitude")
    print(f"{label}: {len(values)} rows, largest relative difference {worst:.3g} (tolerance {tolerance:g})")
    return problems


