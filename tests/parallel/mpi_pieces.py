#!/usr/bin/env python3
"""Parallel VTK output read back by VTK (ctest `mpi_pieces`, FIBRANE_PETSC builds only; /usr/bin/python3 with
python3-vtk9).

Runs the peeling example at the coarse mesh of mpi_history.py with `output: {vtk_every: 4, vtk_pieces: true}`
on 1 process (serial), 2 and 3 processes, and checks for every series and every step:
  - <series>_pieces.pvd lists the .pvtu files of exactly the steps and timesteps of <series>.pvd;
  - each .pvtu, read by vtkXMLPUnstructuredGridReader, names one piece per process, and equals the gathered
    .vtu of the step (vtkXMLUnstructuredGridReader): the same cells in the same order with the same types,
    and every cell's point coordinates, point fields and cell fields within 1e-12 of the largest magnitude
    of the array (the pieces are written from the same doubles, so in practice they are equal);
  - the manifest lists every piece, .pvtu and _pieces.pvd file, and no *.tmp.* file is left;
and the same of a 2-process run stopped by --max-steps 6 and continued on 3 processes by --restart (the
series continue; each .pvtu names the pieces of the run that wrote it).
Exit 0 when all hold, 1 with the failures listed otherwise.
"""
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

from mpi_common import case_text, driver_arguments, mpi_environment, run

TOLERANCE = 1e-12


def read(path, parallel):
    reader = vtk.vtkXMLPUnstructuredGridReader() if parallel else vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def cells(grid):
    """Per cell: its type and point ids, in order."""
    out = []
    ids = vtk.vtkIdList()
    for c in range(grid.GetNumberOfCells()):
        grid.GetCellPoints(c, ids)
        out.append((grid.GetCellType(c), [ids.GetId(k) for k in range(ids.GetNumberOfIds())]))
    return out


def arrays(data):
    return {data.GetArrayName(k): vtk_to_numpy(data.GetArray(k)).reshape(data.GetArray(k).GetNumberOfTuples(), -1)
            for k in range(data.GetNumberOfArrays())}


def compare(gathered, pieced, label):
    """Lines naming every difference of the pieced grid from the gathered one."""
    a, b = cells(gathered), cells(pieced)
    if len(a) != len(b) or [t for t, _ in a] != [t for t, _ in b]:
        return [f"{label}: cells differ ({len(a)} gathered, {len(b)} in pieces)"]
    problems = []
    ia = np.concatenate([p for _, p in a]).astype(int) if a else np.zeros(0, int)
    ib = np.concatenate([p for _, p in b]).astype(int) if b else np.zeros(0, int)
    if [len(p) for _, p in a] != [len(p) for _, p in b]:
        return [f"{label}: cells' point counts differ"]
    pa, pb = vtk_to_numpy(gathered.GetPoints().GetData()), vtk_to_numpy(pieced.GetPoints().GetData())
    pairs = [("points", pa[ia], pb[ib])]
    fa, fb = arrays(gathered.GetPointData()), arrays(pieced.GetPointData())
    ca, cb = arrays(gathered.GetCellData()), arrays(pieced.GetCellData())
    if set(fa) != set(fb) or set(ca) != set(cb):
        return [f"{label}: fields differ: {sorted(fa)} {sorted(ca)} against {sorted(fb)} {sorted(cb)}"]
    pairs += [(f"point field {n}", fa[n][ia], fb[n][ib]) for n in fa]
    pairs += [(f"cell field {n}", ca[n], cb[n]) for n in ca]
    for name, x, y in pairs:
        scale = max(float(np.max(np.abs(x))) if x.size else 0.0, 1e-300)
        difference = float(np.max(np.abs(x - y))) / scale if x.size else 0.0
        if not difference <= TOLERANCE:
            problems.append(f"{label}: {name} differs by {difference:.3g} of its largest magnitude")
    return problems


def series(pvd):
    return [(float(d.get("timestep")), d.get("file")) for d in ET.parse(pvd).getroot().findall("./Collection/DataSet")]


def check_directory(directory, processes, label):
    """`processes`: the piece counts a .pvtu may have."""
    problems = []
    manifest = set((directory / ".fibrane-manifest").read_text().splitlines()[1:])
    checked = 0
    for pvd in sorted(directory.glob("*_pieces.pvd")):
        gathered = series(directory / pvd.name.replace("_pieces.pvd", ".pvd"))
        pieced = series(pvd)
        if pvd.name not in manifest:
            problems.append(f"{label}: {pvd.name} not in the manifest")
        if [t for t, _ in gathered] != [t for t, _ in pieced] or \
                [f[:-4] + ".pvtu" for _, f in gathered] != [f for _, f in pieced]:
            problems.append(f"{label}: {pvd.name} does not list the steps of the gathered series")
            continue
        for (_, vtu), (_, pvtu) in zip(gathered, pieced):
            sources = [p.get("Source") for p in ET.parse(directory / pvtu).getroot().iter("Piece")]
            if len(sources) not in processes:
                problems.append(f"{label}: {pvtu} has {len(sources)} pieces, not {processes}")
            for f in [pvtu] + ["vtk/" + s for s in sources]:
                if f not in manifest:
                    problems.append(f"{label}: {f} not in the manifest")
            problems += compare(read(directory / vtu, False), read(directory / pvtu, True), f"{label} {pvtu}")
            checked += 1
    if checked == 0:
        problems.append(f"{label}: no .pvtu series found")
    leftovers = [str(p) for p in directory.rglob("*.tmp.*")]
    if leftovers:
        problems.append(f"{label}: temporaries left: {leftovers}")
    print(f"{label}: {checked} .pvtu files compared with the gathered .vtu files")
    return problems


def main():
    a, fibrane, work = driver_arguments(__doc__.splitlines()[0])
    case = work / "peeling.yaml"
    case.write_text(case_text(a.examples.resolve(), "peeling").replace(
        "output: {vtk: false}", "output: {vtk_every: 4, vtk_pieces: true}"))
    problems = []
    for processes in (1, 2, 3):
        directory = work / f"np{processes}"
        prefix = [fibrane] if processes == 1 else [a.mpiexec, "-n", str(processes), fibrane]
        run(prefix + ["run", case, "-q", "-o", directory], work, work / f"np{processes}.log")
        problems += check_directory(directory, [processes], f"{processes} process{'es' if processes > 1 else ''}")
    restarted = work / "restarted"
    with open(work / "stopped.log", "w") as log:
        code = subprocess.run([a.mpiexec, "-n", "2", fibrane, "run", case, "-q", "--max-steps", "6", "-o", restarted],
                              env=mpi_environment(), stdout=log, stderr=subprocess.STDOUT).returncode
    if code == 0 or not (restarted / "checkpoint.bin").exists():
        problems.append(f"--max-steps 6: exit {code}, expected a stopped run with a checkpoint")
    run([a.mpiexec, "-n", "3", fibrane, "run", case, "-q", "--restart", restarted], work, work / "restarted.log")
    problems += check_directory(restarted, [2, 3], "2 processes, restarted on 3")
    for line in problems:
        print(line)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
