#!/usr/bin/env bash
# petsc_options.sh -- solver.petsc confined (docs/scene-format.md, "PETSc
# options are confined"): what reaches outside the results folder is
# refused as bad input before anything is read or written, and PETSc's own
# judgement of the options (a misspelt name, an unknown type) comes at load
# from `mpgm check` and `mpgm run` alike, as bad input naming the file:
#   - -options_file /etc/passwd: exit 2 from check and run, no line of the
#     file in the output, no results folder;
#   - -options_file naming a FIFO: refused at once (it would block forever);
#   - -ksp_monitor :PATH and -ksp_view_mat binary:PATH: refused, PATH not
#     created, no results folder;
#   - a misspelt option and an unknown KSP type: exit 2 from `mpgm check`
#     with "FILE: solver.petsc:", and from `mpgm run` before any output;
#   - the check uses the run's symmetry: a GMRES option is unused on the
#     cantilever (symmetric: CG by default) and used on the column collapse
#     (Mohr-Coulomb: GMRES by default);
#   - -ksp_monitor with no value runs and prints its residuals to the
#     terminal; a preset (CG + ICC(0)) gives UMFPACK's tip deflection;
#   - a scene that does not ask for PETSc does not load it; an explicit
#     run, which solves nothing, does not judge solver.petsc with PETSc.
# usage: petsc_options.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
cl="$src/cases/cantilever.json"
cc="$src/cases/column_collapse.json"
npass=0; nfail=0
pass() { echo "PASS: $1"; npass=$((npass + 1)); }
fail() { echo "FAIL: $1"; nfail=$((nfail + 1)); }

# refused WHAT OPTIONS [SCENE]: `mpgm check` and `mpgm run` exit 2 within
# 10 s naming the scene file and solver.petsc, with no line of /etc/passwd
# in what they print, and the run writes no results folder.
refused() {
  local what="$1" opts="$2" scene="${3:-$cl}" name rc out
  name=$(basename "$scene")
  for cmd in check run; do
    out="$work/out_$npass$nfail"
    rm -rf "$work/res"
    if [ "$cmd" = check ]; then
      timeout 10 "$exe" check "$scene" --set solver.linear=petsc --set "solver.petsc=$opts" \
        > "$out" 2>&1
    else
      timeout 10 "$exe" run "$scene" --quiet --set output.vtk=none --set solver.linear=petsc \
        --set "solver.petsc=$opts" --out "$work/res" > "$out" 2>&1
    fi
    rc=$?
    if [ $rc -ne 2 ]; then fail "$what: $cmd exits $rc, not 2: $(head -c 300 "$out")"
    elif ! grep -qF "$name: solver.petsc: " "$out"; then fail "$what: $cmd: no '$name: solver.petsc:' in: $(head -c 300 "$out")"
    elif grep -q "root:" "$out"; then fail "$what: $cmd printed a line of /etc/passwd"
    elif [ -e "$work/res" ]; then fail "$what: $cmd wrote the results folder"
    else pass "$what: $cmd exits 2 ($(head -c 160 "$out"))"
    fi
  done
}

refused "-options_file /etc/passwd" "-options_file /etc/passwd"
refused "-options_file_yaml" "-ksp_type cg -options_file_yaml /etc/passwd"
mkfifo "$work/fifo"
refused "-options_file naming a FIFO, without blocking" "-options_file $work/fifo"
refused "-ksp_monitor :PATH" "-ksp_monitor :$work/monitor.txt"
[ ! -e "$work/monitor.txt" ] && pass "-ksp_monitor :PATH: $work/monitor.txt not created" \
  || fail "-ksp_monitor :PATH: $work/monitor.txt was created"
refused "-ksp_view_mat binary:PATH" "-ksp_view_mat binary:$work/A.bin"
[ ! -e "$work/A.bin" ] && [ ! -e "$work/A.bin.info" ] && pass "-ksp_view_mat: $work/A.bin not written" \
  || fail "-ksp_view_mat: $work/A.bin written"
refused "-ksp_converged_reason ascii:PATH" "-ksp_converged_reason ascii:$work/reason.txt"
refused "MUMPS's diagnostics to a Fortran unit (a file)" \
  "-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps -mat_mumps_icntl_2 7"
ls "$work"/fort.* > /dev/null 2>&1 && fail "a fort.N file was written" || pass "no fort.N file"
refused "-prefix_push" "-prefix_push x_ -ksp_type cg -prefix_pop"
refused "a path as a value" "-pc_type ilu -pc_factor_mat_ordering_type /etc/passwd"
# PETSc's own judgement, at load
refused "a misspelt option" "-pc_typo gamg"
refused "an unknown KSP type" "-ksp_type nosuchkrylov"
refused "a GMRES option with the cantilever's symmetric tangent (CG)" \
  "-ksp_gmres_cgs_refinement_type refine_ifneeded"
"$exe" check "$cl" --set solver.linear=petsc --set "solver.petsc=-pc_typo gamg" > /dev/null \
  2> "$work/typo.err"
grep -q "^mpgm: $cl: solver.petsc: PETSc did not use -pc_typo" "$work/typo.err" \
  && pass "mpgm check: the misspelt option with the file prefix: $(cat "$work/typo.err")" \
  || fail "mpgm check: misspelt option message: $(cat "$work/typo.err")"
grep -q "step 1" "$work/typo.err" && fail "the misspelt option reads as a step failure" \
  || pass "the misspelt option is not a step failure"
short=(--set mesh.h=0.25 --set time.end=0.05 --set solver.forcing=fixed --set output.vtk=none)
"$exe" check "$cc" "${short[@]}" --set solver.linear=petsc \
  --set "solver.petsc=-ksp_gmres_cgs_refinement_type refine_ifneeded" > /dev/null 2> "$work/cc.err" \
  && pass "the same GMRES option passes on the column collapse (unsymmetric: GMRES)" \
  || fail "GMRES option on the column collapse refused: $(cat "$work/cc.err")"

# what is allowed runs: a monitor to the terminal; a preset gives UMFPACK's answer
"$exe" run "$cl" --quiet --set output.vtk=none --set solver.linear=petsc \
  --set "solver.petsc=-ksp_type cg -pc_type icc -ksp_monitor" --out "$work/mon" > "$work/mon.out" 2>&1
rc=$?
[ $rc -eq 0 ] && grep -q "KSP Residual norm" "$work/mon.out" \
  && pass "-ksp_monitor without a value runs and prints to the terminal" \
  || fail "-ksp_monitor without a value: exit $rc: $(head -c 300 "$work/mon.out")"
"$exe" run "$cl" --quiet --set output.vtk=none --set solver.linear=umfpack --out "$work/umf" \
  > /dev/null 2>&1
python3 - "$work" <<'PY' && pass "CG + ICC(0) (preset cg-icc): UMFPACK's tip deflection to 1e-8" \
  || fail "CG + ICC(0) against UMFPACK (above)"
import json, sys
w = sys.argv[1]
a = json.load(open(f"{w}/mon/summary.json"))["metrics"]["tip_uy"]
b = json.load(open(f"{w}/umf/summary.json"))["metrics"]["tip_uy"]
print(f"tip_uy petsc {a!r}, umfpack {b!r}")
sys.exit(0 if abs(a - b) <= 1e-8 * abs(b) else 1)
PY

# PETSc is loaded only for scenes that ask for it
LD_DEBUG=libs "$exe" check "$cl" > /dev/null 2> "$work/ld_umf.txt"
LD_DEBUG=libs "$exe" check "$cl" --set solver.linear=petsc > /dev/null 2> "$work/ld_petsc.txt"
! grep -q "mpgm_petsc.so" "$work/ld_umf.txt" && grep -q "mpgm_petsc.so" "$work/ld_petsc.txt" \
  && pass "mpgm check loads PETSc's module for a petsc scene only" \
  || fail "PETSc's module loaded for umfpack, or not for petsc"
# an explicit run solves nothing: solver.petsc is held to the policy only
ex="$src/cases/dyka_bar.json"
"$exe" check "$ex" --set solver.linear=petsc --set "solver.petsc=-pc_typo gamg" > /dev/null \
  2> "$work/ex.err"
rc1=$?
"$exe" check "$ex" --set solver.linear=petsc --set "solver.petsc=-options_file /etc/passwd" \
  > /dev/null 2> "$work/ex2.err"
rc2=$?
[ $rc1 -eq 0 ] && [ $rc2 -eq 2 ] \
  && pass "explicit: PETSc judges nothing (exit $rc1), the policy still holds (exit $rc2)" \
  || fail "explicit: exit $rc1 / $rc2: $(cat "$work/ex.err" "$work/ex2.err" | head -c 300)"

echo "$npass passed, $nfail failed"
[ $nfail -eq 0 ]
