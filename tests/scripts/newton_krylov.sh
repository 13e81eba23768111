#!/usr/bin/env bash
# Newton-Krylov with factor reuse and Eisenstat-Walker forcing (issue 19,
# item 2):
#   - the cantilever in 2 load steps: solver.newton "krylov" (GMRES on each
#     tangent, preconditioned by the last factorisation) gives full
#     Newton's tip to 1e-8 with as many Newton iterations and fewer
#     factorisations, the rest counted as reused; with the forcing term the
#     tip agrees to 1e-6 (the solves are inexact) in at most one more
#     Newton iteration per step;
#   - the column collapse, coarse and short (MPM, Mohr-Coulomb: an
#     unsymmetric tangent): Newton-Krylov with forcing, and PETSc's GMRES +
#     ILU(0) (solver.linear petsc's default there) with forcing, give UMFPACK's runout and height to 1e-6; Newton stays
#     quadratic in the last (plastic) step; the forcing takes fewer Krylov
#     iterations than solving every system to 1e-10;
#   - UL-FEM (the pattern stays): one factorisation serves several steps;
#   - "krylov" with an iterative solver.linear is refused.
# usage: newton_krylov.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail=0
source "$src/tests/tools/run_case.bash"
cl="$src/cases/cantilever.json"
cc="$src/cases/column_collapse.json"
# the column case ships PETSc with the forcing term; these runs compare the
# direct path (auto: UMFPACK), fixed tolerances and the forcing term
coarse=(--set mesh.h=0.1 --set time.dt=0.01 --set time.end=0.2 --set solver.linear=auto --set solver.forcing=fixed)
ew=(--set solver.forcing=eisenstat_walker)
run_case cl_full "$cl" --set time.load_steps=2
run_case cl_krylov "$cl" --set time.load_steps=2 --set solver.newton=krylov
run_case cl_krylov_ew "$cl" --set time.load_steps=2 --set solver.newton=krylov "${ew[@]}"
run_case cc_full "$cc" "${coarse[@]}"
run_case cc_krylov "$cc" "${coarse[@]}" --set solver.newton=krylov "${ew[@]}"
run_case cc_petsc "$cc" "${coarse[@]}" --set solver.linear=petsc
run_case cc_petsc_ew "$cc" "${coarse[@]}" --set solver.linear=petsc "${ew[@]}"
run_case fem_krylov "$cc" --set method=fem --set mesh.h=0.2 --set time.end=0.2 --set solver.linear=auto \
  --set 'boundaries=[{"x":0,"condition":"slip"},{"y":0,"condition":"stick"}]' \
  --set solver.newton=krylov "${ew[@]}"
"$exe" check "$cl" --set solver.newton=krylov --set solver.linear=petsc > /dev/null 2> "$work/bad.err"
echo $? > "$work/bad.rc"

/usr/bin/python3 - "$work" "$src" <<'PY'
import math, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done, summary
w = sys.argv[1]
full, kr, ew = summary(w, "cl_full"), summary(w, "cl_krylov"), summary(w, "cl_krylov_ew")
t0 = full["metrics"]["tip_uy"]
cf, ck, ce = full["counts"], kr["counts"], ew["counts"]
check(kr["status"] == "completed" and abs(kr["metrics"]["tip_uy"] - t0) <= 1e-8 * abs(t0) and
      ck["newton_iterations"] == cf["newton_iterations"],
      f"cantilever, krylov: tip_uy {kr['metrics']['tip_uy']:.12f} = full Newton's {t0:.12f} to 1e-8, "
      f"{ck['newton_iterations']} Newton iterations ({cf['newton_iterations']})")
check(ck["factorizations"] < cf["factorizations"] and
      ck["factorizations"] + ck["factor_reuses"] == ck["newton_iterations"] and ck["linear_iterations"] > 0,
      f"cantilever, krylov: {ck['factorizations']} factorisations (full Newton {cf['factorizations']}), "
      f"{ck['factor_reuses']} reused, {ck['linear_iterations']} GMRES iterations")
check(ew["status"] == "completed" and abs(ew["metrics"]["tip_uy"] - t0) <= 1e-6 * abs(t0) and
      ce["newton_iterations"] <= cf["newton_iterations"] + 2,
      f"cantilever, krylov + forcing: tip_uy {ew['metrics']['tip_uy']:.12f} to 1e-6, "
      f"{ce['newton_iterations']} Newton iterations (at most {cf['newton_iterations']} + 2)")

u = summary(w, "cc_full")
for name, what in (("cc_krylov", "Newton-Krylov + forcing"), ("cc_petsc_ew", "GMRES + ILU(0) + forcing")):
    s = summary(w, name)
    ok = s["status"] == "completed"
    for k in ("runout", "height"):
        ok = ok and abs(s["metrics"][k] - u["metrics"][k]) <= 1e-6 * abs(u["metrics"][k])
    check(ok, f"column collapse, {what}: runout {s['metrics']['runout']:.9f} height "
          f"{s['metrics']['height']:.9f} = UMFPACK's to 1e-6 ({s['counts']['steps']} steps, "
          f"{s['counts']['step_cuts']} cuts)")
    r = s["newton_last_step"]["residuals"]
    ref = max(r[0], 1e-300)
    rates = [math.log(r[k + 1] / ref) / math.log(r[k] / ref)
             for k in range(len(r) - 1) if r[k] / ref < 1e-2 and r[k + 1] / ref > 1e-12]
    check(rates and max(rates) >= 1.8,
          f"column collapse, {what}: Newton in the last step: |R|/ref = "
          f"{', '.join(f'{x / ref:.2e}' for x in r)}; rates {', '.join(f'{x:.2f}' for x in rates)} (>= 1.8)")
g, ge = summary(w, "cc_petsc")["counts"], summary(w, "cc_petsc_ew")["counts"]
check(ge["linear_iterations"] < g["linear_iterations"],
      f"column collapse, GMRES + ILU(0): {ge['linear_iterations']} Krylov iterations with the forcing "
      f"term, {g['linear_iterations']} solving every system to 1e-10")
k = summary(w, "cc_krylov")["counts"]
check(k["factor_reuses"] > 0, f"column collapse, krylov: {k['factorizations']} factorisations, "
      f"{k['factor_reuses']} reused")
f = summary(w, "fem_krylov")
fc = f["counts"]
check(f["status"] == "completed" and fc["factorizations"] < fc["steps"],
      f"UL-FEM column, krylov: {fc['factorizations']} factorisations for {fc['steps']} steps and "
      f"{fc['newton_iterations']} Newton iterations: the pattern stays and one serves several steps")
err = open(f"{w}/bad.err").read()
rc = int(open(f"{w}/bad.rc").read())
check(rc == 2 and "solver.newton" in err and "direct" in err, f"krylov with petsc refused: exit {rc}, {err.strip()[:160]}")
done()
PY
rc=$?
[ $fail -eq 0 ] && exit $rc || exit 1
