#!/usr/bin/env bash
# solver.newton "bfgs" (core/bfgs.c): modified Newton whose corrections
# with the kept factorisation are improved by BFGS updates of the
# iterations since it was made.
#   - The cantilever in one load step, the factorisation kept while |R|
#     falls by 0.9 per iteration (reuse_ratio 0.9). Plain modified Newton
#     used to run out of its 25 iterations at |R|/ref ~ 1e-6 (the kept
#     tangent is that of the straight beam, |R| falling by about 0.76 per
#     iteration); now, with 4 iterations left and the tolerance out of
#     reach at that rate, it renews the factorisation (core/newton.c
#     keep_factor; counts.factor_renewals) and completes at full Newton's
#     tip deflection (1e-8). BFGS converges in at most 10 iterations with
#     fewer factorisations than full Newton, to the same tip: the updates
#     are of the right sign and size, and pairs were counted
#     (counts.bfgs_updates). With one pair kept (solver.bfgs_pairs
#     1) the ring drops its oldest pair at every further update, and the
#     iteration still converges to the same tip; 0 pairs is refused.
#   - The rolling disk, GMM-LME, coarse (contact at rim points: re-solves
#     after contact changes, H_0 with the contact changes on the kept
#     factorisation): the same error (67) as modified Newton to 1e-3
#     relative (the contact set is checked at other iterates) in fewer
#     Newton iterations.
#   - The column collapse, MPM, coarse (Mohr-Coulomb: an unsymmetric,
#     piecewise smooth tangent, where pairs without curvature are skipped):
#     the same runout and height as full Newton to 1e-8.
# usage: bfgs.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail=0
source "$src/tests/tools/run_case.bash"
cl="$src/cases/cantilever.json"
rd="$src/cases/rolling_disk.json"
cc="$src/cases/column_collapse.json"
run_case cl_full "$cl"
run_case cl_bfgs "$cl" --set solver.newton=bfgs --set solver.reuse_ratio=0.9
run_case cl_bfgs1 "$cl" --set solver.newton=bfgs --set solver.reuse_ratio=0.9 --set solver.bfgs_pairs=1
"$exe" check "$cl" --set solver.newton=bfgs --set solver.bfgs_pairs=0 > /dev/null 2> "$work/bad.err"
echo $? > "$work/bad.rc"
run_case cl_modified "$cl" --set solver.newton=modified --set solver.reuse_ratio=0.9
disk=(--set method=gmm --set shape.kind=lme --set shape.gamma=1.8 --set mesh.h=0.02 --set time.dt=0.004
      --set time.end=0.2)
run_case rd_modified "$rd" "${disk[@]}" --set solver.newton=modified
run_case rd_bfgs "$rd" "${disk[@]}" --set solver.newton=bfgs
col=(--set mesh.h=0.1 --set time.dt=0.01 --set time.end=0.2 --set solver.linear=auto)
run_case cc_full "$cc" "${col[@]}"
run_case cc_bfgs "$cc" "${col[@]}" --set solver.newton=bfgs

/usr/bin/python3 - "$work" "$src" <<'PY'
import sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done, summary
w = sys.argv[1]
f, b, m = summary(w, "cl_full"), summary(w, "cl_bfgs"), summary(w, "cl_modified")
cf, cb, cm = f["counts"], b["counts"], m["counts"]
t0, t1 = f["metrics"]["tip_uy"], b["metrics"]["tip_uy"]
tm = m["metrics"]["tip_uy"] if m["status"] == "completed" else float("nan")
check(m["status"] == "completed" and abs(tm - t0) <= 1e-8 * abs(t0) and cm["factor_renewals"] >= 1 and
      cm["newton_iterations"] <= 25,
      f"cantilever, modified Newton, reuse_ratio 0.9: {m['status']}, tip_uy {tm:.12f} = full Newton's to 1e-8, "
      f"{cm['newton_iterations']} iterations, {cm['factorizations']} factorisations, "
      f"{cm.get('factor_renewals')} renewed in the last iterations (>= 1)")
check(b["status"] == "completed" and abs(t1 - t0) <= 1e-8 * abs(t0),
      f"cantilever, bfgs: tip_uy {t1:.12f} = full Newton's {t0:.12f} to 1e-8")
check(cb["newton_iterations"] <= 10 and cb["factorizations"] < cf["factorizations"] and cb["bfgs_updates"] > 0,
      f"cantilever, bfgs: {cb['newton_iterations']} iterations (<= 10), {cb['factorizations']} factorisations "
      f"(full Newton {cf['factorizations']}), {cb['bfgs_updates']} updates")
b1 = summary(w, "cl_bfgs1")
c1 = b1["counts"]
check(b1["status"] == "completed" and abs(b1["metrics"]["tip_uy"] - t0) <= 1e-8 * abs(t0) and
      c1["newton_iterations"] <= 10 and c1["bfgs_updates"] > c1["factorizations"],
      f"cantilever, bfgs, one pair kept: tip_uy {b1['metrics']['tip_uy']:.12f}, {c1['newton_iterations']} "
      f"iterations, {c1['bfgs_updates']} updates in {c1['factorizations']} factorisations' windows "
      f"(more updates than windows: the ring dropped its oldest pair)")
err, brc = open(f"{w}/bad.err").read(), int(open(f"{w}/bad.rc").read())
check(brc == 2 and "solver.bfgs_pairs" in err and "[1, 64]" in err,
      f"bfgs_pairs 0 refused: exit {brc}, {err.strip()[:120]}")
check(cf["bfgs_updates"] == 0, f"cantilever, full Newton: no updates counted ({cf['bfgs_updates']})")
rm, rb = summary(w, "rd_modified"), summary(w, "rd_bfgs")
e0, e1 = rm["metrics"]["error"], rb["metrics"]["error"]
check(rb["status"] == "completed" and abs(e1 - e0) <= 1e-3 * e0 and rb["counts"]["contact_resolves"] > 0,
      f"rolling disk, GMM-LME, bfgs: error {e1:.9f} = modified Newton's {e0:.9f} to 1e-3, "
      f"{rb['counts']['contact_resolves']} contact re-solves")
check(rb["counts"]["newton_iterations"] < rm["counts"]["newton_iterations"] and rb["counts"]["bfgs_updates"] > 0,
      f"rolling disk, bfgs: {rb['counts']['newton_iterations']} Newton iterations against modified Newton's "
      f"{rm['counts']['newton_iterations']}; {rb['counts']['bfgs_updates']} updates")
cf, cb = summary(w, "cc_full"), summary(w, "cc_bfgs")
ok = cb["status"] == "completed" and cb["counts"]["bfgs_updates"] > 0
for k in ("runout", "height"):
    ok = ok and abs(cb["metrics"][k] - cf["metrics"][k]) <= 1e-8 * cf["metrics"][k]
check(ok, f"column collapse (unsymmetric), bfgs: runout {cb['metrics']['runout']:.10f} height "
      f"{cb['metrics']['height']:.10f} = full Newton's to 1e-8; {cb['counts']['bfgs_updates']} updates")
done()
PY
rc=$?
[ $fail -eq 0 ] && exit $rc || exit 1
