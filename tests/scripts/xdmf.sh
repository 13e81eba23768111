#!/usr/bin/env bash
# xdmf.sh -- output.format "xdmf" (issue 52, item 2): results.h5 and its
# XDMF indices.
#   fem        the cantilever (UL-FEM, static: load factors as times; points
#              and mesh), written as .vtu, legacy .vtk and XDMF: h5py reads
#              the same numbers as the .vtk and .vtu frames, to the bit, at the same
#              times (tests/tools/xdmf_same.py), datasets not deflated
#   mpm        an explicit MPM column collapse (h = 0.2, 10 steps, every
#              step a frame), the same with output.compress zlib: the
#              datasets deflated, the numbers the same
#   xdmf only  the cantilever with output.format "xdmf" alone: no VTK
#              frame, and results.h5 holds what the fem run's holds
#   killed     a longer column collapse killed (SIGKILL) once its index lists
#              3 frames: every dataset the index names is in results.h5 and
#              reads back (the file is flushed before the index names a frame)
#   restart    a checkpointed run whose results.h5 is gone or does not hold
#              the frames with the checkpoint's times: the restart is
#              refused with a message, the index left as it was
#   rerun      a run without XDMF in a folder that held one: results.h5 and
#              the indices of the earlier run are gone
#   ParaView   pvbatch opens points.xdmf and mesh.xdmf (tests/tools/
#              pv_xdmf.py: the output times, the arrays to the bit); said
#              plainly and skipped without pvbatch3.11 and its python module
# usage: xdmf.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src=$(cd "$2" && pwd); work="$3"
rm -rf "$work"; mkdir -p "$work"
py=/usr/bin/python3; [ -x "$py" ] || py=python3
npass=0; nfail=0
pass() { echo "PASS: $1"; npass=$((npass + 1)); }
fail() { echo "FAIL: $1"; nfail=$((nfail + 1)); }
both=(--quiet --set 'output.format=["vtu","vtk","xdmf"]' --set output.every=1 --set output.times=[])
cc=("$src/cases/column_collapse.json" --set mesh.h=0.2 --set time.end=0.05)
# run NAME ARGS...: a run that must succeed
run() {
  local name="$1"; shift
  if "$exe" run "$@" --out "$work/$name" > "$work/$name.log" 2>&1; then return 0; fi
  fail "$name: mpgm run exited $?: $(head -c 300 "$work/$name.log")"
  return 1
}
# same NAME: h5py's numbers are the legacy frames'
same() {
  if "$py" "$src/tests/tools/xdmf_same.py" "$work/$1" > "$work/$1.same" 2>&1; then
    pass "$1: $(tail -1 "$work/$1.same"): results.h5 = the .vtk and .vtu frames to the bit, same times, index consistent"
  else
    grep -v '^PASS' "$work/$1.same"; fail "$1: results.h5 differs from the .vtk or .vtu frames (above)"
  fi
}
# deflated NAME yes|no: are results.h5's point datasets deflated?
deflated() {
  local got
  got=$("$py" -c 'import h5py, sys
f = h5py.File(sys.argv[1], "r")
print("yes" if all(f["points"][g][d].compression == "gzip" for g in f["points"] for d in f["points"][g]) else "no")' \
    "$work/$1/results.h5" 2>&1)
  [ "$got" = "$2" ] && pass "$1: datasets deflated: $2" || fail "$1: datasets deflated: $got, expected $2"
}

run fem "$src/cases/cantilever.json" "${both[@]}" && { same fem; deflated fem no; }
run mpm "${cc[@]}" "${both[@]}" --set output.compress=zlib && { same mpm; deflated mpm yes; }

if run xdmf_only "$src/cases/cantilever.json" --quiet --set output.format=xdmf --set output.every=1; then
  if [ -e "$work/xdmf_only/points.xdmf" ] && [ -e "$work/xdmf_only/mesh.xdmf" ] &&
     [ -z "$(ls "$work/xdmf_only/vtk" 2> /dev/null)" ] && ! ls "$work"/xdmf_only/*.pvd > /dev/null 2>&1; then
    if "$py" -c 'import sys; sys.path.insert(0, sys.argv[1]); import same_run
a, b = same_run.h5_items(sys.argv[2]), same_run.h5_items(sys.argv[3])
sys.exit(0 if a == b and len(a) > 4 else 1)' "$src/tests/tools" "$work/fem/results.h5" "$work/xdmf_only/results.h5"; then
      pass "xdmf only: points.xdmf, mesh.xdmf, no VTK frame or .pvd; results.h5 holds what the fem run's holds"
    else
      fail "xdmf only: results.h5 differs from the fem run's (written with the .vtk frames)"
    fi
  else
    fail "xdmf only: expected points.xdmf and mesh.xdmf and no VTK frames: $(ls "$work/xdmf_only" "$work/xdmf_only/vtk" 2>&1 | tr '\n' ' ')"
  fi
fi

# killed: SIGKILL once the index lists 3 frames (a frame per step, 200 steps)
k="$work/killed"
"$exe" run "$src/cases/column_collapse.json" --quiet --set mesh.h=0.2 --set time.end=1 --set output.format=xdmf \
  --set output.every=1 --out "$k" > "$work/killed.log" 2>&1 &
pid=$!
for _ in $(seq 1 3000); do
  [ "$(grep -c '<Time ' "$k/points.xdmf" 2> /dev/null)" -ge 3 ] 2> /dev/null && break
  kill -0 "$pid" 2> /dev/null || break
  sleep 0.01
done
if kill -9 "$pid" 2> /dev/null; then
  wait "$pid" 2> /dev/null
  if out=$("$py" - "$k" <<'EOF' 2>&1
import sys, xml.etree.ElementTree as ET, h5py
run = sys.argv[1]
root = ET.parse(run + "/points.xdmf").getroot()
items = list(root.iter("DataItem"))
with h5py.File(run + "/results.h5", "r") as f:
    for it in items:
        ds = it.text.strip().split(":", 1)[1]
        dims = tuple(int(v) for v in it.get("Dimensions").split())
        assert f[ds].shape == dims, ds
        f[ds][()]  # every byte the index names reads back
print(len(root.findall("./Domain/Grid/Grid")), "frames,", len(items), "datasets")
EOF
  ); then
    pass "killed: SIGKILL mid-run; every dataset its index names reads back from results.h5 ($out)"
  else
    fail "killed: the index of a killed run names what results.h5 does not give: $out"
  fi
else
  wait "$pid"; fail "killed: the run ended before its index listed 3 frames (exit $?): $(tail -c 300 "$work/killed.log")"
fi

# restart: refused when results.h5 does not hold the checkpoint's frames
r="$work/restart"
if run restart "$src/cases/cantilever.json" --quiet --set output.format=xdmf --set time.load_steps=4 \
  --set output.checkpoint_every=2 --set output.every=1; then
  cp "$r/points.xdmf" "$work/points.xdmf.before"
  # refused WHAT RC MESSAGE: the restart exits RC saying MESSAGE, the index untouched
  refused() {
    "$exe" run --restart "$r" --quiet > "$work/restart.log" 2>&1
    local rc=$?
    if [ $rc -eq "$2" ] && grep -q "$3" "$work/restart.log" && cmp -s "$r/points.xdmf" "$work/points.xdmf.before"; then
      pass "restart $1: exit $2, '$(head -c 200 "$work/restart.log")', the index untouched"
    else
      fail "restart $1: exit $rc: $(head -c 300 "$work/restart.log")"
    fi
  }
  mv "$r/results.h5" "$work/results.h5.kept"
  refused "without results.h5" 3 'results.h5: cannot read the frames the checkpoint lists'
  mv "$work/results.h5.kept" "$r/results.h5"
  "$py" -c 'import h5py, sys
f = h5py.File(sys.argv[1], "a"); f["points/000001"].attrs["time"] = 0.3' "$r/results.h5"
  refused "with a frame of another time" 2 'frame 1 of the points is not as written'
fi

# rerun: a run without XDMF in the folder of one with it (--force: mpgm
# refuses to replace a finished run of another scene without it)
if run mpm_rerun "${cc[@]}" --quiet --set output.format=xdmf && run mpm_rerun "${cc[@]}" --quiet --force; then
  if [ ! -e "$work/mpm_rerun/results.h5" ] && [ ! -e "$work/mpm_rerun/points.xdmf" ]; then
    pass "rerun without XDMF: the earlier run's results.h5 and points.xdmf are gone"
  else
    fail "rerun without XDMF: an earlier run's XDMF files are left: $(ls "$work/mpm_rerun" | tr '\n' ' ')"
  fi
fi

pv=$(command -v pvbatch3.11 || command -v pvbatch || true)
if [ -z "$pv" ]; then
  echo "SKIP: ParaView's XDMF reader not checked: pvbatch not installed (Debian: paraview python3-paraview)"
elif ! "$pv" --force-offscreen-rendering <(echo 'import paraview.simple') > "$work/pv_probe.log" 2>&1; then
  echo "SKIP: ParaView's XDMF reader not checked: $pv has no paraview python module (Debian: python3-paraview)"
elif (cd "$work" && "$pv" --force-offscreen-rendering "$src/tests/tools/pv_xdmf.py" fem mpm) > "$work/pv.log" 2>&1; then
  pass "ParaView: $(grep -c '^PASS' "$work/pv.log") checks of points.xdmf and mesh.xdmf (times, arrays to the bit)"
else
  cat "$work/pv.log"; fail "ParaView's XDMF reader (above)"
fi

echo "xdmf: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
