#!/usr/bin/python3
"""vtu_same.py RUN_DIR... -- the .vtu frames of each run (written with
output.format ["vtu", "vtk"]) hold the same numbers as its legacy .vtk
frames, to the bit: points, every point-data array (names, order,
components, values), cell types and connectivity, and the TimeValue equals
the time the .vtk.series lists. The golden records hash the legacy files
(tests/golden/runs.txt), so this is what makes them guard the default
format too. Both files are read with VTK's own readers (python3-vtk9).
Prints PASS/FAIL lines and "N passed, M failed"; exit 1 on a failure."""
import glob
import json
import os
import sys

import numpy as np
from vtkmodules.vtkIOLegacy import vtkUnstructuredGridReader
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_check import check, done  # noqa: E402 (the PASS/FAIL lines and their count)


def read(path):
    r = vtkXMLUnstructuredGridReader() if path.endswith(".vtu") else vtkUnstructuredGridReader()
    r.SetFileName(path)
    if not path.endswith(".vtu"):
        r.ReadAllScalarsOn()
        r.ReadAllVectorsOn()
        r.ReadAllTensorsOn()
    r.Update()
    return r.GetOutput()


def same_bits(a, b):
    """Equal arrays, bit for bit (NaN payloads and -0.0 included)."""
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def cells(g):
    """(types, connectivity) of a grid as arrays."""
    types = np.array([g.GetCellType(c) for c in range(g.GetNumberOfCells())])
    conn = vtk_to_numpy(g.GetCells().GetConnectivityArray()).astype(np.int64)
    return types, conn


def compare(run):
    times = {}
    for kind in ("points", "mesh"):
        path = os.path.join(run, kind + ".vtk.series")
        if os.path.exists(path):
            for e in json.load(open(path))["files"]:
                times[os.path.basename(e["name"])] = e["time"]
    vtus = sorted(glob.glob(os.path.join(run, "vtk", "*.vtu")))
    check(vtus and len(vtus) == len(glob.glob(os.path.join(run, "vtk", "*.vtk"))),
          "%s: %d .vtu frames, as many as .vtk" % (run, len(vtus)))
    for f in vtus:
        u, g = read(f), read(f[:-1] + "k")
        name = os.path.relpath(f, run)
        pu, pg = u.GetPointData(), g.GetPointData()
        nu = [pu.GetArrayName(i) for i in range(pu.GetNumberOfArrays())]
        ng = [pg.GetArrayName(i) for i in range(pg.GetNumberOfArrays())]
        ok = nu == ng and u.GetNumberOfPoints() == g.GetNumberOfPoints()
        ok = ok and same_bits(vtk_to_numpy(u.GetPoints().GetData()), vtk_to_numpy(g.GetPoints().GetData()))
        diff = [n for n in nu if n in ng and not same_bits(vtk_to_numpy(pu.GetArray(n)), vtk_to_numpy(pg.GetArray(n)))]
        tu, cu = cells(u)
        tg, cg = cells(g)
        tv = u.GetFieldData().GetArray("TimeValue")
        t = tv.GetValue(0) if tv is not None and tv.GetNumberOfTuples() == 1 else None
        want = times.get(os.path.basename(f)[:-1] + "k")
        check(ok and not diff and np.array_equal(tu, tg) and np.array_equal(cu, cg) and t == want,
              "%s: points, cells and arrays %s equal the .vtk's to the bit; TimeValue %r (series %r)%s"
              % (name, nu, t, want, "; differ: %s" % diff if diff else ""))


for run in sys.argv[1:]:
    compare(run)
done()
