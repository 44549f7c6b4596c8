"""Reads every .pvd of a fibrane output directory with VTK's own readers and prints one line per dataset:
<pvd> <vtu> <points> <cells> <arrays...>. Exit code 1 if anything cannot be read or is empty."""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import vtk

out = Path(sys.argv[1])
pvds = sorted(out.glob("*.pvd"))
if not pvds:
    print("no .pvd files in", out)
    sys.exit(1)
for pvd in pvds:
    datasets = ET.parse(pvd).getroot().findall("./Collection/DataSet")
    if not datasets:
        print("empty collection", pvd)
        sys.exit(1)
    for ds in datasets:
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(str(out / ds.get("file")))
        reader.Update()
        grid = reader.GetOutput()
        if grid.GetNumberOfPoints() == 0 or grid.GetNumberOfCells() == 0:
            print("empty dataset", ds.get("file"))
            sys.exit(1)
        pd = grid.GetPointData()
        names = [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]
        print(pvd.name, ds.get("file"), ds.get("timestep"), grid.GetNumberOfPoints(), grid.GetNumberOfCells(),
              " ".join(names))
