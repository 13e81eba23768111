#!/usr/bin/env bash
# `mpgm render` (docs/studies.md): a short, coarse column collapse drawn
# coloured by eps_p at given times to PNG (one per time, and a sheet of
# panels), the nearest frame taken with a note or a warning, the common
# colour range equal to the field's range as VTK's own reader sees it (binary
# and ASCII .vtu files), legacy frames drawn from points.vtk.series,
# --size obeyed; a 3-D run projected along the third axis of --view (by
# default seen from +z), with |v| and v_z of all three components; an
# unknown field lists the fields, a
# folder without points.pvd is an I/O error, bad options are bad input.
# usage: render.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$(realpath "$1")"; src="$(realpath "$2")"; work="$3"
rm -rf "$work"; mkdir -p "$work"; work="$(realpath "$work")"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"
"$exe" run "$src/cases/column_collapse.json" --quiet --set mesh.h=0.1 --set time.dt=0.01 --set time.end=0.2 \
  --set 'output.times=[0.1]' --set output.every=1000 --out cc > cc.log 2>&1 || { ko "column collapse run"; cat cc.log; }
"$exe" run "$src/cases/cantilever.json" --quiet --set mesh.h=0.5 --set output.vtk=ascii --out cl > cl.log 2>&1 \
  || { ko "cantilever run"; cat cl.log; }

"$exe" render cc --field eps_p --time 0.1,0.2 > r1.out 2> r1.err; rc=$?
[ $rc -eq 0 ] && [ -s cc/render/eps_p_t0.1.png ] && [ -s cc/render/eps_p_t0.2.png ] \
  && ok "eps_p at t = 0.1, 0.2 into RUN/render/eps_p_t*.png" || ko "render (exit $rc): $(cat r1.err)"
"$exe" render cc --field eps_p --time 0.14,5 --size 640x400 --out sized > r2.out 2> r2.err; rc=$?
[ $rc -eq 0 ] && grep -q "note: t = 0.14 requested, frame at t = 0.1 drawn" r2.err \
  && grep -q "warning: t = 5 requested, frame at t = 0.2 drawn" r2.err \
  && ok "nearest frames: a note when off, a warning when far off" || ko "nearest frames (exit $rc): $(cat r2.err)"
"$exe" render cc --field eps_p --time 0,0.1,0.2 --range 0:0.5 --sheet "$work/sheet.png" --title "coarse" \
  > r3.out 2> r3.err; rc=$?
[ $rc -eq 0 ] && [ -s sheet.png ] && grep -q "3 panels" r3.out && grep -q "from 0 to 0.5" r3.out \
  && ok "--sheet: three panels in one picture, --range obeyed" || ko "sheet (exit $rc): $(cat r3.err)"
"$exe" render cl --field displacement_y > r4.out 2> r4.err; rc=$?
[ $rc -eq 0 ] && [ -s cl/render/displacement_y_t1.png ] && ok "ASCII VTK: the last frame by default" \
  || ko "ASCII render (exit $rc): $(cat r4.err) $(ls cl/render)"
"$exe" run "$src/cases/cantilever.json" --quiet --set mesh.h=0.5 --set output.format=vtk --out clv > clv.log 2>&1 \
  || { ko "cantilever run, legacy frames"; cat clv.log; }
"$exe" render clv --field displacement_y > r5.out 2> r5.err; rc=$?
[ $rc -eq 0 ] && [ -s clv/render/displacement_y_t1.png ] && ok "legacy frames only: drawn from points.vtk.series" \
  || ko "legacy render (exit $rc): $(cat r5.err)"
expect 2 "no field \"nosuch\"; fields: displacement (length), displacement_x" "unknown field: the fields listed" \
  "$exe" render cc --field nosuch
grep -q "eps_p" err.txt && grep -q "stress_q" err.txt && ok "the list names eps_p and stress_q" || ko "list: $(cat err.txt)"
expect 3 "points.pvd: cannot open" "a folder without points.pvd: exit 3" "$exe" render "$work/nothing"
expect 2 "--time: expected numbers" "bad --time" "$exe" render cc --time 0.1,abc
expect 2 "--size: expected WxH" "bad --size" "$exe" render cc --size 10x10
expect 2 "--range: expected MIN:MAX" "bad --range" "$exe" render cc --range 2:1
expect 2 "unknown option" "unknown option" "$exe" render cc --frobnicate
expect 2 "no RUN_DIR" "no run folder" "$exe" render
expect 3 "gnuplot not found on PATH" "without gnuplot on PATH: message, exit 3" \
  env PATH="$work/nowhere" "$exe" render cc --field eps_p
# the default colour range: the 1st to 99th percentile, said so; stresses in kPa
"$exe" render cc --field stress_q --time 0,0.2 --sheet "$work/q.png" --layout 1x2 > r5.out 2> r5.err; rc=$?
[ $rc -eq 0 ] && grep -q "stress_q from .* colour bar from .* (1-99 %)" r5.out \
  && ok "default colour range: 1-99 % of the frames drawn" || ko "percentile (exit $rc): $(cat r5.out r5.err)"
# material: one named colour per material of the scene (two materials here)
/usr/bin/python3 -c "
import json, sys; d = json.load(open(sys.argv[1] + '/cases/colliding_discs.json'))
d['materials']['steel'] = dict(d['materials']['rubber'], density=2000.0)
d['bodies'][1]['material'] = 'steel'; d['output']['fields'] = ['velocity', 'stress', 'material']
json.dump(d, open('two.json', 'w'))" "$src"
"$exe" run two.json --quiet --set mesh.h=0.1 --set time.end=0.02 --out two > two.log 2>&1 || { ko "two-material run"; cat two.log; }
"$exe" render two --field material > r6.out 2> r6.err; rc=$?
[ $rc -eq 0 ] && grep -q "colour bar from -0.5 to 1.5 (index)" r6.out && [ -s two/render/material_t0.02.png ] \
  && ok "material: two indexed colours" || ko "material (exit $rc): $(cat r6.out r6.err)"
expect 2 "no field \"body\"; fields: velocity (length)" "body on frames without it: the fields listed" \
  "$exe" render two --field body
# a 3-D run: projected (x across, gravity's y up, seen from +z by
# default; --view), the lengths and components of all three axes
"$exe" run "$src/cases/column_collapse_3d_free.json" --quiet --set mesh.h=0.5 --set time.dt=0.01 \
  --set time.end=0.02 --set 'solver={"linear": "auto"}' --out c3 > c3.log 2>&1 \
  || { ko "3-D column run"; cat c3.log; }
"$exe" render c3 --field velocity > r7.out 2> r7.err; rc=$?
[ $rc -eq 0 ] && [ -s c3/render/velocity_t0.02.png ] && grep -q "a 3-D run, projected: x across, y up, seen from +z" r7.out \
  && ok "3-D: projected by default x across, y (gravity's) up, seen from +z" || ko "3-D render (exit $rc): $(cat r7.out r7.err)"
"$exe" render c3 --field velocity_z --view xz --out top > r8.out 2> r8.err; rc=$?
[ $rc -eq 0 ] && [ -s top/velocity_z_t0.02.png ] && grep -q "x across, z up, seen from +y" r8.out \
  && ok "3-D: --view xz, seen from +y" || ko "3-D --view xz (exit $rc): $(cat r8.out r8.err)"
expect 2 "--view: expected two different axes" "bad --view" "$exe" render c3 --view xx
expect 2 "--view: a plane-strain run is drawn in x and y" "--view with z on a plane-strain run" \
  "$exe" render cc --view xz

/usr/bin/python3 - "$work" "$src" <<'PY'
import re, struct, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done
import vtk
w = sys.argv[1]
def size(p):
    b = open(p, "rb").read(24)
    return (struct.unpack(">II", b[16:24]) if b[:8] == b"\x89PNG\r\n\x1a\n" else None)
check(size(f"{w}/sized/eps_p_t0.14.png") == (640, 400), f"--size 640x400: {size(w + '/sized/eps_p_t0.14.png')}")
def vrange(f, name, comp):
    rd = vtk.vtkXMLUnstructuredGridReader(); rd.SetFileName(f); rd.Update()
    a = rd.GetOutput().GetPointData().GetArray(name)
    v = [a.GetComponent(i, comp) for i in range(a.GetNumberOfTuples())]
    return min(v), max(v)
r = [vrange(f"{w}/cc/vtk/points_{k:06d}.vtu", "eps_p", 0) for k in (1, 2)]
lo, hi = min(x[0] for x in r), max(x[1] for x in r)
m = re.search(r"eps_p from (\S+) to (\S+);", open(f"{w}/r1.out").read())
check(m and abs(float(m.group(1)) - lo) <= 1e-6 and abs(float(m.group(2)) - hi) <= 1e-5 * hi and hi > 0,
      f"binary .vtu: the common colour range is eps_p's over both frames as VTK reads it ({lo:.6g} to {hi:.6g})")
lo, hi = vrange(f"{w}/cl/vtk/points_000001.vtu", "displacement", 1)
m = re.search(r"displacement_y from (\S+) to (\S+);", open(f"{w}/r4.out").read())
check(m and abs(float(m.group(1)) - lo) <= 1e-5 * abs(lo) and abs(float(m.group(2)) - hi) <= 1e-5 * abs(lo) + 1e-12,
      f"ASCII .vtu: displacement_y from {lo:.6g} to {hi:.6g}, as VTK reads it")
# the percentile range lies inside the values' own range
m = re.search(r"stress_q from (\S+) to (\S+); colour bar from (\S+) to (\S+)", open(f"{w}/r5.out").read())
check(m and float(m.group(1)) <= float(m.group(3)) < float(m.group(4)) <= float(m.group(2)),
      "the 1-99 % colour range lies within the values' range")
# 3-D: |v| of all three components, and v_z, as VTK reads the last frame
last = sorted(__import__("glob").glob(f"{w}/c3/vtk/points_*.vtu"))[-1]
rd = vtk.vtkXMLUnstructuredGridReader(); rd.SetFileName(last); rd.Update()
a = rd.GetOutput().GetPointData().GetArray("velocity")
vs = [[a.GetComponent(i, c) for c in range(3)] for i in range(a.GetNumberOfTuples())]
speed = [sum(c * c for c in v) ** 0.5 for v in vs]
m = re.search(r"velocity from (\S+) to (\S+);", open(f"{w}/r7.out").read())
check(m and abs(float(m.group(2)) - max(speed)) <= 1e-5 * max(speed) and max(abs(v[2]) for v in vs) > 0,
      f"3-D: |v| over x, y and z, max {max(speed):.6g} as VTK reads it")
lo, hi = min(v[2] for v in vs), max(v[2] for v in vs)
m = re.search(r"velocity_z from (\S+) to (\S+);", open(f"{w}/r8.out").read())
check(m and abs(float(m.group(1)) - lo) <= 1e-5 * (hi - lo) and abs(float(m.group(2)) - hi) <= 1e-5 * (hi - lo),
      f"3-D: velocity_z from {lo:.6g} to {hi:.6g}, as VTK reads it")
done()
PY
pyrc=$?
echo "$npass passed, $nfail failed (shell checks)"
[ $nfail -eq 0 ] && [ $pyrc -eq 0 ]
