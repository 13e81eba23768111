#!/usr/bin/env bash
# Column collapse (issue 5), coarse and short: cases/column_collapse.json at
# h = 0.1, dt = 0.01 s, to 0.2 s with MPM. Plastic flow has started (eps_p
# grows in the last step), mass is conserved to round-off, nothing is NaN,
# the unsymmetric tangent (psi = 0 != phi) went to UMFPACK, and Newton
# converges quadratically in the last (plastic) step: the consistent tangent
# holds in a real run, not only in test_mohr_coulomb.
# usage: column_collapse.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail=0
source "$src/tests/tools/run_case.bash"
coarse=(--set mesh.h=0.1 --set time.dt=0.01)
run_case mpm "$src/cases/column_collapse.json" "${coarse[@]}" --set time.end=0.2
run_case mpm_before "$src/cases/column_collapse.json" "${coarse[@]}" --set time.end=0.19
[ $fail -eq 0 ] || { echo "0 passed, 1 failed"; exit 1; }
/usr/bin/python3 - "$work" "$src" <<'PY'
import csv, math, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done, finite, summary
w = sys.argv[1]
s, b = summary(w, "mpm"), summary(w, "mpm_before")
m, c = s["metrics"], s["counts"]
check(s["status"] == "completed" and c["steps"] == 20, f"MPM runs to 0.2 s ({c['steps']} steps, {c['step_cuts']} cuts)")
check(finite(s["metrics"]) and finite(s["probes"]), "no NaN or Inf in the metrics and probes")
rows = list(csv.reader(open(f"{w}/mpm/probes.csv")))[1:]
check(all(math.isfinite(float(x)) for r in rows for x in r), f"probes.csv finite ({len(rows)} rows)")
mass = 1850.0 * 4.0 * 2.0
check(abs(m["mass_total"] - mass) <= 1e-12 * mass, f"mass conserved: {m['mass_total']!r} kg vs rho V = {mass} kg")
check(s["effects"]["plasticity"] and s["solver"] == "umfpack",
      f"plasticity effect on; psi = 0 != phi: unsymmetric tangent solved by {s['solver']}")
e1, e0 = m["eps_p_max"], b["metrics"]["eps_p_max"]
check(e1 > 0.01 and e1 > e0, f"plastic flow under way: eps_p_max {e0:.4f} at 0.19 s, {e1:.4f} at 0.2 s")
check(m["runout"] > 4.0 and m["height"] < 2.0, f"the column spreads: runout {m['runout']:.4f} m > 4, height {m['height']:.4f} m < 2")
# quadratic convergence: log(r_k+1 / ref) / log(r_k / ref) near 2 once the
# residual is small, before the round-off floor (~1e-13 ref)
r = s["newton_last_step"]["residuals"]
ref = max(r[0], 1e-300)
rates = [math.log(r[k + 1] / ref) / math.log(r[k] / ref)
         for k in range(len(r) - 1) if r[k] / ref < 1e-2 and r[k + 1] / ref > 1e-12]
seq = ", ".join(f"{x / ref:.2e}" for x in r)
check(rates and max(rates) >= 1.8, f"Newton in the last step: |R|/ref = {seq}; rates {', '.join(f'{x:.2f}' for x in rates)} (>= 1.8)")
done()
PY
