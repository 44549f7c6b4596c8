"""Reads one .pvd series as ParaView plays it (its data sets sorted by timestep) with VTK's own reader and
prints one line per data set: <timestep> <step> <t> from the FieldData arrays `step` and `t` of each .vtu.
Exit code 1 if a file cannot be read or lacks those arrays."""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import vtk

pvd = Path(sys.argv[1])
datasets = ET.parse(pvd).getroot().findall("./Collection/DataSet")
if not datasets:
    print("empty collection", pvd)
    sys.exit(1)
for ds in sorted(datasets, key=lambda d: float(d.get("timestep"))):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(pvd.parent / ds.get("file")))
    reader.Update()
    fields = reader.GetOutput().GetFieldData()
    step, t = fields.GetArray("step"), fields.GetArray("t")
    if step is None or t is None:
        print("no step or t field data in", ds.get("file"))
        sys.exit(1)
    print(ds.get("timestep"), int(step.GetValue(0)), repr(t.GetValue(0)))
