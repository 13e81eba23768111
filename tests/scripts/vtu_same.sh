#!/usr/bin/env bash
# The default .vtu frames hold the numbers of the legacy .vtk frames to the
# bit (tests/tools/vtu_same.py), on short runs of each kind the golden
# records cover: FEM (static cantilever, quads), MPM explicit (Dyka bar),
# GMM (rolling disk, MLS), written in both formats at once, the .vtu raw,
# zlib-compressed and ASCII (ASCII writes 17 digits: the doubles come back
# exactly). With it the golden records, which hash the legacy files
# (tests/golden/runs.txt), guard the default format's numbers too.
# usage: vtu_same.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail=0; runs=()
both=(--quiet --set 'output.format=["vtu","vtk"]')
run() { # NAME SCENE ARGS...
  local name="$1" scene="$2"; shift 2
  if "$exe" run "$src/cases/$scene" "${both[@]}" --out "$work/$name" "$@" > "$work/$name.log" 2>&1; then
    runs+=("$work/$name")
  else
    echo "FAIL: $name: mpgm run exited $?"; cat "$work/$name.log"; fail=1
  fi
}
run fem cantilever.json --set mesh.h=0.25 --set time.load_steps=2
run fem_ascii cantilever.json --set mesh.h=0.25 --set time.load_steps=2 --set output.vtk=ascii
run mpm_explicit dyka_bar.json --set time.end=2e-5 --set output.every=20 --set output.fields=[\"displacement\",\"velocity\",\"stress\",\"mass\",\"J\",\"body\"]
run gmm_zlib rolling_disk_gmm.json --set mesh.h=0.05 --set time.end=0.012 --set output.compress=zlib
/usr/bin/python3 "$src/tests/tools/vtu_same.py" "${runs[@]}" || fail=1
[ $fail -eq 0 ]
