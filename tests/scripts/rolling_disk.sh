#!/usr/bin/env bash
# Rolling disk (issue 3), coarse: h = 0.05, dt = 0.01, T = 0.3 s.
# - contact floor: the disk rolls; its centre follows s_ref = g sin(a) t^2 / 3
#   within a coarse-grid band (see the tolerances below);
# - slip floor: frictionless sliding, s = g sin(a) t^2 / 2 (minus the Newmark
#   start-up lag of a_0 = 0);
# mass is conserved in both.
# usage: rolling_disk.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
coarse=(--quiet --set mesh.h=0.05 --set time.dt=0.01 --set time.end=0.3 --set output.vtk=none)
fail=0
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" --out "$work/roll" > "$work/roll.log" 2>&1 || { cat "$work/roll.log"; fail=1; }
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" --set 'boundaries=[{"y":0,"condition":"slip"}]' \
  --out "$work/slip" > "$work/slip.log" 2>&1 || { cat "$work/slip.log"; fail=1; }
[ $fail -eq 0 ] || { echo "0 passed, 1 failed"; exit 1; }
/usr/bin/python3 - "$work" <<'PY'
import json, math, sys
w = sys.argv[1]
npass = nfail = 0
def check(ok, msg):
    global npass, nfail
    print(("PASS: " if ok else "FAIL: ") + msg); npass += ok; nfail += (not ok)
g, a, T, dt = 9.81, math.radians(60.0), 0.3, 0.01
r = json.load(open(f"{w}/roll/summary.json")); m = r["metrics"]
check(r["effects"]["contact"] and r["counts"]["contact_resolves"] > 0,
      f"contact floor: nodes released where the disk lifts ({r['counts']['contact_resolves']} re-solves)")
# Coarse grid: every particle of the bottom cell row (|x - x_c| < sqrt(2 R h)
# = 0.22 m) interpolates from floor nodes, which delays rolling. Measured here:
# s_final 17 % below s_ref, max horizontal deviation 0.021 m; the bounds leave
# a margin of about 1.5x and fail if the disk sticks (s_final ~ 0) or slides
# (s = 1.5 s_ref).
check(m["s_final"] > 0.75 * m["s_ref_final"] and m["s_final"] < 1.1 * m["s_ref_final"],
      f"rolls: s(0.3 s) = {m['s_final']:.4f} m against s_ref = {m['s_ref_final']:.4f} m (within -25 %/+10 %)")
check(m["error_max"] < 0.03, f"centre follows the analytic curve: max |u_ref - u| = {m['error_max']:.4f} m < 0.03 m")
check(abs(m["mass_total"] - 6123.0) < 1e-9 * 6123.0, f"mass conserved ({m['mass_total']})")
s = json.load(open(f"{w}/slip/summary.json"))["metrics"]
# Newmark with a_0 = 0 lags the exact solution by g sin(a) dt t / 2 (theory.md)
s_exact = 0.5 * g * math.sin(a) * T * T - 0.5 * g * math.sin(a) * dt * T
check(abs(s["centre_ux"] - s_exact) < 2e-3 * s_exact,
      f"slip floor: frictionless slide s = {s['centre_ux']:.5f} m vs {s_exact:.5f} m (0.2 %)")
check(abs(s["centre_uy"]) < 1e-3, f"slip floor: the disk stays on the plane (uy = {s['centre_uy']:.2e} m)")
print(f"{npass} passed, {nfail} failed")
sys.exit(1 if nfail else 0)
PY
