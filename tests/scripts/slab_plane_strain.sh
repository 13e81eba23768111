#!/usr/bin/env bash
# slab_plane_strain.sh -- a 3-D slab with rollers on its z faces is plane
# strain (issue 53): the same command (mpgm hands a 3-D scene to mpgm-3d)
# runs each case in 2-D and as the slab, on the same mesh in x and y, and
# the answers agree.
# 1. the static cantilever (cases/cantilever.json, cases/cantilever_3d.json
#    at h = 0.25: 32 x 4 x 4 cells), UL-FEM on Q4 / H8 and implicit MPM with
#    fe, ugimp (at the sub-cell centres) and cpdi (2 x 2 / 2 x 2 x 2 points
#    a cell): the tip
#    deflection within 1e-8 relative (the discrete equations coincide, so
#    what is left is the solvers' round-off);
# 2. Dyka's bar (explicit npc, cases/dyka_bar*.json at h = L/20): the RMS
#    of the points' velocity at 1e-5 s and at the end, and the probe's
#    displacement error, within 1e-8 relative;
# 3. the elastic column settling under gravity (cases/column_wave*.json,
#    implicit Newmark, MPM fe): the top's displacement history against the
#    same analytic solution, error within 1e-8 relative of the 2-D one's.
# usage: slab_plane_strain.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"
metric() { summary_metric "$work/$1" "$2"; }

# same NAME CASE2D CASE3D METRIC TOL WHAT [--set ...]: both runs complete and
# METRIC agrees within TOL relative
same() {
  local name="$1" c2="$2" c3="$3" m="$4" tol="$5" what="$6"; shift 6
  "$exe" run "$src/cases/$c2" --quiet --set output.vtk=none "$@" --out "$work/${name}_2d" \
    > /dev/null 2> "$work/${name}_2d.err"
  local r2=$?
  "$exe" run "$src/cases/$c3" --quiet --set output.vtk=none "$@" --out "$work/${name}_3d" \
    > /dev/null 2> "$work/${name}_3d.err"
  local r3=$?
  local a b
  a=$(metric ${name}_2d "$m"); b=$(metric ${name}_3d "$m")
  if [ $r2 -eq 0 ] && [ $r3 -eq 0 ] && python3 -c "
import sys; a, b = float('$a'), float('$b')
sys.exit(0 if abs(a - b) <= $tol * max(abs(a), 1e-300) else 1)"; then
    ok "$what: $m $a (2-D) and $b (slab)"
  else
    ko "$what: $m $a (2-D, exit $r2) against $b (slab, exit $r3): $(tail -c 300 "$work/${name}_3d.err")"
  fi
}

# ---- 1: the cantilever ------------------------------------------------------------
same fem cantilever.json cantilever_3d.json tip_uy 1e-8 "UL-FEM cantilever, Q4 and H8" --set mesh.h=0.25
for k in fe cpdi; do
  same mpm_$k cantilever.json cantilever_3d.json tip_uy 1e-8 "implicit MPM cantilever, $k" \
    --set mesh.h=0.25 --set method=mpm --set shape.kind=$k
done
# uGIMP's squares at the sub-cell centres end on the slab's faces, where its
# grid ends (at the Gauss points they reach past it: refused in 3-D)
same mpm_ugimp cantilever.json cantilever_3d.json tip_uy 1e-8 "implicit MPM cantilever, ugimp" \
  --set mesh.h=0.25 --set method=mpm --set shape.kind=ugimp --set mesh.layout=centres

# ---- 2: Dyka's bar ----------------------------------------------------------------
for m in velocity_rms_t1 velocity_rms_end error_rms; do
  same dyka_$m dyka_bar.json dyka_bar_3d.json $m 1e-8 "Dyka's bar, explicit npc" --set mesh.h=0.006665
done

# ---- 3: the elastic column ----------------------------------------------------------
same wave column_wave.json column_wave_3d.json error_rms 1e-8 "elastic column, implicit Newmark" \
  --set time.end=0.5

echo "$npass passed, $nfail failed"
[ $nfail -eq 0 ]
