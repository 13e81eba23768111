"""pv_check.py RUN_DIR... -- open every series of mpgm runs with ParaView's
own readers, as a user does (File > Open points.pvd), under
`pvbatch3.11 --force-offscreen-rendering` (tests/scripts/paraview.sh).

For each run (written with output.every 1, so that every row of probes.csv
is a frame): every collection present (points.pvd, mesh.pvd,
points.vtk.series, mesh.vtk.series, and grid.pvd, grid.vtk.series of
output.grid, checked by check_grid; check_series takes any file name
ParaView opens, so an XDMF series, points.xdmf, is checked by the same
function once it is written) must open, its TimestepValues must equal the
time column of probes.csv, and at every time the frame must load with the
point count of summary.json and the same arrays as the first frame
(displacement and velocity among the points' arrays). At one time (the
last) the points' data are compared with the CSV records:
  - the probe: the runs put it exactly on a material point's initial
    position (checked: within 1e-12 m at t = 0), followed to the last
    time by its id where the frames have one (a run on many processes
    changes the points' order between frames). A probe and a material
    point at the same place take the same shape functions of the same
    nodes, so their displacements agree to rounding; 1e-9 of |u| (plus
    1e-15 m) is far above rounding and far below the difference to the
    next point (of the order of the strain times h, 1e-4 of |u| here);
  - the kinetic energy, sum m |v|^2 / 2 over the points' mass and velocity
    arrays, against steps.csv's kinetic_energy at that step: the same
    numbers summed in another order, so 1e-10 relative.
Prints PASS/FAIL lines and "N passed, M failed"; exit 1 on a failure."""
import csv
import json
import math
import os
import sys

from paraview import servermanager as sm
from paraview.simple import OpenDataFile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from script_check import check, done  # noqa: E402 (the PASS/FAIL lines and their count)


def frame(reader, t):
    reader.UpdatePipeline(t)
    return sm.Fetch(reader)


def arrays(d):
    pd = d.GetPointData()
    return [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())]


def check_series(path, times, npoints, need):
    """Open path with ParaView, check its times, and every frame's point
    count and arrays. Returns (reader, last frame) or (None, None)."""
    name = os.path.relpath(path)
    reader = OpenDataFile(path)
    if not check(reader is not None, "%s: ParaView opens it" % name):
        return None, None
    tv = list(reader.TimestepValues)
    check(len(tv) == len(times) and all(abs(a - b) <= 1e-12 * max(1.0, abs(b)) for a, b in zip(tv, times)),
          "%s (%s): %d TimestepValues equal probes.csv's %d times" % (name, reader.GetXMLName(), len(tv), len(times)))
    first, bad, d = None, [], None
    for t in tv:
        d = frame(reader, t)
        a = arrays(d)
        first = first if first is not None else a
        npoints = d.GetNumberOfPoints() if npoints is None else npoints
        if d.GetNumberOfPoints() != npoints or a != first:
            bad.append(t)
    check(not bad and all(n in first for n in need),
          "%s: every time loads %d points with arrays %s%s" % (name, npoints, first, "; not at %s" % bad[:3] if bad else ""))
    return reader, d


def numbers(row):
    return {k: float(v) for k, v in row.items()}


def check_values(run, reader, last, probes, steps):
    """The points at the last time against probes.csv and steps.csv."""
    d0 = frame(reader, reader.TimestepValues[0])
    scene = json.load(open(os.path.join(run, "summary.json")))["scene"]
    x0, dim = scene["probes"], len(scene["mesh"]["domain"]["min"])  # 2, or 3 in a 3-D run
    row = probes[-1]
    disp = last.GetPointData().GetArray("displacement")
    vec = lambda a: "(" + ", ".join("%.10g" % x for x in a) + ")"
    for pname, pos in x0.items():
        best = min(range(d0.GetNumberOfPoints()), key=lambda i: math.dist(d0.GetPoint(i)[:dim], pos))
        dist = math.dist(d0.GetPoint(best)[:dim], pos)
        at = best
        ids0, ids = d0.GetPointData().GetArray("id"), last.GetPointData().GetArray("id")
        if ids0 is not None and ids is not None:  # the same material point by its id (order may change)
            pid = ids0.GetValue(best)
            at = next((i for i in range(last.GetNumberOfPoints()) if ids.GetValue(i) == pid), best)
        u = disp.GetTuple3(at)[:dim]
        want = [row[pname + "_u" + c] for c in "xyz"[:dim]]
        err = math.dist(u, want)
        check(dist <= 1e-12 and err <= 1e-9 * math.hypot(*want) + 1e-15,
              "%s: probe %s on point %d (%.1e m away at t = 0): displacement at t = %.6g %s "
              "= probes.csv %s, |diff| %.2e" % (run, pname, best, dist, row["time"], vec(u), vec(want), err))
    if "kinetic_energy" in steps[-1]:
        m, v = last.GetPointData().GetArray("mass"), last.GetPointData().GetArray("velocity")
        ke = sum(0.5 * m.GetValue(i) * sum(v.GetComponent(i, c) ** 2 for c in range(dim))
                 for i in range(last.GetNumberOfPoints()))
        want = steps[-1]["kinetic_energy"]
        check(abs(ke - want) <= 1e-10 * abs(want), "%s: kinetic energy of the points' mass and velocity "
              "%.12g J = steps.csv's %.12g J" % (run, ke, want))


def total(d, name):
    a = d.GetPointData().GetArray(name)
    return sum(a.GetValue(i) for i in range(d.GetNumberOfPoints()))


def check_grid(run, path, points):
    """output.grid: the background grid's series opens at the same times,
    the nodes of the last step are marked active, and their mass is the
    points' mass (the shape functions are a partition of unity, so
    sum_I m_I = sum_I sum_p N_Ip m_p = sum_p m_p, to rounding; 1e-12)."""
    times = list(points.TimestepValues)
    reader, last = check_series(path, times, None, ["active", "mass", "velocity", "displacement_increment"])
    if reader is None:
        return
    pts = frame(points, times[-1])
    mg, mp, act = total(last, "mass"), total(pts, "mass"), total(last, "active")
    check(abs(mg - mp) <= 1e-12 * mp and act > 0,
          "%s: the grid's mass at t = %g, %.15g kg, is the points' %.15g kg (%d active nodes)"
          % (os.path.relpath(path), times[-1], mg, mp, act))
    d0 = frame(reader, times[0])
    check(total(d0, "active") == 0 and total(d0, "mass") == 0,
          "%s: no node is active before the first step" % os.path.relpath(path))


def check_run(run):
    summary = json.load(open(os.path.join(run, "summary.json")))
    probes = [numbers(r) for r in csv.DictReader(open(os.path.join(run, "probes.csv")))]
    steps = [numbers(r) for r in csv.DictReader(open(os.path.join(run, "steps.csv")))]
    times = [r["time"] for r in probes]
    c = summary["counts"]
    found = 0
    for series in ("points.pvd", "mesh.pvd", "points.vtk.series", "mesh.vtk.series", "points.xdmf", "mesh.xdmf"):
        path = os.path.join(run, series)
        if not os.path.exists(path):
            continue
        found += 1
        pts = series.startswith("points")
        reader, last = check_series(path, times, c["points"] if pts else c["nodes"],
                                    ["displacement", "velocity"] if pts else ["displacement"])
        if reader is not None and pts:
            check_values(run, reader, last, probes, steps)
            grid = os.path.join(run, "grid" + series[len("points"):])
            if os.path.exists(grid):
                found += 1
                check_grid(run, grid, reader)
    check(found >= 1 + (c.get("cells", 0) > 0), "%s: %d series found" % (run, found))


for r in sys.argv[1:]:
    check_run(r)
done()
