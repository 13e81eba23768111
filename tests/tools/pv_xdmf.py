"""pv_xdmf.py RUN_DIR... -- ParaView's own XDMF reader opens the XDMF
index of mpgm runs written with output.format ["vtk", "xdmf"], under
`pvbatch3.11 --force-offscreen-rendering` (tests/scripts/xdmf.sh): for
points.xdmf and mesh.xdmf (when written) the reader's TimestepValues are
the times of the legacy series (.vtk.series) exactly, and at the last
time the grid ParaView gives has the legacy frame's points and arrays
(names, and values to the bit; the legacy frame read by ParaView's legacy
reader). Prints PASS/FAIL lines and "N passed, M failed"; exit 1 on a
failure."""
import json
import os
import sys

from paraview import servermanager as sm
from paraview.simple import LegacyVTKReader, OpenDataFile
from paraview.vtk.util.numpy_support import vtk_to_numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_check import check, done  # noqa: E402 (the PASS/FAIL lines and their count)


def arrays(d):
    pd = d.GetPointData()
    return {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


def check_index(run, kind):
    path = os.path.join(run, kind + ".xdmf")
    series = os.path.join(run, kind + ".vtk.series")
    if not os.path.exists(series):
        return
    entries = json.load(open(series))["files"]
    reader = OpenDataFile(path)
    if not check(reader is not None, "%s: ParaView opens it" % path):
        return
    tv = list(reader.TimestepValues)
    check(tv == [e["time"] for e in entries], "%s (%s): TimestepValues %s are the series' %d times"
          % (path, reader.GetXMLName(), tv[:4] + ["..."] if len(tv) > 4 else tv, len(entries)))
    reader.UpdatePipeline(tv[-1])
    got = sm.Fetch(reader)
    legacy = LegacyVTKReader(FileNames=[os.path.join(run, entries[-1]["name"])])
    want = sm.Fetch(legacy)
    ga, wa = arrays(got), arrays(want)
    same = (got.GetNumberOfPoints() == want.GetNumberOfPoints() and got.GetNumberOfCells() == want.GetNumberOfCells()
            and sorted(ga) == sorted(wa) and all(ga[n].tobytes() == wa[n].tobytes() for n in wa)
            and vtk_to_numpy(got.GetPoints().GetData()).tobytes() == vtk_to_numpy(want.GetPoints().GetData()).tobytes())
    check(same, "%s at t = %r: %d points, %d cells, arrays %s as the legacy frame, to the bit"
          % (path, tv[-1], got.GetNumberOfPoints(), got.GetNumberOfCells(), sorted(ga)))


for r in sys.argv[1:]:
    for k in ("points", "mesh"):
        check_index(r, k)
done()
