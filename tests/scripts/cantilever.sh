#!/usr/bin/env bash
# Cantilever acceptance (issue 2): tip deflection within 0.5 % of the
# references at h = 0.0625, observed order >= 1.5 between the two finest
# meshes, CHOLMOD and UMFPACK agree to 1e-9.
# usage: cantilever.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
scene="$src/cases/cantilever.json"
fail=0
run() { # name, args...
  local name="$1"; shift
  if ! "$exe" run "$scene" --quiet --set output.vtk=none --out "$work/$name" "$@" > "$work/$name.log" 2>&1; then
    echo "FAIL: run $name ($*) exited non-zero:"; cat "$work/$name.log"; fail=1
  fi
}
for h in 0.25 0.125 0.0625; do run "fin_$h" --set mesh.h=$h; done
run small_0.0625 --set mesh.h=0.0625 --set kinematics=small
run tri_0.0625 --set mesh.h=0.0625 --set mesh.cell=tri
run cholmod --set mesh.h=0.125 --set solver.linear=cholmod
run umfpack --set mesh.h=0.125 --set solver.linear=umfpack
run modified --set mesh.h=0.125 --set solver.linear=cholmod --set solver.newton=modified
[ $fail -eq 0 ] || { echo "0 passed, 1 failed"; exit 1; }
/usr/bin/python3 - "$work" <<'PY'
import json, math, sys
w = sys.argv[1]
def tip(name):
    return json.load(open(f"{w}/{name}/summary.json"))["metrics"]["tip_uy"]
npass = nfail = 0
def check(ok, msg):
    global npass, nfail
    print(("PASS: " if ok else "FAIL: ") + msg)
    npass += ok; nfail += (not ok)
# Reference values (issue 2): converged nonlinear plane strain -0.67437 m,
# linear small strain -0.67803 m. 0.5 % is the issue's acceptance band; Q4
# at h = 0.0625 is ~0.2 % off, so the band is not loose by design.
REF, REF_SMALL = -0.67437, -0.67803
e = {h: abs(tip(f"fin_{h}") - REF) for h in ("0.25", "0.125", "0.0625")}
for h, v in e.items():
    print(f"  h = {h}: tip_uy = {tip('fin_' + h):.6f}, error = {v:.3e}")
rel = e["0.0625"] / abs(REF)
check(rel <= 5e-3, f"finite, Q4, h = 0.0625: |tip_uy - ({REF})| / |ref| = {rel:.4%} <= 0.5 %")
order = math.log(e["0.125"] / e["0.0625"]) / math.log(2.0)
check(order >= 1.5, f"observed order between h = 0.125 and 0.0625: {order:.3f} >= 1.5")
order_c = math.log(e["0.25"] / e["0.125"]) / math.log(2.0)
check(order_c >= 1.5, f"observed order between h = 0.25 and 0.125: {order_c:.3f} >= 1.5")
rs = abs(tip("small_0.0625") - REF_SMALL) / abs(REF_SMALL)
check(rs <= 5e-3, f"small strain, h = 0.0625: tip_uy = {tip('small_0.0625'):.6f}, off by {rs:.4%} <= 0.5 % of {REF_SMALL}")
rt = abs(tip("tri_0.0625") - REF) / abs(REF)
# T3 (linear triangles) are stiffer in bending: the band is wider (2 %), stated here
check(rt <= 2e-2, f"finite, T3, h = 0.0625: tip_uy = {tip('tri_0.0625'):.6f}, off by {rt:.3%} <= 2 %")
a, b = tip("cholmod"), tip("umfpack")
check(abs(a - b) <= 1e-9 * abs(a), f"cholmod {a:.15f} vs umfpack {b:.15f}: rel diff {abs(a-b)/abs(a):.2e} <= 1e-9")
s = json.load(open(f"{w}/cholmod/summary.json"))
c = s["counts"]
check(c["analyses"] == 1 and c["factorizations"] == c["newton_iterations"],
      f"symbolic analysis reused: {c['analyses']} analysis, {c['factorizations']} factorizations for {c['newton_iterations']} Newton iterations")
sm = json.load(open(f"{w}/modified/summary.json"))
d = sm["metrics"]["tip_uy"]
check(abs(d - a) <= 1e-8 * abs(a), f"modified Newton reaches the same tip_uy ({d:.12f} vs {a:.12f})")
check(sm["counts"]["factorizations"] < sm["counts"]["newton_iterations"],
      f"modified Newton: {sm['counts']['factorizations']} factorisations for {sm['counts']['newton_iterations']} iterations")
check(s["solver"] == "cholmod" and json.load(open(f"{w}/umfpack/summary.json"))["solver"] == "umfpack", "solver choice recorded")
print(f"{npass} passed, {nfail} failed")
sys.exit(1 if nfail else 0)
PY
