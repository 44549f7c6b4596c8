#!/usr/bin/env python3
"""Distributed runs reproduce the serial CHOLMOD history (ctest `mpi_history`, FIBRANE_PETSC builds only).

For the peeling and the bending example at a coarse mesh (the meshes of their C++ tests), runs
  serial:       fibrane run CASE --threads 1                 (the case's solver set to auto: CHOLMOD)
  1 process:    mpiexec -n 1 fibrane run CASE --mpi-solver mumps
  2 processes:  mpiexec -n 2 fibrane run CASE
  3 processes:  mpiexec -n 3 fibrane run CASE                (uneven ownership: unequal shares of the unknowns)
(the distributed runs with the default graph partition) and compares every history.csv with the serial one
(mpi_common.compare): the same steps, Newton iterations and limit-point flags, and every other column
within 1e-8 of the serial column's largest magnitude (relative). The bending example keeps its
`local_first_update`: every run makes as many local updates as the serial one (summary.json), and some.
`--processes 4 8` runs other counts in place of 1, 2 and 3 (more processes than cores: oversubscribed, for
correctness only).
Exit 0 when all agree, 1 with the differing columns listed otherwise.
"""
import sys

from mpi_common import CASES, case_text, compare, driver_arguments, read_history, run, summary


def main():
    def options(p):
        p.add_argument("--cases", nargs="+", default=sorted(CASES), choices=sorted(CASES))
        p.add_argument("--processes", nargs="+", type=int, default=[1, 2, 3])
    a, a.fibrane, a.work = driver_arguments(__doc__.splitlines()[0], options)
    a.examples = a.examples.resolve()
    problems = []
    for name in a.cases:
        case = a.work / f"{name}.yaml"
        case.write_text(case_text(a.examples, name))
        runs = {"serial": [a.fibrane, "run", case, "-q", "--threads", "1", "-o", a.work / f"{name}-serial"]}
        for n in a.processes:
            # One process runs distributed only when asked to; several always do.
            solver = ["--mpi-solver", "mumps"] if n == 1 else []
            runs[f"np{n}"] = [a.mpiexec, "-n", str(n), a.fibrane, "run", case, "-q"] + solver + ["-o", a.work / f"{name}-np{n}"]
        for label, command in runs.items():
            run(command, a.work, a.work / f"{name}-{label}.log")
        serial = read_history(a.work / f"{name}-serial" / "history.csv")
        local = summary(a.work / f"{name}-serial")["local_updates"]
        if "local_first_update" in case.read_text() and local == 0:
            problems.append(f"{name}: the serial run made no local update")
        for n in a.processes:
            problems += compare(serial, read_history(a.work / f"{name}-np{n}" / "history.csv"), f"{name} np{n}")
            made = summary(a.work / f"{name}-np{n}")["local_updates"]
            print(f"{name} np{n}: {made} local updates (serial {local})")
            if made != local:
                problems.append(f"{name} np{n}: {made} local updates, serial {local}")
    if 3 in a.processes:
        # 3 processes own unequal shares of the unknowns in at least one case.
        uneven = [n for n in a.cases if len(set(summary(a.work / f"{n}-np3")["partition"]["owned_unknowns"])) > 1]
        print(f"cases whose unknowns 3 processes own unevenly: {uneven}")
        if not uneven:
            problems.append("no case splits its unknowns unevenly over 3 processes")
    for line in problems:
        print(line)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
