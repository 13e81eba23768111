#!/usr/bin/python3
"""check_vtk.py RUN_DIR -- read an mpgm run's VTK output the way ParaView
does (vtkXMLUnstructuredGridReader for .vtu frames, vtkUnstructuredGridReader
for legacy .vtk frames) and check it against RUN_DIR/summary.json.

Run with Debian's /usr/bin/python3 (python3-vtk9 is installed for it only).

Run layout (the contract with the mpgm program):
  RUN_DIR/summary.json   counts.points, counts.nodes, counts.cells, probes
  RUN_DIR/probes.csv     step,time,<name>_ux,<name>_uy,...
  RUN_DIR/points.pvd, RUN_DIR/mesh.pvd           (.vtu frames)
  RUN_DIR/points.vtk.series, mesh.vtk.series     (legacy .vtk frames, JSON)
  RUN_DIR/vtk/points_NNNNNN.EXT  vectors displacement, velocity (3 comp.);
                                 tensor stress (9); mass, volume, J, id
  RUN_DIR/vtk/mesh_NNNNNN.EXT    displacement
Every format present in vtk/ is checked.

Prints one line per check (PASS / FAIL / SKIP / NOTE) and finishes with
"N passed, M failed". Exit status: 0 all passed, 1 a check failed,
2 vtk cannot be imported or bad usage.
"""
import csv
import glob
import json
import math
import os
import re
import sys
import xml.etree.ElementTree as ET

VTK_VERTEX = 1
POINT_ARRAYS = {"displacement": 3, "velocity": 3, "stress": 9,
                "mass": 1, "volume": 1, "J": 1, "id": 1}
MESH_ARRAYS = {"displacement": 3}
PROBE_DIST_TOL = 1e-9   # node must lie this close to the probe (x max(1,|x|))
PROBE_REL_TOL = 1e-9    # relative to the norm of the probe's displacement


class Checker:
    """Counts and prints checks."""

    def __init__(self):
        self.passed = 0
        self.failed = 0

    def check(self, ok, msg):
        if ok:
            self.passed += 1
        else:
            self.failed += 1
        print(("PASS: " if ok else "FAIL: ") + msg)
        return ok

    @staticmethod
    def skip(msg):
        print("SKIP: " + msg)

    @staticmethod
    def note(msg):
        print("NOTE: " + msg)


def import_vtk():
    """Import the legacy reader and VTK's output windows; None if
    python3-vtk9 is missing."""
    try:
        from vtkmodules.vtkIOLegacy import vtkUnstructuredGridReader
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
        from vtkmodules.vtkCommonCore import (vtkLogger, vtkOutputWindow,
                                              vtkStringOutputWindow)
    except ImportError:
        return None
    vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)  # we print them
    return (vtkUnstructuredGridReader, vtkOutputWindow, vtkStringOutputWindow,
            vtkXMLUnstructuredGridReader)


def read_grid(vtk_mods, path):
    """Read a .vtu or legacy file as ParaView does; returns (grid or None,
    list of VTK error and warning texts). Any error or warning fails the
    read."""
    reader_cls, output_window, string_window, xml_cls = vtk_mods
    window = string_window()  # catches warnings of free functions too
    output_window.SetInstance(window)
    xml = path.endswith(".vtu")
    reader = xml_cls() if xml else reader_cls()
    reader.SetFileName(path)
    if not xml:
        reader.ReadAllScalarsOn()
        reader.ReadAllVectorsOn()
        reader.ReadAllTensorsOn()
    reader.Update()
    errors = [" ".join(line.split())[-200:]
              for line in window.GetOutput().splitlines() if line.strip()]
    if xml and not errors and reader.GetOutput().GetFieldData().GetArray("TimeValue") is None:
        errors.append("no TimeValue field data")
    if not xml and not errors and not reader.IsFileUnstructuredGrid():
        errors.append("not a legacy unstructured grid")
    return (reader.GetOutput() if not errors else None), errors


def file_number(name):
    """NNNNNN of points_NNNNNN.vtk / mesh_NNNNNN.vtk (for ordering)."""
    m = re.search(r"_(\d+)\.vt[ku]$", name)
    return int(m.group(1)) if m else -1


def check_arrays(ck, grid, name, expected):
    """Every point-data array free of NaN/Inf; the expected arrays present
    with their number of components."""
    pd = grid.GetPointData()
    found, bad = {}, []
    for i in range(pd.GetNumberOfArrays()):
        arr = pd.GetArray(i)
        if arr is None:
            continue
        nc = arr.GetNumberOfComponents()
        found[arr.GetName()] = nc
        nbad = sum(1 for t in range(arr.GetNumberOfTuples())
                   for c in range(nc) if not math.isfinite(arr.GetComponent(t, c)))
        if nbad:
            bad.append("%s: %d values" % (arr.GetName(), nbad))
    ck.check(not bad, "%s: no NaN/Inf in %d point-data arrays%s" % (
        name, len(found), " (" + "; ".join(bad) + ")" if bad else ""))
    if expected:
        wrong = ["%s (%s components, want %d)" % (a, found.get(a, "missing"), n)
                 for a, n in expected.items() if found.get(a) != n]
        ck.check(not wrong, "%s: arrays %s%s" % (
            name, ", ".join(expected), "; wrong: " + ", ".join(wrong) if wrong else ""))


def check_files(ck, vtk_mods, run, summary, kind_files, ext):
    """Open every vtk/*EXT and compare sizes with summary counts."""
    counts = summary.get("counts", {})
    grids = {}
    for path in sorted(glob.glob(os.path.join(run, "vtk", "*" + ext))):
        name = os.path.relpath(path, run)
        base = os.path.basename(path)
        kind = base.split("_")[0] if base.startswith(("points_", "mesh_")) else None
        if kind:
            kind_files[kind].append(name)
        grid, errors = read_grid(vtk_mods, path)
        if not ck.check(grid is not None, "%s: read by VTK's reader%s"
                        % (name, "" if not errors else " (" + " | ".join(errors) + ")")):
            continue
        npts, ncells = grid.GetNumberOfPoints(), grid.GetNumberOfCells()
        if kind == "points":
            want = counts.get("points")
            ck.check(npts == want, "%s: %d points (summary: %s)" % (name, npts, want))
            ck.check(ncells == npts and all(
                grid.GetCellType(c) == VTK_VERTEX for c in range(ncells)),
                "%s: %d cells, all VTK_VERTEX" % (name, ncells))
            check_arrays(ck, grid, name, POINT_ARRAYS)
            ids = grid.GetPointData().GetArray("id")
            if ids is not None:  # points may be reordered; ids stay 0..n-1
                got = sorted(int(ids.GetValue(t)) for t in range(ids.GetNumberOfTuples()))
                ck.check(got == list(range(npts)), "%s: id is a permutation of 0..%d" % (name, npts - 1))
        elif kind == "mesh":
            wn, wc = counts.get("nodes"), counts.get("cells")
            ck.check(npts == wn, "%s: %d points (summary nodes: %s)" % (name, npts, wn))
            ck.check(ncells == wc, "%s: %d cells (summary cells: %s)" % (name, ncells, wc))
            check_arrays(ck, grid, name, MESH_ARRAYS)
            grids[name] = grid
        else:
            ck.note("%s: neither points_* nor mesh_*: only read and NaN checks" % name)
            check_arrays(ck, grid, name, {})
    return grids


def read_series(ck, path, label):
    """The (time, file) entries of a .vtk.series (ParaView's JSON), or
    None."""
    try:
        with open(path) as fh:
            js = json.load(fh)
    except (OSError, ValueError) as e:
        ck.check(False, "%s is JSON (%s)" % (label, e))
        return None
    ck.check(js.get("file-series-version") == "1.0" and isinstance(js.get("files"), list),
             "%s: file-series-version 1.0 and a files list" % label)
    return [(float(e.get("time", "nan")), os.path.normpath(e.get("name", "")))
            for e in js.get("files", [])]


def check_pvd(ck, run, kind, files, ext):
    """The collection (.pvd of .vtu frames, .vtk.series of legacy ones)
    lists exactly the files of its kind, in increasing time. Returns the
    list of (time, file) or None."""
    label = kind + (".pvd" if ext == ".vtu" else ".vtk.series")
    pvd = os.path.join(run, label)
    if kind == "mesh" and not files and not os.path.exists(pvd):
        ck.skip("%s: no mesh files, no collection" % label)
        return None
    if not ck.check(os.path.isfile(pvd), "%s exists" % label):
        return None
    if ext == ".vtk":
        entries = read_series(ck, pvd, label)
        if entries is None:
            return None
    else:
        try:
            root = ET.parse(pvd).getroot()
        except ET.ParseError as e:
            ck.check(False, "%s is well-formed XML (%s)" % (label, e))
            return None
        coll = root.find("Collection")
        ck.check(root.tag == "VTKFile" and root.get("type") == "Collection"
                 and coll is not None, "%s: VTKFile type=Collection" % label)
        entries = []
        for ds in (coll if coll is not None else []):
            if ds.tag != "DataSet":
                continue
            try:
                t = float(ds.get("timestep"))
            except (TypeError, ValueError):
                t = float("nan")
            f = os.path.normpath(ds.get("file", ""))
            entries.append((t, f))
    listed = [f for _, f in entries]
    want = sorted(os.path.normpath(f) for f in files)
    extra = sorted(set(listed) - set(want))
    missing = sorted(set(want) - set(listed))
    dup = len(listed) != len(set(listed))
    ck.check(not extra and not missing and not dup,
             "%s lists exactly the %d %s files (%d entries%s%s%s)" % (
                 label, len(want), kind, len(listed),
                 ", not on disk: %s" % extra[:3] if extra else "",
                 ", not listed: %s" % missing[:3] if missing else "",
                 ", duplicates" if dup else ""))
    times = [t for t, _ in entries]
    inc = all(math.isfinite(t) for t in times) and all(
        b > a for a, b in zip(times, times[1:]))
    ck.check(inc, "%s: times strictly increasing (%s .. %s)" % (
        label, times[0] if times else "-", times[-1] if times else "-"))
    return entries


def last_probe_row(run):
    """Header and last non-empty row of probes.csv, or (None, None)."""
    path = os.path.join(run, "probes.csv")
    if not os.path.isfile(path):
        return None, None
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(fh) if r and any(c.strip() for c in r)]
    if len(rows) < 2:
        return (rows[0] if rows else None), None
    return [c.strip() for c in rows[0]], rows[-1]


def check_probes(ck, run, summary, grids, mesh_entries):
    """LAST mesh file's displacement at a probe node == probes.csv last row."""
    probes = summary.get("probes") or {}
    if not probes:
        ck.skip("probes: none in summary.json")
        return
    if not grids:
        ck.skip("probes: no mesh files to compare with")
        return
    last = max(grids, key=lambda n: file_number(os.path.basename(n)))
    grid = grids[last]
    header, row = last_probe_row(run)
    if not ck.check(row is not None, "probes.csv exists with a header and data"):
        return
    col = {h: i for i, h in enumerate(header)}
    if mesh_entries and "time" in col:
        tmesh = dict((f, t) for t, f in mesh_entries).get(os.path.normpath(last))
        try:
            tcsv = float(row[col["time"]])
        except (ValueError, IndexError):
            tcsv = None
        if tmesh is not None and tcsv is not None and \
                abs(tmesh - tcsv) > 1e-12 * max(1.0, abs(tmesh)):
            ck.note("probes.csv last time %r differs from %s time %r"
                    % (tcsv, last, tmesh))
    disp = grid.GetPointData().GetArray("displacement")
    if not ck.check(disp is not None, "%s: displacement for probes" % last):
        return
    pts = grid.GetPoints()
    ref = []
    for i in range(grid.GetNumberOfPoints()):
        p, u = pts.GetPoint(i), disp.GetTuple3(i)
        ref.append((p[0] - u[0], p[1] - u[1]))
    for name, spec in sorted(probes.items()):
        try:
            px, py = float(spec["x"][0]), float(spec["x"][1])
        except (KeyError, TypeError, ValueError, IndexError):
            ck.check(False, "probe %s: summary gives its position x = [x, y]" % name)
            continue
        cols = (name + "_ux", name + "_uy")
        if not ck.check(all(c in col for c in cols),
                        "probe %s: probes.csv has %s, %s" % (name, cols[0], cols[1])):
            continue
        best, dist = -1, float("inf")
        for i, (rx, ry) in enumerate(ref):
            d = math.hypot(rx - px, ry - py)
            if d < dist:
                best, dist = i, d
        if dist > PROBE_DIST_TOL * max(1.0, abs(px), abs(py)):
            ck.skip("probe %s: nearest mesh node %d is %.3g away from (%r, %r); "
                    "displacement not compared" % (name, best, dist, px, py))
            continue
        try:
            ucsv = (float(row[col[cols[0]]]), float(row[col[cols[1]]]))
        except (ValueError, IndexError):
            ck.check(False, "probe %s: last row of probes.csv is numeric" % name)
            continue
        uvtk = disp.GetTuple3(best)[:2]
        scale = max(math.hypot(*ucsv), 1e-300)
        err = max(abs(a - b) for a, b in zip(uvtk, ucsv)) / scale
        ck.check(err <= PROBE_REL_TOL,
                 "probe %s: %s node %d displacement (%.10g, %.10g) == probes.csv "
                 "last row (%.10g, %.10g) (rel err %.2g)" % (
                     name, last, best, uvtk[0], uvtk[1], ucsv[0], ucsv[1], err))


def main(argv):
    if len(argv) != 2 or not os.path.isdir(argv[1]):
        print("usage: /usr/bin/python3 check_vtk.py RUN_DIR", file=sys.stderr)
        return 2
    vtk_mods = import_vtk()
    if vtk_mods is None:
        print("error: cannot import vtk. Install python3-vtk9 "
              "(apt-get install python3-vtk9) and run this script with "
              "/usr/bin/python3, not another python.", file=sys.stderr)
        return 2
    run = argv[1]
    ck = Checker()
    summary = {}
    try:
        with open(os.path.join(run, "summary.json")) as fh:
            summary = json.load(fh)
        ck.check(isinstance(summary.get("counts"), dict),
                 "summary.json has counts")
    except (OSError, ValueError) as e:
        ck.check(False, "summary.json readable (%s)" % e)
    exts = [e for e in (".vtu", ".vtk") if glob.glob(os.path.join(run, "vtk", "*" + e))]
    ck.check(bool(exts), "vtk/ holds .vtu or .vtk frames")
    for ext in exts:
        kind_files = {"points": [], "mesh": []}
        grids = check_files(ck, vtk_mods, run, summary, kind_files, ext)
        ck.check(bool(kind_files["points"] or kind_files["mesh"]),
                 "vtk/ holds %s output files (%d points, %d mesh)" % (
                     ext, len(kind_files["points"]), len(kind_files["mesh"])))
        check_pvd(ck, run, "points", kind_files["points"], ext)
        mesh_entries = check_pvd(ck, run, "mesh", kind_files["mesh"], ext)
        check_probes(ck, run, summary, grids, mesh_entries)
    print("%d passed, %d failed" % (ck.passed, ck.failed))
    return 1 if ck.failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
