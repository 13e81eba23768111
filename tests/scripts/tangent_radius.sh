#!/usr/bin/env bash
# tangent_radius.sh -- the tangent of smaller clouds (shape.tangent_radius,
# discretisation/skin.c; issue 19).
#
# With a tangent radius the residual still takes every node of each cloud,
# and only K couples fewer nodes: Newton converges to the same answer, to
# its tolerance, with a sparser K and factor. Checked on the coarse GMM-LME
# rolling disk at gamma 0.8 (clouds of about 4.2 h) with the contact set
# checked at convergence only (solver.contact_check 0, so that the caught
# rim points do not depend on the iterates):
#   - a radius larger than every cloud gives the run without one to the bit;
#   - the radius 2 sqrt(2) h gives the answer of the full tangent to 1e-7,
#     with fewer entries in K and in its factor, while the same radius as a
#     cut of the shape functions (shape.radius, a change of the model) moves
#     the answer a thousand times more;
#   - full Newton on the smaller tangent still converges;
#   - a restart from the first step's checkpoint is the run not interrupted;
#   - the same on the GMM-LME column collapse (Mohr-Coulomb: an unsymmetric
#     tangent, UMFPACK), short;
#   - a static run (the cantilever), narrow from its first step: no
#     initial acceleration to solve;
#   - shape.tangent_tol, the radius where the LME weight falls to a
#     tolerance, gives the run of the radius it stands for, to the bit;
# then the refusals: no skin, a negative radius, another method, a
# tolerance with MLS, with a radius, of 1, without the skin.
#
# usage: tangent_radius.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
source "$src/tests/tools/checks.bash"

rd=(run "$src/cases/rolling_disk.json" --quiet --set method=gmm --set shape.kind=lme
    --set shape.gamma=0.8 --set mesh.h=0.05 --set time.dt=0.004 --set time.end=0.2
    --set output.vtk=none --set solver.contact_check=0)
"$exe" "${rd[@]}" --out rd_full > rd_full.log 2>&1
"$exe" "${rd[@]}" --set shape.tangent_radius=100 --out rd_wide > rd_wide.log 2>&1
"$exe" "${rd[@]}" --set shape.tangent_radius=2.8284271247 --out rd_t > rd_t.log 2>&1
"$exe" "${rd[@]}" --set shape.radius=0.1414213562 --out rd_cut > rd_cut.log 2>&1
"$exe" "${rd[@]}" --set shape.tangent_radius=2.8284271247 --set solver.newton=full \
  --out rd_tfull > rd_tfull.log 2>&1

r=$(python3 - <<'PY'
import csv, json
def load(d):  # steps.csv without its wall times
    rows = [{k: v for k, v in r.items() if k != "wall_s"} for r in csv.DictReader(open(f"{d}/steps.csv"))]
    return json.load(open(f"{d}/summary.json")), rows
(f, fs), (w, ws), (t, ts), (c, cs), (n, ns) = (load(d) for d in
    ("rd_full", "rd_wide", "rd_t", "rd_cut", "rd_tfull"))
def gap(a, b):
    return max(abs(x - b["metrics"][k]) / max(abs(x), 1e-12) for k, x in a["metrics"].items())
res = []
same = (f["metrics"] == w["metrics"] and fs == ws
        and f["counts"]["newton_iterations"] == w["counts"]["newton_iterations"])
res.append((same, "a radius wider than the clouds: the same steps.csv and metrics to the bit"
            if same else "a wide radius changed the run"))
ok_status = all(s["status"] == "completed" for s in (f, t, c, n))
res.append((ok_status, f"status {f['status']}/{t['status']}/{c['status']}/{n['status']}"))
gt, gc = gap(f, t), gap(f, c)
res.append((gt < 1e-7, f"tangent radius 2.83 h: metrics within {gt:.1e} of the full tangent's"))
res.append((gc > 1e3 * gt and gc > 1e-5,
            f"shape.radius 2.83 h (the model cut there) moves them by {gc:.1e}"))
cf, ct = f["counts"], t["counts"]
sparser = ct["nnz"] < 0.7 * cf["nnz"] and ct["nnz_factor"] < 0.8 * cf["nnz_factor"]
res.append((sparser, f"K {cf['nnz']} -> {ct['nnz']} entries, factor {cf['nnz_factor']} -> "
            f"{ct['nnz_factor']}, Newton its {cf['newton_iterations']} -> {ct['newton_iterations']}"))
gn = gap(f, n)
res.append((gn < 1e-7, f"full Newton on it: {n['counts']['newton_iterations']} iterations, "
            f"metrics within {gn:.1e}"))
print("\n".join(("OK " if ok else "BAD ") + m for ok, m in res))
PY
)
while IFS= read -r line; do
  case "$line" in OK*) ok "rolling disk, GMM-LME 0.8: ${line#OK }" ;;
                  *) ko "rolling disk, GMM-LME 0.8: ${line#BAD }" ;; esac
done <<< "$r"

# shape.tangent_tol: the radius where the LME weight falls to tol; at
# gamma 0.8, tol exp(-6.4) is the radius 2 sqrt(2) h of rd_t, to the bit
"$exe" "${rd[@]}" --set shape.tangent_tol=0.001661557273173934 --out rd_tol > rd_tol.log 2>&1
r=$(python3 - <<'PY'
import csv, json
(t, ts), (w, ws) = ((json.load(open(f"{d}/summary.json")),
                     [{k: v for k, v in r.items() if k != "wall_s"} for r in csv.DictReader(open(f"{d}/steps.csv"))])
                    for d in ("rd_t", "rd_tol"))
ok = (w["status"] == "completed" and t["metrics"] == w["metrics"] and ts == ws
      and t["counts"]["nnz"] == w["counts"]["nnz"])
print(("OK " if ok else "BAD ") + f"status {w['status']}, K {t['counts']['nnz']} / {w['counts']['nnz']} "
      f"entries, the same steps.csv and metrics: {ok}")
PY
)
case "$r" in OK*) ok "tangent_tol exp(-6.4) at gamma 0.8 is the radius 2 sqrt(2) h: ${r#OK }" ;;
             *) ko "tangent_tol: ${r#BAD }" ;; esac

# a restart from the checkpoint of the first step (whole clouds: it solves
# for the initial acceleration) must narrow the lists at the second step as
# the uninterrupted run does: a failure made on purpose at step 2 stops B
ck=("${rd[@]}" --set time.end=0.04 --set shape.tangent_radius=2.8284271247
    --set output.checkpoint_every=1)
"$exe" "${ck[@]}" --out ck_A > ck_A.log 2>&1
MPGM_TEST_FAULT=nan:2:99 "$exe" "${ck[@]}" --out ck_B > ck_B.log 2>&1
"$exe" run --restart ck_B --quiet > ck_R.log 2>&1
r=$(python3 - <<'PY'
import csv, json
a, b = (json.load(open(f"ck_{k}/summary.json")) for k in "AB")
sa, sb = ([{k: v for k, v in r.items() if k != "wall_s"} for r in csv.DictReader(open(f"ck_{k}/steps.csv"))]
          for k in "AB")
ok = a["status"] == b["status"] == "completed" and a["metrics"] == b["metrics"] and sa == sb
print(("OK " if ok else "BAD ") + f"status {a['status']}/{b['status']}, analyses "
      f"{a['counts']['analyses']}/{b['counts']['analyses']}, same steps.csv and metrics: {ok}")
PY
)
case "$r" in OK*) ok "restart from step 1: ${r#OK }" ;; *) ko "restart from step 1: ${r#BAD }" ;; esac

cc=(run "$src/cases/column_collapse_gmm.json" --quiet --set shape.kind=lme --set mesh.h=0.1
    --set time.dt=0.005 --set time.end=0.2 --set output.vtk=none --set solver.linear=auto --set solver.forcing=fixed)
"$exe" "${cc[@]}" --set shape.tangent_radius=0 --out cc_full > cc_full.log 2>&1
"$exe" "${cc[@]}" --set shape.tangent_radius=2 --out cc_t > cc_t.log 2>&1
r=$(python3 - <<'PY'
import json
f, t = (json.load(open(f"{d}/summary.json")) for d in ("cc_full", "cc_t"))
g = max(abs(x - t["metrics"][k]) / max(abs(x), 1e-12) for k, x in f["metrics"].items())
ok = f["status"] == t["status"] == "completed" and g < 1e-6 and t["counts"]["nnz"] < f["counts"]["nnz"]
print(("OK " if ok else "BAD ") + f"status {f['status']}/{t['status']}, metrics within {g:.1e}, "
      f"K {f['counts']['nnz']} -> {t['counts']['nnz']} entries, solver {t['solver']}")
PY
)
case "$r" in OK*) ok "column collapse, GMM-LME, tangent radius 2 h: ${r#OK }" ;;
             *) ko "column collapse: ${r#BAD }" ;; esac

# a static run has no initial acceleration: the narrow tangent from the
# first step, the same tip
ct=(run "$src/cases/cantilever.json" --quiet --set method=gmm --set shape.kind=lme
    --set shape.gamma=0.8 --set output.vtk=none)
"$exe" "${ct[@]}" --out ct_full > ct_full.log 2>&1
"$exe" "${ct[@]}" --set shape.tangent_radius=3 --out ct_t > ct_t.log 2>&1
r=$(python3 - <<'PY'
import json
f, t = (json.load(open(f"{d}/summary.json")) for d in ("ct_full", "ct_t"))
a, b = f["metrics"]["tip_uy"], t["metrics"]["tip_uy"]
ok = (f["status"] == t["status"] == "completed" and abs(a - b) <= 1e-9 * abs(a)
      and t["counts"]["nnz"] < 0.7 * f["counts"]["nnz"])
print(("OK " if ok else "BAD ") + f"tip {a:.12f} / {b:.12f} m, K {f['counts']['nnz']} -> "
      f"{t['counts']['nnz']} entries from the first step, Newton its "
      f"{f['counts']['newton_iterations']} -> {t['counts']['newton_iterations']}")
PY
)
case "$r" in OK*) ok "static cantilever, GMM-LME 0.8, tangent radius 3 h: ${r#OK }" ;;
             *) ko "static cantilever: ${r#BAD }" ;; esac

expect 2 'shape.tangent_radius' "a tangent radius without the pattern skin is refused" \
  "$exe" run "$src/cases/column_collapse_gmm.json" --set shape.skin=0 \
  --set shape.tangent_radius=0.2 --out bad1
expect 2 'shape.tangent_radius' "a negative tangent radius is refused" \
  "$exe" run "$src/cases/column_collapse_gmm.json" --set shape.tangent_radius=-0.1 --out bad2
expect 2 'shape.tangent_radius' "a tangent radius with method mpm is refused" \
  "$exe" run "$src/cases/column_collapse.json" --set shape.kind=lme \
  --set shape.tangent_radius=0.2 --out bad3

expect 2 'shape.tangent_tol' "a tangent tolerance with MLS is refused" \
  "$exe" run "$src/cases/column_collapse_gmm.json" --set shape.tangent_tol=1e-3 --out bad4
expect 2 'shape.tangent_tol' "a tangent tolerance and a tangent radius together are refused" \
  "$exe" run "$src/cases/column_collapse_gmm.json" --set shape.kind=lme --set shape.tangent_tol=1e-3 \
  --set shape.tangent_radius=2 --out bad5
expect 2 'shape.tangent_tol' "a tangent tolerance of 1 is refused" \
  "$exe" run "$src/cases/column_collapse_gmm.json" --set shape.kind=lme --set shape.tangent_tol=1 --out bad6
expect 2 'shape.tangent_tol' "a tangent tolerance without the pattern skin is refused" \
  "$exe" run "$src/cases/column_collapse_gmm.json" --set shape.kind=lme --set shape.skin=0 \
  --set shape.tangent_tol=1e-3 --out bad7

echo "$npass passed, $nfail failed"
[ "$nfail" -eq 0 ]
