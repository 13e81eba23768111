#!/usr/bin/env bash
# GMM on the static cantilever (issue 4): node clouds with MLS (linear basis,
# dilation 2) and LME (gamma = 1.8) over the persistent nodes of the mesh,
# points at the 2 x 2 Gauss points of the cells. Acceptance: tip_uy within
# 1 % of -0.67437 m at h = 0.0625 for both kinds, and the error falls from
# h = 0.125 to 0.0625. Ten load steps (clouds searched again on moved nodes,
# LME warm starts) must reach the same answer. Counters and the time split
# of the search and the shape functions are in summary.json; no NaN.
# usage: gmm_cantilever.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
scene="$src/cases/cantilever.json"
fail=0
source "$src/tests/tools/run_case.bash"
run() { local name="$1"; shift; run_case "$name" "$scene" --set method=gmm "$@"; }
for h in 0.125 0.0625; do
  run "mls_$h" --set shape.kind=mls --set mesh.h=$h
  run "lme_$h" --set shape.kind=lme --set shape.gamma=1.8 --set mesh.h=$h
done
run lme_steps --set shape.kind=lme --set mesh.h=0.125 --set time.load_steps=10
run mls_steps --set shape.kind=mls --set mesh.h=0.125 --set time.load_steps=10
[ $fail -eq 0 ] || { echo "0 passed, 1 failed"; exit 1; }
/usr/bin/python3 - "$work" "$src" <<'PY'
import json, math, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done, finite, summary
w = sys.argv[1]
S = lambda n: summary(w, n)
REF = -0.67437
for kind in ("mls", "lme"):
    e = {}
    for h in ("0.125", "0.0625"):
        s = S(f"{kind}_{h}")
        t = s["metrics"]["tip_uy"]
        e[h] = abs(t - REF)
        c, ts = s["counts"], s["time_s"]
        print(f"  {kind} h = {h}: tip_uy = {t:.6f} ({e[h] / abs(REF):.4%}), nodes {c['nodes']}, "
              f"nnz {c['nnz']}, radius_growths {c['radius_growths']}, cloud_enlargements "
              f"{c['cloud_enlargements']}; search {ts['search']:.4f} s, shape {ts['shape']:.4f} s")
        check(s["status"] == "completed" and s["method"] == "gmm" and s["shape"] == kind,
              f"{kind} h = {h}: completed, method gmm and shape {kind} recorded")
        check(all(k in c for k in ("radius_growths", "cloud_enlargements", "shape_cold_restarts"))
              and "search" in ts and "shape" in ts and ts["search"] >= 0 and ts["shape"] > 0,
              f"{kind} h = {h}: counts radius_growths, cloud_enlargements, shape_cold_restarts and "
              f"times search, shape in summary.json")
        check(finite(s["metrics"]) and finite(s["probes"]) and finite(s["newton_last_step"]),
              f"{kind} h = {h}: no NaN or Inf in metrics, probes, Newton statistics")
        check(abs(s["metrics"]["mass_total"] - 8000.0) <= 1e-9 * 8000.0,
              f"{kind} h = {h}: mass {s['metrics']['mass_total']} (8000 kg)")
    # 1 % is the issue's acceptance band (the paper's Fig. 7: GMM-MLS on the
    # FEM curve, GMM-LME slightly above); measured 0.002 % (MLS) and 0.017 %
    # (LME) at h = 0.0625
    rel = e["0.0625"] / abs(REF)
    check(rel <= 1e-2, f"{kind} h = 0.0625: |tip_uy - ({REF})| / |ref| = {rel:.4%} <= 1 %")
    check(e["0.0625"] < e["0.125"], f"{kind}: error falls from h = 0.125 ({e['0.125']:.3e}) to "
          f"0.0625 ({e['0.0625']:.3e})")
for kind in ("mls", "lme"):
    s, one = S(f"{kind}_steps"), S(f"{kind}_0.125")
    t, t1 = s["metrics"]["tip_uy"], one["metrics"]["tip_uy"]
    c = s["counts"]
    # ten load steps reach the same equilibrium as one (a hyperelastic
    # material; the clouds differ between steps only where nodes cross a
    # support radius): measured 9e-7 (MLS) and 1.6e-6 (LME) relative
    check(s["status"] == "completed" and c["steps"] == 10 and abs(t - t1) <= 1e-4 * abs(t1),
          f"{kind}, 10 load steps: tip_uy {t:.7f} vs one step {t1:.7f} (rel {abs(t - t1) / abs(t1):.1e} "
          f"<= 1e-4); {c['analyses']} pattern analyses, {c['shape_cold_restarts']} LME cold restarts")
done()
PY
