#!/usr/bin/env python3
"""The graph partition of distributed runs (ctest `mpi_partition`, FIBRANE_PETSC builds only).

For the peeling and the bending example at the coarse meshes of mpi_common.py, on 2 and 3 processes:
  mpiexec -n N fibrane run CASE --partition contiguous    (the unknowns in contiguous ranges)
  mpiexec -n N fibrane run CASE --partition graph         (PT-Scotch's partition of the element graph)
and checks
  - the graph run's history equals the contiguous one's to 1e-8 (mpi_common.compare, each column relative
    to its largest magnitude; the same steps, Newton iterations and limit-point flags);
  - summary.json's "partition" of each: the method asked for (no fallback note), one entry per process in
    elements, owned_unknowns and element_weight, the owned unknowns summing to free_dofs, the elements to
    the same total in both runs, imbalance = max / mean of element_weight, 0 < interface_unknowns <
    free_dofs; and the graph partition differs from the contiguous one;
  - summary.json's "memory" of each: both peaks (resident, allocated) a sum over the processes, between the
    largest process's and that many times it;
and that `fibrane run CASE --partition metis` exits with 2, names the option, and writes nothing.
Exit 0 when all hold, 1 with the failures listed otherwise.
"""
import subprocess
import sys

from mpi_common import CASES, case_text, compare, driver_arguments, mpi_environment, read_history, run, summary

PROCESSES = (2, 3)


def check_partition(s, method, processes, label):
    """Lines naming what is wrong with summary `s`'s partition."""
    p = s.get("partition")
    if p is None:
        return [f"{label}: summary.json has no partition"]
    problems = []
    if p["method"] != method or "note" in p:
        problems.append(f"{label}: method {p['method']} ({p.get('note', '')}), not {method}")
    for key in ("elements", "owned_unknowns", "element_weight"):
        if len(p[key]) != processes:
            problems.append(f"{label}: {key} has {len(p[key])} entries for {processes} processes")
    if p["processes"] != processes:
        problems.append(f"{label}: processes {p['processes']}, not {processes}")
    if sum(p["owned_unknowns"]) != s["free_dofs"]:
        problems.append(f"{label}: owned unknowns sum to {sum(p['owned_unknowns'])}, not {s['free_dofs']}")
    weights = p["element_weight"]
    expected = max(weights) / (sum(weights) / len(weights))
    if abs(p["imbalance"] - expected) > 1e-12 * expected:
        problems.append(f"{label}: imbalance {p['imbalance']}, max / mean of the weights {expected}")
    if not 0 < p["interface_unknowns"] < s["free_dofs"]:
        problems.append(f"{label}: interface_unknowns {p['interface_unknowns']} outside (0, {s['free_dofs']})")
    print(f"{label}: elements {p['elements']}, owned unknowns {p['owned_unknowns']}, interface "
          f"{p['interface_unknowns']}, imbalance {p['imbalance']:.4f}")
    return problems


def check_memory(s, processes, label):
    """Lines naming what is wrong with summary `s`'s memory section: each peak is a sum over the processes
    of per-process peaks, the largest of which is given beside it."""
    m = s["memory"]
    problems = [] if m.get("processes") == processes else [f"{label}: memory processes {m.get('processes')}"]
    for total, largest in (("peak_bytes", "largest_process_peak_bytes"),
                           ("peak_allocated_bytes", "largest_process_peak_allocated_bytes")):
        if not 0 < m[largest] <= m[total] <= processes * m[largest]:
            problems.append(f"{label}: {largest} {m[largest]} and {total} {m[total]} are not a largest part and a sum")
    return problems


def bad_value(fibrane, case, work):
    """`--partition metis`: exit 2, a message naming --partition, no output directory."""
    directory = work / "rejected"
    result = subprocess.run([fibrane, "run", case, "--partition", "metis", "-o", directory], env=mpi_environment(),
                            capture_output=True, text=True)
    problems = []
    if result.returncode != 2 or "--partition" not in result.stderr + result.stdout:
        problems.append(f"--partition metis: exit {result.returncode}, output {result.stderr + result.stdout!r}")
    if directory.exists():
        problems.append("--partition metis: the output directory was created")
    print(f"--partition metis: exit {result.returncode}: {(result.stderr + result.stdout).strip()}")
    return problems


def main():
    a, fibrane, work = driver_arguments(__doc__.splitlines()[0])
    problems = []
    for name in sorted(CASES):
        case = work / f"{name}.yaml"
        case.write_text(case_text(a.examples.resolve(), name))
        for processes in PROCESSES:
            partitions = {}
            for method in ("contiguous", "graph"):
                label = f"{name} np{processes} {method}"
                directory = work / label.replace(" ", "-")
                run([a.mpiexec, "-n", str(processes), fibrane, "run", case, "-q", "--partition", method, "-o", directory],
                    work, work / f"{directory.name}.log")
                s = summary(directory)
                problems += check_partition(s, method, processes, label)
                problems += check_memory(s, processes, label)
                partitions[method] = (s["partition"], read_history(directory / "history.csv"))
            (contiguous, reference), (graph, history) = partitions["contiguous"], partitions["graph"]
            problems += compare(reference, history, f"{name} np{processes}: graph against contiguous")
            if sum(graph["elements"]) != sum(contiguous["elements"]):
                problems.append(f"{name} np{processes}: the partitions count different elements")
            if all(graph[k] == contiguous[k] for k in ("elements", "owned_unknowns", "interface_unknowns")):
                problems.append(f"{name} np{processes}: the graph partition is the contiguous one; nothing is tested")
    problems += bad_value(fibrane, work / "peeling.yaml", work)
    for line in problems:
        print(line)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
