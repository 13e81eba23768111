#!/usr/bin/env bash
# PETSc behind the solver family (issue 19, item 1): solver.linear "petsc"
# with solver.petsc options gives the same runs as the direct solvers:
#   - the cantilever (symmetric tangent: CG + ICC(0) by default; GAMG,
#     MUMPS Cholesky): tip_uy the same as cholmod's to 1e-8;
#   - GAMG gets the tangent in blocks of a node's components with the
#     rigid-body near-null space (solvers/petsc/blocks.c): block size 2 in
#     the plane, 3 on the 3-D slab cantilever (whose tip is cholmod's to
#     1e-8), and CG needs under 120 iterations on each (82 and 79 measured;
#     256 and 357 with the free equations only, as before the block form);
#   - the column collapse, coarse and short (Mohr-Coulomb: an unsymmetric
#     tangent, GMRES + ILU(0) by default; GMRES + BoomerAMG, MUMPS LU):
#     runout and height the same as umfpack's to 1e-6, as many steps;
#   - a Krylov solve that stops short (-ksp_max_it 2) without a fallback
#     (solver.linear_fallback none) is a recoverable failure: the step is
#     cut, with PETSc's reason (DIVERGED_ITS) in summary.json's step_cuts,
#     counted in linear_not_converged;
#   - with solver.linear_fallback, a Krylov solve that stops short hands its
#     matrix to the direct backend instead: the cantilever with every CG
#     solve stopped at 1 iteration and cholmod as the fallback is cholmod's
#     run to the bit, each matrix counted (linear_fallbacks); the short
#     column with GMRES stopped at 2 iterations and umfpack as the fallback
#     runs to its end with no cut, umfpack's runout and height to 1e-12;
#   - GMRES stopped by PETSc's breakdown check at a restart: the message
#     names DIVERGED_BREAKDOWN and the remedy (re-orthogonalisation);
#   - bad input exits 2 and says why: an option PETSc did not use (a typo),
#     solver.petsc with another backend, a Cholesky fallback with an
#     unsymmetric material;
#   - bench-solvers runs PETSc's configurations on the column's unsymmetric
#     systems: each agrees with UMFPACK (direct to 1e-8, iterative to the
#     tolerance), CG and Cholesky are left out as "not symmetric".
# usage: petsc.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail=0
source "$src/tests/tools/run_case.bash"
cl="$src/cases/cantilever.json"
cc="$src/cases/column_collapse.json"
# the case ships the forcing term; these solves go to the fixed linear_tol
short=(--set mesh.h=0.25 --set time.end=0.05 --set solver.forcing=fixed)
run_case cl_cholmod "$cl" --set solver.linear=cholmod
run_case cl_petsc "$cl" --set solver.linear=petsc
run_case cl_gamg "$cl" --set solver.linear=petsc --set "solver.petsc=-pc_type gamg"
run_case cl3_cholmod "$src/cases/cantilever_3d.json" --set solver.linear=cholmod
run_case cl3_gamg "$src/cases/cantilever_3d.json" --set solver.linear=petsc --set "solver.petsc=-pc_type gamg"
run_case cl_mumps "$cl" --set solver.linear=petsc \
  --set "solver.petsc=-ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps"
run_case cc_umfpack "$cc" "${short[@]}" --set solver.linear=umfpack --set output.matrices=2
run_case cc_petsc "$cc" "${short[@]}" --set solver.linear=petsc
run_case cc_amg "$cc" "${short[@]}" --set solver.linear=petsc --set "solver.petsc=-pc_type hypre"
run_case cc_mumps "$cc" "${short[@]}" --set solver.linear=petsc \
  --set "solver.petsc=-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps"
# every solve stops after 2 iterations: cut twice, then the run fails
# (without the case's fallback)
"$exe" run "$cc" "${short[@]}" --quiet --set output.vtk=none --set solver.linear=petsc \
  --set "solver.petsc=-ksp_max_it 2" --set time.max_cuts=2 --set solver.linear_fallback=none \
  --out "$work/cc_short" \
  > "$work/cc_short.log" 2>&1
echo $? > "$work/cc_short.rc"
# GMRES stopped at its first restart by PETSc's breakdown check (made to
# fire with a zero tolerance): the reason and the remedy in the message
"$exe" run "$cc" "${short[@]}" --quiet --set output.vtk=none --set solver.linear=petsc \
  --set "solver.petsc=-ksp_gmres_breakdown_tolerance 1e-300" --set solver.linear_restart=3 \
  --set time.max_cuts=1 --set solver.linear_fallback=none --out "$work/cc_breakdown" \
  > "$work/cc_breakdown.log" 2>&1
echo $? > "$work/cc_breakdown.rc"
# the same with a direct fallback for the failed solves
run_case cl_fallback "$cl" --set solver.linear=petsc --set "solver.petsc=-ksp_max_it 1" \
  --set solver.linear_fallback=cholmod
run_case cc_fallback "$cc" "${short[@]}" --set solver.linear=petsc --set "solver.petsc=-ksp_max_it 2" \
  --set time.max_cuts=2 --set solver.linear_fallback=umfpack
bad() { # NAME ARGS...: a run that must be refused
  local name="$1"; shift
  "$exe" run "$cl" --quiet --set output.vtk=none --out "$work/bad_$name" "$@" > /dev/null \
    2> "$work/bad_$name.err"
  echo $? > "$work/bad_$name.rc"
}
bad typo --set solver.linear=petsc --set "solver.petsc=-pc_typo gamg"
bad other --set solver.linear=cholmod --set "solver.petsc=-pc_type gamg"
"$exe" run "$cc" --quiet --set output.vtk=none --set solver.linear_fallback=cholmod \
  --out "$work/bad_chol" > /dev/null 2> "$work/bad_chol.err"
echo $? > "$work/bad_chol.rc"
"$exe" bench-solvers "$work/cc_umfpack" --repeat 1 --out "$work/bench.csv" \
  --only umfpack,petsc,petsc:gmres-boomeramg,petsc:gmres-gamg,petsc:gmres-ilu,petsc:mumps-lu,petsc:cg-gamg,petsc:mumps-cholesky \
  > "$work/bench.md" 2> "$work/bench.err"
echo $? > "$work/bench.rc"

/usr/bin/python3 - "$work" "$src" <<'PY'
import csv, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done, summary
w = sys.argv[1]
rc = lambda n: int(open(f"{w}/{n}.rc").read())

ref = summary(w, "cl_cholmod")["metrics"]["tip_uy"]
for name, what in (("cl_petsc", "CG + ICC(0) (default)"), ("cl_gamg", "CG + GAMG"),
                   ("cl_mumps", "MUMPS Cholesky")):
    s = summary(w, name)
    v = s["metrics"]["tip_uy"]
    check(s["status"] == "completed" and s["solver"] == "petsc" and abs(v - ref) <= 1e-8 * abs(ref),
          f"cantilever, {what}: tip_uy {v:.15f} = cholmod's {ref:.15f} to 1e-8")
r3 = summary(w, "cl3_cholmod")["metrics"]["tip_uy"]
s = summary(w, "cl3_gamg")
v = s["metrics"]["tip_uy"]
check(s["status"] == "completed" and abs(v - r3) <= 1e-8 * abs(r3),
      f"3-D slab cantilever, CG + GAMG: tip_uy {v:.15f} = cholmod's {r3:.15f} to 1e-8")
for name, bs in (("cl_gamg", 2), ("cl3_gamg", 3)):
    c = summary(w, name)["counts"]
    check(c.get("solver_block_size") == bs and 0 < c["linear_iterations"] < 120,
          f"{name}: GAMG in blocks of {c.get('solver_block_size')} (expected {bs}) with the "
          f"rigid-body modes, {c['linear_iterations']} CG iterations (< 120)")
check("solver_block_size" not in summary(w, "cl_petsc")["counts"],
      "CG + ICC(0): the free equations only, no block size")
s = summary(w, "cl_petsc")
check(s["counts"]["linear_iterations"] > 0 and s["counts"]["linear_not_converged"] == 0,
      f"cantilever: {s['counts']['linear_iterations']} Krylov iterations counted, none short")

u = summary(w, "cc_umfpack")
check(u["status"] == "completed" and u["counts"]["steps"] == 10,
      f"column collapse, umfpack: {u['status']}, {u['counts']['steps']} steps")
for name, what in (("cc_petsc", "GMRES + ILU(0) (default)"), ("cc_amg", "GMRES + BoomerAMG"),
                   ("cc_mumps", "MUMPS LU")):
    s = summary(w, name)
    ok = s["status"] == "completed" and s["counts"]["steps"] == u["counts"]["steps"]
    for k in ("runout", "height"):
        ok = ok and abs(s["metrics"][k] - u["metrics"][k]) <= 1e-6 * abs(u["metrics"][k])
    check(ok, f"column collapse (unsymmetric tangent), {what}: runout {s['metrics']['runout']:.9f} "
          f"height {s['metrics']['height']:.9f} = umfpack's to 1e-6, {s['counts']['steps']} steps")

s = summary(w, "cc_short")
cuts = s.get("step_cuts", [])
check(rc("cc_short") == 1 and s["status"] == "failed" and len(cuts) == 2 and
      all("DIVERGED_ITS" in c["reason"] for c in cuts) and s["counts"]["linear_not_converged"] == 3,
      f"-ksp_max_it 2: exit {rc('cc_short')}, {len(cuts)} cuts with PETSc's reason, "
      f"{s['counts']['linear_not_converged']} solves counted short; {s['message'][:160]}")
s = summary(w, "cc_breakdown")
cuts = s.get("step_cuts", [])
check(rc("cc_breakdown") == 1 and s["status"] == "failed" and len(cuts) == 1 and
      all("DIVERGED_BREAKDOWN" in c["reason"] and "refine_ifneeded" in c["reason"]
          for c in cuts) and "DIVERGED_BREAKDOWN" in s["message"],
      f"GMRES breakdown at a restart: exit {rc('cc_breakdown')}, {len(cuts)} cut, the reason "
      f"and the remedy in the message; {s['message'][:200]}")

c = summary(w, "cl_cholmod")
s = summary(w, "cl_fallback")
sc, cc_ = s["counts"], c["counts"]
check(s["status"] == "completed" and s["metrics"]["tip_uy"] == ref and
      sc["newton_iterations"] == cc_["newton_iterations"] and
      sc["linear_fallbacks"] == sc["linear_not_converged"] == cc_["factorizations"],
      f"cantilever, CG stopped at 1 iteration, cholmod fallback: tip_uy {s['metrics']['tip_uy']!r} "
      f"= cholmod's {ref!r} to the bit, {sc['linear_fallbacks']} matrices handed over "
      f"({cc_['factorizations']} factorisations in cholmod's run)")
s = summary(w, "cc_fallback")
sc = s["counts"]
ok = s["status"] == "completed" and sc["steps"] == u["counts"]["steps"] and sc["step_cuts"] == 0
for k in ("runout", "height"):
    ok = ok and abs(s["metrics"][k] - u["metrics"][k]) <= 1e-12 * abs(u["metrics"][k])
check(ok and sc["linear_fallbacks"] > 0,
      f"column, GMRES stopped at 2 iterations, umfpack fallback: {s['status']}, {sc['steps']} steps, "
      f"{sc['step_cuts']} cuts, runout {s['metrics']['runout']:.12f} height "
      f"{s['metrics']['height']:.12f} = umfpack's to 1e-12; {sc['linear_fallbacks']} matrices "
      f"handed over, {sc['linear_not_converged']} Krylov solves short")

def bad(name, *words):
    err = open(f"{w}/bad_{name}.err").read()
    check(rc(f"bad_{name}") == 2 and all(x in err for x in words) and "Sanitizer" not in err,
          f"refused ({name}): exit {rc('bad_' + name)}, {err.strip()[:200]}")
bad("typo", "solver.petsc", "did not use -pc_typo")
bad("other", "solver.petsc", "a key of solver.linear \"petsc\", not of solver.linear \"cholmod\"")
bad("chol", "materials.soil.type", "solver.linear_fallback \"cholmod\" needs a symmetric matrix")

check(rc("bench") == 0, f"bench-solvers exits 0 ({rc('bench')}): " + open(f"{w}/bench.err").read()[-300:])
rows = list(csv.DictReader(open(f"{w}/bench.csv")))
num = lambda r, k: float(r[k]) if r[k] else float("nan")
check(rows and all(r["symmetric"] == "0" for r in rows), f"{len(rows)} rows, unsymmetric systems")
for r in rows:
    b = r["backend"]
    if b in ("petsc:cg-gamg", "petsc:mumps-cholesky"):
        check(r["status"] == "not symmetric", f"{r['matrix']} {b}: left out ({r['status']})")
    elif b == "umfpack":
        continue
    elif b == "petsc:mumps-lu":
        check(r["status"] == "ok" and num(r, "diff_ref") <= 1e-8,
              f"{r['matrix']} {b}: UMFPACK's solution to {num(r, 'diff_ref'):.1e} <= 1e-8")
    else:
        check(r["status"] == "ok" and num(r, "residual") <= 1e-10 * 1.001 and int(r["iterations"]) > 0,
              f"{r['matrix']} {b}: |A x - b| / |b| = {num(r, 'residual'):.1e} <= 1e-10 in "
              f"{r['iterations']} iterations (diff {num(r, 'diff_ref'):.1e})")
done()
PY
rc=$?
[ $fail -eq 0 ] && exit $rc || exit 1
