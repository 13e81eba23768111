#!/usr/bin/env bash
# MPM on the static cantilever (issue 3): with one load step and particles at
# the Gauss points of a grid aligned with the beam, MPM and FEM build the same
# algebra, so tip_uy agrees to 1e-9; with 10 load steps (grid reset between
# steps) MPM stays within 0.5 % of -0.67437 m at h = 0.0625.
# usage: mpm_cantilever.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
scene="$src/cases/cantilever.json"
fail=0
source "$src/tests/tools/run_case.bash"
run() { local name="$1"; shift; run_case "$name" "$scene" "$@"; }
for cell in quad tri; do
  run "fem_$cell" --set mesh.h=0.0625 --set mesh.cell=$cell
  run "mpm_$cell" --set mesh.h=0.0625 --set mesh.cell=$cell --set method=mpm
done
run mpm_steps --set mesh.h=0.0625 --set method=mpm --set time.load_steps=10
[ $fail -eq 0 ] || { echo "0 passed, 1 failed"; exit 1; }
/usr/bin/python3 - "$work" "$src" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done, finite, summary
w = sys.argv[1]
S = lambda n: summary(w, n)
for cell in ("quad", "tri"):
    f, m = S(f"fem_{cell}"), S(f"mpm_{cell}")
    a, b = f["metrics"]["tip_uy"], m["metrics"]["tip_uy"]
    check(m["method"] == "mpm" and f["method"] == "fem", f"{cell}: methods recorded")
    check(f["counts"]["points"] == m["counts"]["points"] and f["counts"]["dofs"] == m["counts"]["dofs"],
          f"{cell}: same points ({m['counts']['points']}) and equations ({m['counts']['dofs']})")
    # identical quadrature and shape functions: only round-off (equation
    # order differs) separates them
    check(abs(a - b) <= 1e-9 * abs(a), f"{cell}: one load step, MPM tip_uy {b:.15f} vs FEM {a:.15f}: rel diff {abs(a-b)/abs(a):.2e} <= 1e-9")
s = S("mpm_steps")
t = s["metrics"]["tip_uy"]
rel = abs(t + 0.67437) / 0.67437
check(s["counts"]["steps"] == 10 and s["counts"]["analyses"] >= 1, f"10 load steps, {s['counts']['analyses']} pattern analyses (grid reset every step)")
# 0.5 % is the issue's band; MPM with 10 resets measures about 0.2 % here
check(rel <= 5e-3, f"MPM, 10 load steps, h = 0.0625: tip_uy = {t:.6f}, {rel:.3%} from -0.67437 (<= 0.5 %)")
check(abs(s["metrics"]["mass_total"] - 8000.0) <= 1e-9 * 8000.0, f"mass conserved: {s['metrics']['mass_total']}")
done()
PY
