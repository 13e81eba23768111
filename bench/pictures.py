# bench/pictures.py -- draws one frame of a run with ParaView (run by
# bench/pictures under `pvbatch3.11 --force-offscreen-rendering`).
# usage: pictures.py RUN_DIR TIME|last FIELD COMPONENT LABEL LO:HI|auto OUT.png TITLE
#   COMPONENT -1 colours by the vector's magnitude, k >= 0 by its k-th component.
# The frame is opened by ParaView's own readers, chosen by file name, so the
# script works with either output format mpgm writes: a series of VTK XML
# frames (.vtu) is opened as points.pvd and moved to the wanted time; a
# series of legacy .vtk frames (which ParaView's PVD reader cannot open)
# is looked up in points.pvd or points.vtk.series and the one frame at that
# time is opened with the legacy reader.
import json, os, sys
import xml.etree.ElementTree as ET
from paraview.simple import (LegacyVTKReader, PVDReader, XMLUnstructuredGridReader, Show, Text,
                             GetActiveViewOrCreate, GetColorTransferFunction, GetScalarBar, ColorBy,
                             SaveScreenshot, UpdatePipeline)
from paraview import servermanager
from vtk.util.numpy_support import vtk_to_numpy
import numpy as np

run, want, field, comp, label, rng, out, title = sys.argv[1:9]
comp = int(comp)

def series(run):
    """[(time, file)] of the run's point frames, from whichever index it wrote."""
    pvd = os.path.join(run, "points.pvd")
    if os.path.exists(pvd):
        return [(float(d.get("timestep")), os.path.join(run, d.get("file")))
                for d in ET.parse(pvd).getroot().iter("DataSet")]
    js = os.path.join(run, "points.vtk.series")
    if os.path.exists(js):
        return [(float(f["time"]), os.path.join(run, f["name"])) for f in json.load(open(js))["files"]]
    sys.exit(f"pictures.py: {run}: neither points.pvd nor points.vtk.series")

frames = series(run)
if not frames:
    sys.exit(f"pictures.py: {run}: the series lists no frame")
if want == "last":
    t, path = frames[-1]
else:
    t, path = min(frames, key=lambda f: abs(f[0] - float(want)))
    if abs(t - float(want)) > 1e-6 * max(1.0, abs(float(want))):
        sys.exit(f"pictures.py: {run}: no frame at t = {want} (nearest {t})")
if path.endswith(".vtu"):
    src = PVDReader(FileName=os.path.join(run, "points.pvd"))
    UpdatePipeline(time=t, proxy=src)
    if not src.TimestepValues:   # a .pvd ParaView cannot read as a series: the frame itself
        src = XMLUnstructuredGridReader(FileName=[path])
else:
    src = LegacyVTKReader(FileNames=[path])
view = GetActiveViewOrCreate("RenderView")
view.ViewTime = t
src.UpdatePipeline(t)

data = servermanager.Fetch(src)
arr = data.GetPointData().GetArray(field)
if arr is None:
    sys.exit(f"pictures.py: {path}: no point array {field}")
vals = vtk_to_numpy(arr)
vals = np.linalg.norm(vals, axis=1) if vals.ndim > 1 and comp < 0 else (vals[:, comp] if vals.ndim > 1 else vals)
if rng == "auto":
    lo, hi = (float(v) for v in np.percentile(vals, [1, 99]))
    label += "  (1st-99th percentile)"
else:
    lo, hi = (float(v) for v in rng.split(":"))
if hi <= lo:
    hi = lo + (abs(lo) if lo else 1.0) * 1e-6
b = data.GetBounds()
n = data.GetNumberOfPoints()
# a point's share of the area it fills: the Gaussians just touch
radius = 0.75 * ((b[1] - b[0]) * max(b[3] - b[2], 1e-12 * (b[1] - b[0])) / max(n, 1)) ** 0.5

view.ViewSize = [1200, 700]
view.OrientationAxesVisibility = 0
view.Background = [1, 1, 1]
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
disp = Show(src, view)
disp.SetScalarBarVisibility(view, False)   # only the bar set up below
disp.SetRepresentationType("Point Gaussian")
disp.GaussianRadius = radius
disp.ShaderPreset = "Plain circle"
ColorBy(disp, ("POINTS", field))
lut = GetColorTransferFunction(field)
if arr.GetNumberOfComponents() > 1:
    lut.VectorMode = "Magnitude" if comp < 0 else "Component"
    lut.VectorComponent = max(comp, 0)
disp.LookupTable = lut
if not lut.ApplyPreset("Turbo", True):
    lut.ApplyPreset("Jet", True)
lut.RescaleTransferFunction(lo, hi)
lut.AutomaticRescaleRangeMode = "Never"
bar = GetScalarBar(lut, view)
bar.Title = label
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0, 0, 0]
bar.TitleFontSize = 16
bar.LabelFontSize = 14
bar.RangeLabelFormat = "%-#.3g"
bar.WindowLocation = "Any Location"
bar.Orientation = "Horizontal"
bar.Position = [0.3, 0.05]
bar.ScalarBarLength = 0.4
bar.Visibility = 1
grid = disp.DataAxesGrid
grid.GridAxesVisibility = 1
grid.XTitle, grid.YTitle = "x [m]", "y [m]"
grid.ShowEdges = 0
grid.AxesToLabel = 3          # the x and y axes only
grid.XTitleColor = grid.YTitleColor = grid.XLabelColor = grid.YLabelColor = grid.GridColor = [0, 0, 0]
grid.XTitleFontSize = grid.YTitleFontSize = 16
grid.XLabelFontSize = grid.YLabelFontSize = 14
txt = Text(Text=f"{title}\nt = {t:.4g} s, {n} points")
tdisp = Show(txt, view)
tdisp.Color = [0, 0, 0]
tdisp.FontSize = 16
tdisp.WindowLocation = "Upper Center"
view.InteractionMode = "2D"
# the frame's bounds fill the middle of the picture (ResetCamera would also
# fit the axes' labels and the text)
cx, cy = (b[0] + b[1]) / 2, (b[2] + b[3]) / 2
view.CameraPosition = [cx, cy, 10 * max(b[1] - b[0], b[3] - b[2], 1e-9)]
view.CameraFocalPoint = [cx, cy, 0]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelProjection = 1
aspect = view.ViewSize[0] / view.ViewSize[1]
scale = 0.5 * max(b[3] - b[2], (b[1] - b[0]) / aspect) * 1.7   # room for the title and the bar
view.CameraParallelScale = scale
view.CameraPosition = [cx, cy - 0.12 * scale, 10 * max(b[1] - b[0], b[3] - b[2], 1e-9)]
view.CameraFocalPoint = [cx, cy - 0.12 * scale, 0]
SaveScreenshot(out, view, ImageResolution=[1200, 700], TransparentBackground=0)
print(f"pictures.py: {out}: {path} at t = {t}, {field} in [{lo:g}, {hi:g}], {n} points")
