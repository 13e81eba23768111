#!/usr/bin/env bash
# skin.sh -- sparsity patterns kept across steps for node clouds
# (shape.skin, discretisation/skin.c; issue 19, item 3).
#
# The pattern built from lists a skin wider than the clouds holds every
# coupling of the clouds, so the tangent is the same up to explicit zeros:
# with full Newton each step must take the same iterations with the same
# residuals (a coupling missing from the pattern would be dropped from K
# and change them), and the answer must agree to round-off, while fewer
# patterns are analysed (counts.analyses) and patterns_kept counts the
# steps that kept theirs. Cases: the GMM-MLS column collapse (rectangle
# bodies, Mohr-Coulomb, unsymmetric: UMFPACK), and the GMM-LME rolling disk
# (bodies filled on the grid: light nodes parked, so equations renumber
# over a kept node graph; contact at surface points; CHOLMOD), coarse.
# Then the refusals: a skin with another method, a negative skin.
#
# usage: skin.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"; cd "$work" || exit 1
source "$src/tests/tools/checks.bash"

# compare NAME: runs NAME_0 (no skin: shape.skin 0) and NAME_s (a skin)
compare() {
  python3 - "$1" <<'PY'
import csv, json, sys
n = sys.argv[1]
a, b = (json.load(open(f"{n}_{k}/summary.json")) for k in ("0", "s"))
sa, sb = (list(csv.DictReader(open(f"{n}_{k}/steps.csv"))) for k in ("0", "s"))
out = []
ok = a["status"] == b["status"] == "completed" and len(sa) == len(sb)
out.append(f"status {a['status']}/{b['status']}, steps {len(sa)}/{len(sb)}")
its = [int(r["newton_iterations"]) for r in sa] == [int(r["newton_iterations"]) for r in sb]
ok &= its
out.append("same Newton iterations every step" if its else "Newton iterations differ")
worst = 0.0
for ra, rb in zip(sa, sb):
    for k in ("residual_initial", "kinetic_energy"):
        x, y = float(ra[k]), float(rb[k])
        worst = max(worst, abs(x - y) / max(abs(x), 1e-300))
ok &= worst < 1e-6
out.append(f"steps.csv residual_initial, kinetic_energy agree to {worst:.1e}")
mw = 0.0
for k, x in a["metrics"].items():
    y = b["metrics"][k]
    mw = max(mw, abs(x - y) / max(abs(x), 1e-12))
ok &= mw < 1e-8
out.append(f"metrics agree to {mw:.1e}")
ca, cb = a["counts"], b["counts"]
fewer = cb["analyses"] < ca["analyses"] and cb["patterns_kept"] > 0 and ca["patterns_kept"] == 0
ok &= fewer
out.append(f"analyses {ca['analyses']} -> {cb['analyses']}, patterns_kept {cb['patterns_kept']}, "
           f"nnz {ca['nnz']} -> {cb['nnz']}")
print(("OK " if ok else "BAD ") + "; ".join(out))
PY
}

cc=(run "$src/cases/column_collapse_gmm.json" --quiet --set mesh.h=0.1 --set time.dt=0.005 --set time.end=0.3
    --set output.vtk=none --set solver.newton=full)
"$exe" "${cc[@]}" --set shape.skin=0 --out cc_0 > cc_0.log 2>&1
# a thin skin, so that the lists are built again several times (6 in 60
# steps): a kept list that missed a cloud would show here
"$exe" "${cc[@]}" --set shape.skin=0.05 --out cc_s > cc_s.log 2>&1
r=$(compare cc)
case "$r" in OK*) ok "column collapse, GMM-MLS, skin 0.05 h: ${r#OK }" ;; *) ko "column collapse: ${r#BAD }" ;; esac

rd=(run "$src/cases/rolling_disk.json" --quiet --set method=gmm --set shape.kind=lme
    --set mesh.h=0.05 --set time.dt=0.004 --set time.end=0.2 --set output.vtk=none
    --set solver.newton=full)
"$exe" "${rd[@]}" --set shape.skin=0 --out rd_0 > rd_0.log 2>&1
"$exe" "${rd[@]}" --set shape.skin=0.25 --out rd_s > rd_s.log 2>&1
r=$(compare rd)
case "$r" in OK*) ok "rolling disk, GMM-LME, skin 0.25 h: ${r#OK }" ;; *) ko "rolling disk: ${r#BAD }" ;; esac

expect 2 'shape.skin' "a skin with method mpm is refused" \
  "$exe" run "$src/cases/column_collapse.json" --set shape.kind=lme --set shape.skin=0.2 --out bad1
expect 2 'shape.skin' "a negative skin is refused" \
  "$exe" run "$src/cases/column_collapse_gmm.json" --set shape.skin=-0.1 --out bad2

echo "$npass passed, $nfail failed"
[ "$nfail" -eq 0 ]
