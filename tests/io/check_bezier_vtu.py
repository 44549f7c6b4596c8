"""Checks a .vtu of Bezier cells with VTK itself.

usage: check_bezier_vtu.py MESH.vtu POINTS.csv [TOLERANCE]

POINTS.csv has the columns cell, r, s, x, y, z, then one column per field component named
<field>:<component>. Each row is a point of cell `cell` at VTK's parametric coordinates (r, s) in
[0, 1]^2 (s = 0 for curves) with fibrane's own evaluation of the NURBS there: the position and the fields.
vtkXMLUnstructuredGridReader reads the mesh; the cell evaluates the position (EvaluateLocation, which
uses the cell's rational Bernstein functions) and the same interpolation weights give the fields.
Positions must agree to TOLERANCE (default 1e-12) times the mesh's bounding-box diagonal, each field to
TOLERANCE times its largest expected magnitude. Prints the worst relative errors; exit code 0 if all
agree, 1 if not, 2 if VTK cannot read the file or the mesh is not a rational Bezier mesh.
"""
import csv
import math
import sys

import vtk


def read_grid(path):
    errors = []
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.AddObserver("ErrorEvent", lambda obj, event: errors.append(event))
    reader.SetFileName(path)
    reader.Update()
    if errors or reader.GetErrorCode() != 0:
        print("VTK could not read", path)
        sys.exit(2)
    grid = reader.GetOutput()
    if grid.GetPointData().GetRationalWeights() is None or grid.GetCellData().GetHigherOrderDegrees() is None:
        print("RationalWeights / HigherOrderDegrees are not marked as attributes")
        sys.exit(2)
    return grid


def main():
    grid = read_grid(sys.argv[1])
    with open(sys.argv[2], newline="") as f:
        rows = list(csv.DictReader(f))
    tolerance = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-12
    b = grid.GetBounds()
    size = math.sqrt(sum((b[2 * k + 1] - b[2 * k]) ** 2 for k in range(3)))
    components = [c for c in rows[0].keys() if ":" in c]
    fields = sorted({c.split(":")[0] for c in components})
    scale = {name: max(max(abs(float(r[c])) for r in rows) for c in components if c.split(":")[0] == name)
             for name in fields}
    arrays = {name: grid.GetPointData().GetArray(name) for name in fields}
    missing = [name for name, array in arrays.items() if array is None]
    if missing:
        print("fields missing from the mesh:", missing)
        sys.exit(2)

    worst = {"position": 0.0, **{name: 0.0 for name in fields}}
    for row in rows:
        cell = grid.GetCell(int(row["cell"]))
        if cell.GetCellType() not in (vtk.VTK_BEZIER_CURVE, vtk.VTK_BEZIER_QUADRILATERAL):
            print("cell", row["cell"], "is not a Bezier cell but type", cell.GetCellType())
            sys.exit(2)
        n = cell.GetNumberOfPoints()
        x, weights = [0.0, 0.0, 0.0], [0.0] * n
        cell.EvaluateLocation(vtk.reference(0), [float(row["r"]), float(row["s"]), 0.0], x, weights)
        expected = [float(row[c]) for c in "xyz"]
        worst["position"] = max(worst["position"], max(abs(x[k] - expected[k]) for k in range(3)) / size)
        for column in components:
            name, k = column.split(":")
            value = sum(weights[a] * arrays[name].GetComponent(cell.GetPointId(a), int(k)) for a in range(n))
            worst[name] = max(worst[name], abs(value - float(row[column])) / scale[name])

    print(" ".join("%s %.3g" % item for item in worst.items()))
    sys.exit(0 if all(error <= tolerance for error in worst.values()) else 1)


if __name__ == "__main__":
    main()
