#!/usr/bin/env bash
# Open every VTK file of short runs (.vtu raw binary, ASCII and zlib; legacy
# .vtk binary and ASCII; both at once) with Debian's VTK readers
# (python3-vtk9, as ParaView would) and check counts, fields and the
# collections (.pvd, .vtk.series) against summary.json and probes.csv.
# usage: vtk_read.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail=0
for mode in binary ascii zlib legacy_binary legacy_ascii both; do
  case $mode in
    binary|ascii) sets=(--set output.vtk=$mode) ;;
    zlib) sets=(--set output.compress=zlib) ;;
    legacy_*) sets=(--set output.format=vtk --set output.vtk=${mode#legacy_}) ;;
    both) sets=(--set 'output.format=["vtu","vtk"]') ;;
  esac
  for cell in quad tri; do
    d="$work/${mode}_$cell"
    if ! "$exe" run "$src/cases/cantilever.json" --quiet --out "$d" --set mesh.h=0.25 \
         --set mesh.cell=$cell --set time.load_steps=3 "${sets[@]}" > "$d.log" 2>&1; then
      echo "FAIL: run $mode $cell"; cat "$d.log"; fail=1; continue
    fi
    echo "== $mode $cell"
    /usr/bin/python3 "$src/tests/tools/check_vtk.py" "$d" || fail=1
  done
done
# MPM: particle files only (the background grid is not a body mesh)
d="$work/mpm"
if "$exe" run "$src/cases/rolling_disk.json" --quiet --out "$d" --set mesh.h=0.05 --set time.dt=0.01 \
     --set time.end=0.1 --set output.every=5 > "$d.log" 2>&1; then
  echo "== mpm"
  /usr/bin/python3 "$src/tests/tools/check_vtk.py" "$d" || fail=1
else
  echo "FAIL: run mpm"; cat "$d.log"; fail=1
fi
# output.every: steps 0, 2, 4 and the last (5) are written
d="$work/every"
"$exe" run "$src/cases/cantilever.json" --quiet --out "$d" --set mesh.h=0.5 \
  --set time.load_steps=5 --set output.every=2 > "$d.log" 2>&1 || { echo "FAIL: run every"; fail=1; }
n=$(ls "$d"/vtk/points_*.vtu 2>/dev/null | wc -l)
if [ "$n" -eq 4 ]; then echo "PASS: output.every=2 over 5 steps writes 4 point files"; else echo "FAIL: output.every=2 wrote $n point files, expected 4"; fail=1; fi
/usr/bin/python3 "$src/tests/tools/check_vtk.py" "$d" || fail=1
if [ $fail -eq 0 ]; then echo "1 passed, 0 failed"; else echo "0 passed, 1 failed"; fi
exit $fail
