#!/usr/bin/env python3
"""The case's solver keys in distributed runs (ctest `mpi_solvers`, FIBRANE_PETSC builds only).

For the peeling example (arc-length through pull-off: its sign rule factorises every converged state
exactly) and the bending example at the coarse meshes of mpi_common.py:
  fibrane run CASE --threads 1                       (serial, direct, full Newton: the reference)
  mpiexec -n 2 fibrane run CASE+krylov               (steps.krylov: true -> GMRES with an earlier
                                                      tangent's MUMPS factorisation)
  mpiexec -n 2 fibrane run CASE+low_rank             (steps.low_rank: 1e-10 -> MUMPS's block low-rank
                                                      factorisations, refined by GMRES)
  mpiexec -n 2 fibrane run CASE+mumps-lu             (steps.solver: mumps-lu -> MUMPS's LU of the
                                                      symmetric tangents, PETSc's AIJ matrix)
  mpiexec -n 2 fibrane run CASE+out_of_core          (steps.out_of_core: a directory -> each process's
                                                      factor in files there while the run lasts (the
                                                      directory is polled), deleted at the run's end)
(modified Newton's `reuse_factorization` removed from all four, as Krylov solves exclude it, and the
bending example's `local_first_update`, so that every Newton update is the solver's) and checks
that each distributed history equals the serial one to 1e-6 of each column's largest magnitude with the
same steps, Newton iterations and limit-point flags (the solves are refined to 1e-8 relative, so the
Newton iterates agree to about that, well inside Newton's tolerance; `negative_eigenvalues` is -1 where a
step's last factorisation was an earlier tangent's, and is not compared), that summary.json names the
GMRES path (with `-blr` for low_rank) or the LU, and that GMRES reused factorisations (fewer
factorisations than Newton iterations) where the case asks for Krylov solves. Then that a distributed run exits with 2, names the key, and writes
nothing for what that path cannot do: `precision: single`, a serial solver (`solver: cholmod`),
`--mpi-solver mumps` against `krylov: true`, and Newton's local solves (`local_newton`).
Exit 0 when all hold, 1 with the failures listed otherwise.
"""
import pathlib
import re
import subprocess
import sys
import time

from mpi_common import CASES, case_text, compare, driver_arguments, mpi_environment, read_history, run, summary

TOLERANCE = 1e-6
VARIANTS = {"krylov": "  krylov: true\n", "low_rank": "  low_rank: 1.0e-10\n", "mumps-lu": "",
            "out_of_core": "  out_of_core: FACTOR_DIRECTORY\n"}
SOLVER_NAMES = {"krylov": "petsc-gmres(mumps-ldlt)", "low_rank": "petsc-gmres(mumps-ldlt-blr)", "mumps-lu": "petsc-mumps-lu",
                "out_of_core": "petsc-mumps-ldlt-ooc"}


def with_steps(text, lines):
    """The case text with `lines` added to its steps, modified Newton's reuse removed (it excludes both), the
    split Cholesky removed (a key of solver auto and cholmod, which one variant replaces) and the local
    first update removed (every update then goes through the solver under test)."""
    text = re.sub(r"\n  reuse_factorization: [^\n]*", "", text)
    text = re.sub(r"\n  split: [^\n]*", "", text)
    text = re.sub(r"\n  local_first_update: [^\n]*", "", text)
    return text.replace("\nsteps:\n", "\nsteps:\n" + lines, 1)


def run_watching(command, cwd, log, directory):
    """run() of mpi_common, polling `directory` while the command runs: the most files seen in it at once."""
    with open(log, "w") as out:
        process = subprocess.Popen(command, cwd=cwd, env=mpi_environment(), stdout=out, stderr=subprocess.STDOUT)
        most = 0
        while process.poll() is None:
            most = max(most, sum(1 for _ in directory.iterdir()))
            time.sleep(0.02)
    if process.returncode != 0:
        sys.stdout.write(pathlib.Path(log).read_text())
        raise SystemExit(f"mpi_solvers: {' '.join(map(str, command))} exited with {process.returncode}")
    return most


def factorisations(s):
    m = re.search(r"(\d+) factorisations", s.get("linear_solver_statistics", ""))
    return int(m.group(1)) if m else -1


def refused(fibrane, a, work, label, text, arguments, key):
    """A 2-process run of `text` with `arguments`: exit 2, `key` in the message, no output directory."""
    case = work / f"{label}.yaml"
    case.write_text(text)
    directory = work / label
    result = subprocess.run([a.mpiexec, "-n", "2", fibrane, "run", case, "-o", directory] + arguments,
                            env=mpi_environment(), capture_output=True, text=True)
    message = (result.stderr + result.stdout).strip()
    print(f"{label}: exit {result.returncode}: {message.splitlines()[0] if message else ''}")
    problems = []
    if result.returncode != 2 or key not in message:
        problems.append(f"{label}: exit {result.returncode}, message {message!r} (expected 2, naming {key})")
    if directory.exists():
        problems.append(f"{label}: the output directory was created")
    return problems


def main():
    a, fibrane, work = driver_arguments(__doc__.splitlines()[0])
    problems = []
    for name in sorted(CASES):
        text = case_text(a.examples.resolve(), name)
        case = work / f"{name}.yaml"
        case.write_text(with_steps(text, ""))
        serial_dir = work / f"{name}-serial"
        run([fibrane, "run", case, "-q", "--threads", "1", "-o", serial_dir], work, work / f"{name}-serial.log")
        serial = read_history(serial_dir / "history.csv")
        for variant, lines in VARIANTS.items():
            label = f"{name}-{variant}"
            variant_case = work / f"{label}.yaml"
            variant_text = with_steps(text, lines)
            if variant == "mumps-lu":
                variant_text = variant_text.replace("  solver: auto\n", "  solver: mumps-lu\n", 1)
            factor_directory = work / f"{label}-factor-files"
            if variant == "out_of_core":
                factor_directory.mkdir(exist_ok=True)
                variant_text = variant_text.replace("FACTOR_DIRECTORY", str(factor_directory))
            variant_case.write_text(variant_text)
            directory = work / label
            command = [a.mpiexec, "-n", "2", fibrane, "run", variant_case, "-q", "-o", directory]
            if variant == "out_of_core":
                # Each of the 2 processes writes its part of the factor there while the run lasts.
                most = run_watching(command, work, work / f"{label}.log", factor_directory)
                print(f"{label}: at most {most} factor files at once")
                if most < 2:
                    problems.append(f"{label}: {most} factor files seen in {factor_directory} during the run "
                                    "(expected one per process at least)")
            else:
                run(command, work, work / f"{label}.log")
            problems += compare(serial, read_history(directory / "history.csv"), label, TOLERANCE,
                                skipped=("negative_eigenvalues",))
            s = summary(directory)
            print(f"{label}: {s['linear_solver']}; {s['newton_iterations']} Newton iterations; "
                  f"{s.get('linear_solver_statistics', '')}")
            if not s["linear_solver"].startswith(SOLVER_NAMES[variant] + " "):
                problems.append(f"{label}: linear_solver {s['linear_solver']!r}, not {SOLVER_NAMES[variant]}")
            if variant == "out_of_core" and any(factor_directory.iterdir()):
                problems.append(f"{label}: factor files left in {factor_directory}")
            if variant == "krylov" and not 0 < factorisations(s) < s["newton_iterations"]:
                problems.append(f"{label}: {factorisations(s)} factorisations for {s['newton_iterations']} Newton "
                                "iterations: no factorisation was reused")
    text = case_text(a.examples.resolve(), "bending")
    problems += refused(fibrane, a, work, "single", with_steps(text, "  precision: single\n"), [], "steps.precision")
    problems += refused(fibrane, a, work, "cholmod", text.replace("  solver: auto\n", "  solver: cholmod\n", 1), [],
                        "steps.solver")
    problems += refused(fibrane, a, work, "mumps-and-krylov", with_steps(text, VARIANTS["krylov"]),
                        ["--mpi-solver", "mumps"], "--mpi-solver")
    problems += refused(fibrane, a, work, "local-newton", with_steps(text, "  local_newton: 4\n"), [],
                        "steps.local_newton")
    for p in problems:
        print(f"FAIL {p}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
