# bench/pictures3d.py -- one frame of a 3-D run seen from above at an angle
# (pvbatch3.11 --force-offscreen-rendering pictures3d.py RUN_DIR FIELD LABEL OUT.png TITLE):
# the last frame of RUN_DIR/points.pvd, opened by ParaView's own readers,
# the points as small discs coloured by FIELD (a scalar), the data's axes.
import os, sys
import xml.etree.ElementTree as ET
from paraview.simple import (PVDReader, Show, Text, GetActiveViewOrCreate, GetColorTransferFunction,
                             GetScalarBar, ColorBy, SaveScreenshot, UpdatePipeline)
from paraview import servermanager

run, field, label, out, title = sys.argv[1:6]
frames = [float(d.get("timestep")) for d in ET.parse(os.path.join(run, "points.pvd")).getroot().iter("DataSet")]
if not frames:
    sys.exit(f"pictures3d.py: {run}: the series lists no frame")
t = frames[-1]
src = PVDReader(FileName=os.path.join(run, "points.pvd"))
UpdatePipeline(time=t, proxy=src)
view = GetActiveViewOrCreate("RenderView")
view.ViewTime = t
data = servermanager.Fetch(src)
if data.GetPointData().GetArray(field) is None:
    sys.exit(f"pictures3d.py: {run}: no point array {field}")
lo, hi = data.GetPointData().GetArray(field).GetRange()
b, n = data.GetBounds(), data.GetNumberOfPoints()
view.ViewSize = [1200, 800]
view.OrientationAxesVisibility = 1
view.Background = [1, 1, 1]
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass
disp = Show(src, view)
disp.SetScalarBarVisibility(view, False)
disp.SetRepresentationType("Point Gaussian")
disp.GaussianRadius = 0.35 * ((b[1] - b[0]) * (b[3] - b[2]) * (b[5] - b[4]) / max(n, 1)) ** (1.0 / 3.0)
disp.ShaderPreset = "Plain circle"
ColorBy(disp, ("POINTS", field))
lut = GetColorTransferFunction(field)
if not lut.ApplyPreset("Turbo", True):
    lut.ApplyPreset("Jet", True)
lut.RescaleTransferFunction(lo, hi)
lut.AutomaticRescaleRangeMode = "Never"
disp.LookupTable = lut
bar = GetScalarBar(lut, view)
bar.Title, bar.ComponentTitle = label, ""
bar.TitleColor = bar.LabelColor = [0, 0, 0]
bar.RangeLabelFormat = "%-#.3g"
bar.Visibility = 1
grid = disp.DataAxesGrid
grid.GridAxesVisibility = 1
grid.XTitle, grid.YTitle, grid.ZTitle = "x [m]", "y [m]", "z [m]"
grid.XTitleColor = grid.YTitleColor = grid.ZTitleColor = [0, 0, 0]
grid.XLabelColor = grid.YLabelColor = grid.ZLabelColor = grid.GridColor = [0, 0, 0]
txt = Text(Text=f"{title}\nt = {t:.4g} s, {n} points")
tdisp = Show(txt, view)
tdisp.Color = [0, 0, 0]
tdisp.FontSize = 16
tdisp.WindowLocation = "Upper Center"
cx, cy, cz = (b[0] + b[1]) / 2, (b[2] + b[3]) / 2, (b[4] + b[5]) / 2
r = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
view.CameraFocalPoint = [cx, cy, cz]
view.CameraPosition = [cx + 1.6 * r, cy + 1.3 * r, cz + 2.2 * r]
view.CameraViewUp = [0, 1, 0]
view.CameraParallelProjection = 0
SaveScreenshot(out, view, ImageResolution=[1200, 800])
print(f"pictures3d.py: {out}: t = {t}, {n} points, {field} in [{lo:.3g}, {hi:.3g}]")
