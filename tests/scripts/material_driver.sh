#!/usr/bin/env bash
# `mpgm material` (docs/material-driver.md): triaxial compression of the
# Mohr-Coulomb material (phi = 25 deg, c = 5 kPa, confining 50 kPa) fails
# at the analytic axial stress (compression-positive magnitudes)
#   sigma_1 = sigma_3 (1 + sin phi)/(1 - sin phi) + 2 c cos phi/(1 - sin phi),
# the tangent check column stays at finite-difference level, and bad inputs
# exit 2 naming the JSON path.
# usage: material_driver.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
in="$src/tests/material_driver"
fail=0
for k in triaxial_small triaxial_finite shear_path; do
  "$exe" material "$in/$k.json" --out "$work/$k.csv" > "$work/$k.log" 2>&1 \
    || { echo "FAIL: mpgm material $k.json"; cat "$work/$k.log"; fail=1; }
done
# bad inputs: exit 2 and a message that names the file and the JSON path
bad() { # NAME EXPECTED_TEXT JSON
  printf '%s\n' "$3" > "$work/$1.json"
  "$exe" material "$work/$1.json" --out "$work/$1.csv" > "$work/$1.out" 2> "$work/$1.err"
  local rc=$?
  if [ $rc -eq 2 ] && grep -qF "$1.json: $2" "$work/$1.err"; then
    echo "PASS: bad input $1: exit 2, \"$(cat "$work/$1.err")\""
  else
    echo "FAIL: bad input $1: exit $rc, stderr: $(cat "$work/$1.err") (expected \"$2\")"; fail=1
  fi
}
M='"material": {"type": "mohr_coulomb", "density": 1850, "E": 1.8e6, "nu": 0.3, "c": 5000, "phi": 25'
bad psi_above_phi 'material: mohr_coulomb: need' "{$M, \"psi\": 30}, \"triaxial\": {\"confining\": 5e4, \"axial_strain\": 0.1, \"steps\": 5}}"
bad missing_cohesion 'material.c: required key is missing' '{"material": {"type": "mohr_coulomb", "density": 1850, "E": 1.8e6, "nu": 0.3, "phi": 25}, "triaxial": {"confining": 5e4, "axial_strain": 0.1, "steps": 5}}'
bad unknown_type 'material.type: expected "linear_elastic" | "neo_hookean" | "mohr_coulomb", found "cam_clay"' '{"material": {"type": "cam_clay", "density": 1850}, "path": [{"F": [[1, 0], [0, 1]], "steps": 1}]}'
bad no_path 'path: expected exactly one of "path" and "triaxial", found neither' "{$M}}"
bad both_paths 'path: expected exactly one of "path" and "triaxial", found both' "{$M}, \"path\": [{\"F\": [[1, 0], [0, 1]], \"steps\": 1}], \"triaxial\": {\"confining\": 5e4, \"axial_strain\": 0.1, \"steps\": 5}}"
bad short_F 'path.0.F.1: expected an array of 2 numbers' "{$M}, \"path\": [{\"F\": [[1, 0], [0]], \"steps\": 3}]}"
bad inverted_F 'path.0.F: expected det F > 0' "{$M}, \"path\": [{\"F\": [[1, 0], [0, -1]], \"steps\": 3}]}"
bad zero_steps 'path.0.steps: ' "{$M}, \"path\": [{\"F\": [[1, 0], [0, 1]], \"steps\": 0}]}"
bad unknown_key 'extra: unknown key' "{$M}, \"path\": [{\"F\": [[1, 0], [0, 1]], \"steps\": 1}], \"extra\": 1}"
bad bad_kinematics 'kinematics: expected "finite" | "small", found "large"' "{$M}, \"kinematics\": \"large\", \"path\": [{\"F\": [[1, 0], [0, 1]], \"steps\": 1}]}"
bad stress_outside 'initial_stress: mohr_coulomb: initial stress (0, -400000, 0, 0) Pa lies outside the yield surface' "{$M}, \"initial_stress\": [0, -4e5, 0, 0], \"path\": [{\"F\": [[1, 0], [0, 1]], \"steps\": 1}]}"
bad elastic_prestress 'triaxial.confining: material "neo_hookean" cannot start from an initial stress' '{"material": {"type": "neo_hookean", "density": 1850, "E": 1.8e6, "nu": 0.3}, "triaxial": {"confining": 1e4, "axial_strain": 0.1, "steps": 5}}'
bad truncated 'line 2, column 1: JSON syntax error' '{"material": {"type": "neo_hookean"'
[ $fail -eq 0 ] || { echo "0 passed, 1 failed"; exit 1; }
/usr/bin/python3 - "$work" "$src" <<'PY'
import csv, math, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done
w = sys.argv[1]
phi, c, pc = math.radians(25.0), 5000.0, 50000.0
s = math.sin(phi)
k, sc = (1 + s) / (1 - s), 2 * c * math.cos(phi) / (1 - s)
analytic = pc * k + sc
def rows(name):
    return [{key: float(v) for key, v in r.items()} for r in csv.DictReader(open(f"{w}/{name}.csv"))]
for name in ("triaxial_small", "triaxial_finite"):
    R = rows(name)
    check(len(R) == 51, f"{name}: 51 rows (step 0 and 50 increments), found {len(R)}")
    lat = max(abs(r["sigma_xx"] + pc) for r in R)
    # Newton on F11 stops at 1e-12 of the stress scale
    check(lat <= 1e-12 * analytic, f"{name}: sigma_xx held at -{pc:g} Pa (max deviation {lat:.2e} Pa)")
    i = max(range(len(R)), key=lambda i: -R[i]["sigma_yy"])
    r = R[i]
    peak = -r["sigma_yy"]
    J = r["F11"] * r["F22"]
    # small strain: the analytic value itself. Finite strain: the yield
    # condition holds for the Kirchhoff stress tau = J sigma, so with the
    # Cauchy confining stress held the Cauchy peak is k pc + sc / J.
    expect = analytic if name == "triaxial_small" else k * pc + sc / J
    # 1e-12: the return is closed-form, only round-off separates them
    check(abs(peak - expect) <= 1e-12 * expect,
          f"{name}: peak axial stress {peak:.10f} Pa = {expect:.10f} Pa (rel err {abs(peak - expect) / expect:.1e} <= 1e-12; "
          f"analytic sigma_3 k + 2c cos phi/(1 - sin phi) = {analytic:.6f} Pa)")
    check(R[-1]["eps_p"] > 0.05 and R[0]["eps_p"] == 0.0 and all(R[j + 1]["eps_p"] >= R[j]["eps_p"] for j in range(len(R) - 1)),
          f"{name}: eps_p from 0 to {R[-1]['eps_p']:.4f}, never decreasing")
    check(abs(R[-1]["yield"]) <= 1e-12 * analytic, f"{name}: on the yield surface at the end (f = {R[-1]['yield']:.2e} Pa)")
    check(r["sigma_yy"] < r["sigma_zz"] < r["sigma_xx"],
          f"{name}: sigma_zz ({r['sigma_zz']:.1f} Pa) is the intermediate stress at the peak, so the lateral and axial stresses are sigma_1 and sigma_3")
for name in ("triaxial_small", "triaxial_finite", "shear_path"):
    R = rows(name)
    t = max(r["tangent_check"] for r in R)
    # central differences with h = 1e-6 of strain: truncation and round-off
    # stay below 1e-8 inside a region of the return
    check(t <= 1e-8, f"{name}: tangent check (D against central differences) max {t:.2e} <= 1e-8")
R = rows("shear_path")
check(abs(R[0]["sigma_xx"] + 30000) <= 1e-9 * 3e4 and abs(R[0]["sigma_yy"] + 50000) <= 1e-9 * 5e4,
      "shear_path: step 0 carries the initial stress (-30, -50) kPa")
check(max(r["eps_p"] for r in R) > 0.0 and max(r["yield"] for r in R) <= 1e-9 * 5e4,
      f"shear_path: yields (eps_p {R[-1]['eps_p']:.4g}) and stays on or inside f = 0")
done()
PY
