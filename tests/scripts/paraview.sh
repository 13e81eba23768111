#!/usr/bin/env bash
# ParaView itself opens the results (issue 52): short runs of the column
# collapse (MPM, h = 0.2, 0.1 s = 20 steps; the probe set on the material
# point nearest the case's top-right probe) and the rolling disk (MPM and
# GMM with rim contact, h = 0.05, dt = 0.004, 0.02 s: the disk starts
# rolling; the probe on the point next to its centre) and the 3-D free
# column (MPM, H8, 5 steps), written as .vtu and
# legacy .vtk at every step, are checked under pvbatch by
# tests/tools/pv_check.py (times, point counts, arrays, values against
# probes.csv and steps.csv). Without pvbatch3.11 (Debian's paraview) the
# test says so and returns 77, ctest's skip code (tests/CMakeLists.txt).
# usage: paraview.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src=$(cd "$2" && pwd); work="$3"
pv=$(command -v pvbatch3.11 || command -v pvbatch)
if [ -z "$pv" ]; then
  echo "SKIP: pvbatch not installed (Debian: apt-get install paraview python3-paraview): the ParaView tests are skipped"
  exit 77
fi
rm -rf "$work"; mkdir -p "$work"
fail=0; runs=()
common=(--quiet --set output.every=1 --set output.times=[] --set 'output.format=["vtu","vtk","xdmf"]')
run() { # NAME SCENE ARGS...
  local name="$1" scene="$2"; shift 2
  if "$exe" run "$src/cases/$scene" "${common[@]}" --out "$work/$name" "$@" > "$work/$name.log" 2>&1; then
    runs+=("$work/$name")
  else
    echo "FAIL: $name: mpgm run exited $?"; cat "$work/$name.log"; fail=1
  fi
}
run column_collapse column_collapse.json --set mesh.h=0.2 --set time.end=0.1 \
  --set 'probes={"top_right":[3.957735026918962,1.9577350269189624]}' \
  --set 'output.fields=["displacement","velocity","stress","eps_p","J","id","mass","body"]' \
  --set output.grid=true
disk=(--set mesh.h=0.05 --set time.dt=0.004 --set time.end=0.02
      --set 'probes={"centre":[0.6083333333333334,0.49666666666666665]}')
run rolling_disk rolling_disk.json "${disk[@]}" --set output.grid=true
run rolling_disk_gmm rolling_disk.json "${disk[@]}" --set method=gmm --set shape.kind=mls --set output.compress=zlib
# 3-D: the free column (MPM, H8, h = 0.5: 128 points), 5 steps; the probe
# on the material point of the top corner's cell nearest (1.95, 1.95, 1.95)
# (a Gauss point: 1.75 + 0.25 / sqrt(3) in each axis)
g3=1.8943375672974065
run column_3d column_collapse_3d_free.json --set mesh.h=0.5 --set time.dt=0.01 --set time.end=0.05 \
  --set 'solver={"linear": "auto"}' --set "probes={\"corner\":[$g3,$g3,$g3]}" --set output.grid=true \
  --set 'output.fields=["displacement","velocity","stress","eps_p","J","id","mass"]'
# on 3 processes (issue 54; Open MPI's mpiexec, oversubscribed): the
# column collapse explicit (20 steps of 1 ms), written as each process's
# .vtu pieces of one .pvtu per frame: ParaView opens points.pvd as one
# dataset of the whole run's points, the probe and the energy as above
mpx=$(command -v mpiexec || true)
if [ -n "$mpx" ] && "$mpx" --version 2>&1 | grep -qE "Open MPI|OpenRTE"; then
  if OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "$mpx" --oversubscribe -n 3 "$exe" run \
      "$src/cases/column_collapse.json" --quiet --set output.every=1 --set output.times=[] \
      --set mesh.h=0.2 --set time.analysis=explicit --set time.dt=0.001 --set time.end=0.02 \
      --set 'probes={"top_right":[3.957735026918962,1.9577350269189624]}' \
      --set 'output.fields=["displacement","velocity","stress","eps_p","J","id","mass","body"]' \
      --out "$work/column_3procs" > "$work/column_3procs.log" 2>&1; then
    runs+=("$work/column_3procs")
  else
    echo "FAIL: column_3procs: mpiexec -n 3 mpgm run exited $?"; cat "$work/column_3procs.log"; fail=1
  fi
else
  echo "note: no Open MPI mpiexec: the pieces of a run on many processes are not opened"
fi
(cd "$work" && "$pv" --force-offscreen-rendering "$src/tests/tools/pv_check.py" "${runs[@]##*/}") \
  > "$work/pv_check.log" 2>&1 || fail=1
cat "$work/pv_check.log"
[ $fail -eq 0 ]
