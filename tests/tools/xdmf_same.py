#!/usr/bin/python3
"""xdmf_same.py RUN_DIR... -- the HDF5 output of each run (written with
output.format ["vtk", "xdmf"]), read with h5py as a user's script would,
holds the same numbers as its legacy .vtk frames and, when the run wrote
them too (format vtu), its .vtu frames, to the bit: for every frame of
points.vtk.series and mesh.vtk.series (and points.pvd, mesh.pvd), the group /KIND/NNNNNN of
results.h5 has the series' time as its attribute time, its geometry is the
frame's points, its datasets are the frame's point-data arrays (names,
order, components, values) and the mesh's topology (XDMF's mixed list)
decodes to the frame's cell types and connectivity. The indices
points.xdmf and mesh.xdmf list the same frames with the same times (as
written, %.17g: the same doubles), and every DataItem names a dataset of
results.h5 of the dimensions it states. The frames are read with VTK's
own readers (legacy and XML), as ParaView reads them.
Prints PASS/FAIL lines and "N passed, M failed"; exit 1 on a failure."""
import json
import os
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np
from vtkmodules.vtkIOLegacy import vtkUnstructuredGridReader
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_check import check, done  # noqa: E402 (the PASS/FAIL lines and their count)

VTK_TO_XDMF = {5: 4, 9: 5}  # triangle, quadrilateral


def read_vtk(path):
    if path.endswith(".vtu"):
        r = vtkXMLUnstructuredGridReader()
    else:
        r = vtkUnstructuredGridReader()
        r.ReadAllScalarsOn()
        r.ReadAllVectorsOn()
        r.ReadAllTensorsOn()
    r.SetFileName(path)
    r.Update()
    return r.GetOutput()


def pvd_entries(path):
    """A .pvd's frames as the .vtk.series' entries: file name and time."""
    return [{"name": d.get("file"), "time": float(d.get("timestep"))}
            for d in ET.parse(path).getroot().iter("DataSet")]


def same_bits(a, b):
    """Equal arrays, bit for bit (NaN payloads and -0.0 included)."""
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def mixed(types, conn, offsets):
    """VTK cells as XDMF's mixed list."""
    out = []
    for c, t in enumerate(types):
        out.append(VTK_TO_XDMF.get(int(t), -1))
        out.extend(conn[offsets[c]:offsets[c + 1]])
    return np.array(out, dtype=np.int64)


def compare_frame(run, h5, kind, i, entry):
    """Frame i of kind in results.h5 against the legacy file of entry."""
    name = "/%s/%06d" % (kind, i)
    what = "%s: %s (%s)" % (run, name, entry["name"])
    if not check(name in h5, "%s: in results.h5" % what):
        return
    g = h5[name]
    d = read_vtk(os.path.join(run, entry["name"]))
    check(g.attrs["time"] == entry["time"], "%s: time %r = the series' %r" % (what, g.attrs["time"], entry["time"]))
    pd = d.GetPointData()
    vtk_names = [pd.GetArrayName(k) for k in range(pd.GetNumberOfArrays())]
    h5_names = [n for n in g.keys() if n not in ("geometry", "topology")]
    # the groups track their links' creation order, which h5py follows
    check(h5_names == vtk_names, "%s: arrays %s = the VTK frame's %s" % (what, h5_names, vtk_names))
    bad = [n for n in vtk_names if n in g and not same_bits(g[n][()], vtk_to_numpy(pd.GetArray(n)))]
    pts = vtk_to_numpy(d.GetPoints().GetData())
    check(not bad and same_bits(g["geometry"][()], pts),
          "%s: geometry (%d points) and %d arrays equal the VTK frame's to the bit%s"
          % (what, len(pts), len(vtk_names), "; not %s" % bad if bad else ""))
    if kind == "mesh":
        types = np.array([d.GetCellType(c) for c in range(d.GetNumberOfCells())])
        cells = d.GetCells()
        want = mixed(types, vtk_to_numpy(cells.GetConnectivityArray()), vtk_to_numpy(cells.GetOffsetsArray()))
        got = g["topology"][()]
        check(got.dtype == np.int32 and np.array_equal(got.astype(np.int64), want) and g.attrs["cells"] == len(types),
              "%s: topology = the VTK frame's %d cells" % (what, len(types)))
    return vtk_names


def check_index(run, h5, kind, entries):
    """kind.xdmf: the frames, their times, DataItems that exist."""
    path = os.path.join(run, kind + ".xdmf")
    if not check(os.path.exists(path), "%s: %s.xdmf written" % (run, kind)):
        return
    root = ET.parse(path).getroot()
    grids = root.findall("./Domain/Grid/Grid")
    times = [float(g.find("Time").get("Value")) for g in grids]
    check(times == [e["time"] for e in entries],
          "%s: %s.xdmf lists %d frames at the series' times" % (run, kind, len(grids)))
    bad = []
    for item in root.iter("DataItem"):
        f, ds = item.text.strip().split(":", 1)
        dims = tuple(int(v) for v in item.get("Dimensions").split())
        if f != "results.h5" or ds not in h5 or h5[ds].shape != dims:
            bad.append(item.text.strip())
    check(not bad, "%s: every DataItem of %s.xdmf names a dataset of its dimensions%s"
          % (run, kind, "; not %s" % bad[:3] if bad else ""))


def compare(run):
    h5path = os.path.join(run, "results.h5")
    if not check(os.path.exists(h5path), "%s: results.h5 written" % run):
        return
    with h5py.File(h5path, "r") as h5:
        for kind in ("points", "mesh"):
            series = os.path.join(run, kind + ".vtk.series")
            if not os.path.exists(series):
                check(kind == "mesh" and kind not in h5, "%s: no %s series, none in results.h5" % (run, kind))
                continue
            entries = json.load(open(series))["files"]
            check(len(entries) > 0 and len(h5[kind]) == len(entries),
                  "%s: results.h5 holds %d frames of %s, the series %d" % (run, len(h5[kind]), kind, len(entries)))
            for i, e in enumerate(entries):
                compare_frame(run, h5, kind, i, e)
            check_index(run, h5, kind, entries)
            pvd = os.path.join(run, kind + ".pvd")
            if os.path.exists(pvd):
                xml = pvd_entries(pvd)
                check([e["time"] for e in xml] == [e["time"] for e in entries],
                      "%s: %s.pvd lists the series' %d times" % (run, kind, len(entries)))
                for i, e in enumerate(xml):
                    compare_frame(run, h5, kind, i, e)


for r in sys.argv[1:]:
    compare(r)
done()
