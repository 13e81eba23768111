#!/usr/bin/env bash
# Rolling disk (issue 3), coarse: h = 0.025, dt = 0.005, T = 0.3 s.
# - contact floor at rim points (the case's enforce points): the disk rolls;
#   its centre follows s_ref = g sin(a) t^2 / 3 within a band (see below);
# - contact floor at the grid nodes (enforce nodes): rolls with the O(h) lag
#   of the held bottom cell row, a wider band; the rim points do better;
# - slip floor: frictionless sliding, s = g sin(a) t^2 / 2: exact with the
#   initial acceleration from the equation of motion (the default), and
#   lagging by g sin(a) dt t / 2 when Newmark starts from a_0 = 0;
# the particles fill the disk; 1 and 3 threads give the same bits.
# usage: rolling_disk.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
coarse=(--quiet --set mesh.h=0.025 --set time.dt=0.005 --set time.end=0.3 --set output.vtk=none)
# grid-node conditions need grid nodes on the plane: the grid starts at y = 0
ongrid=(--set 'mesh.domain.min=[0,0]')
fail=0
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" --out "$work/roll" > "$work/roll.log" 2>&1 || { cat "$work/roll.log"; fail=1; }
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" "${ongrid[@]}" --set boundaries.0.enforce=nodes \
  --out "$work/nodes" > "$work/nodes.log" 2>&1 || { cat "$work/nodes.log"; fail=1; }
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" "${ongrid[@]}" --set 'boundaries=[{"y":0,"condition":"slip"}]' \
  --out "$work/slip" > "$work/slip.log" 2>&1 || { cat "$work/slip.log"; fail=1; }
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" "${ongrid[@]}" --set 'boundaries=[{"y":0,"condition":"slip"}]' \
  --set time.initial_acceleration=zero --out "$work/slip_a0" > "$work/slip_a0.log" 2>&1 || { cat "$work/slip_a0.log"; fail=1; }
# contact at grid nodes with the contact set checked only at convergence
# (solver.contact_check = 0), and with Newton started from du = 0
# (time.predictor = zero; the case uses velocity): the same answer. (At rim
# points a point caught is anchored from the iterate it is caught at, each
# point changing at most once per step: the answers differ by 1e-7 to 1e-5
# at 1e-3; the case checks at 1e-6, below.)
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" "${ongrid[@]}" --set boundaries.0.enforce=nodes \
  --set solver.contact_check=0 --out "$work/roll0" > "$work/roll0.log" 2>&1 || { cat "$work/roll0.log"; fail=1; }
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" "${ongrid[@]}" --set boundaries.0.enforce=nodes \
  --set time.predictor=zero --out "$work/roll_zero" > "$work/roll_zero.log" 2>&1 || { cat "$work/roll_zero.log"; fail=1; }
# the contact changes at rim points applied to the kept factorisation
# (solver.contact_rank, by default 32) against refactorising at each
# change (0): the same contact history and answer, fewer factorisations
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" --set solver.contact_rank=0 \
  --out "$work/roll_refactor" > "$work/roll_refactor.log" 2>&1 || { cat "$work/roll_refactor.log"; fail=1; }
# and with room for one point's two columns only: the changes of two or
# more points at once are factorised again
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" --set solver.contact_rank=2 \
  --out "$work/roll_rank2" > "$work/roll_rank2.log" 2>&1 || { cat "$work/roll_rank2.log"; fail=1; }
# the answer does not depend on the solver's path: GMM-MLS to 0.6 s with
# the pattern and the factorisation kept across steps and contact changes
# applied to it (as shipped) and refactorising at every change with no
# pattern kept (shape.skin 0, solver.contact_rank 0). A rim point caught
# during a solve is anchored from that iterate; the case checks the set at
# |R| <= 1e-6 ref, so the anchors are those of the converged motion.
gpath=(--set method=gmm --set shape.kind=mls --set time.end=0.6)
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" "${gpath[@]}" \
  --out "$work/gmm_kept" > "$work/gmm_kept.log" 2>&1 || { cat "$work/gmm_kept.log"; fail=1; }
"$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" "${gpath[@]}" --set shape.skin=0 \
  --set solver.contact_rank=0 --out "$work/gmm_refactor" > "$work/gmm_refactor.log" 2>&1 ||
  { cat "$work/gmm_refactor.log"; fail=1; }
# the same on 1 and on 3 threads (mpgm's loops): the same bits
for t in 1 3; do
  "$exe" run "$src/cases/rolling_disk.json" "${coarse[@]}" --set threads=$t \
    --out "$work/roll_t$t" > "$work/roll_t$t.log" 2>&1 || { cat "$work/roll_t$t.log"; fail=1; }
done
[ $fail -eq 0 ] || { echo "0 passed, 1 failed"; exit 1; }
/usr/bin/python3 - "$work" <<'PY'
import json, math, sys
w = sys.argv[1]
npass = nfail = 0
def check(ok, msg):
    global npass, nfail
    print(("PASS: " if ok else "FAIL: ") + msg); npass += ok; nfail += (not ok)
g, a, T, dt = 9.81, math.radians(60.0), 0.3, 0.005
r = json.load(open(f"{w}/roll/summary.json")); m = r["metrics"]
rn = json.load(open(f"{w}/nodes/summary.json")); mn = rn["metrics"]
r0 = json.load(open(f"{w}/roll0/summary.json"))
d = abs(r0["metrics"]["s_final"] - mn["s_final"]) / abs(r0["metrics"]["s_final"])
check(d < 1e-9 and rn["counts"]["newton_iterations"] < r0["counts"]["newton_iterations"],
      f"grid nodes: contact set checked early (1e-3) and only at convergence: same s_final (rel. diff {d:.1e}), "
      f"{rn['counts']['newton_iterations']} vs {r0['counts']['newton_iterations']} Newton iterations")
rz = json.load(open(f"{w}/roll_zero/summary.json"))
dz = abs(rz["metrics"]["s_final"] - mn["s_final"]) / abs(rz["metrics"]["s_final"])
check(rn["scene"]["time"]["predictor"] == "velocity" and dz < 1e-8 and
      rn["counts"]["newton_iterations"] < rz["counts"]["newton_iterations"],
      f"grid nodes: predictor du = dt v and du = 0: same s_final (rel. diff {dz:.1e}), "
      f"{rn['counts']['newton_iterations']} vs {rz['counts']['newton_iterations']} Newton iterations")
r1 = json.load(open(f"{w}/roll_t1/summary.json")); r3 = json.load(open(f"{w}/roll_t3/summary.json"))
def steps(d):  # steps.csv without its wall-clock column (found by its name)
    rows = [l.rstrip("\n").split(",") for l in open(f"{w}/{d}/steps.csv")]
    drop = rows[0].index("wall_s")
    return [r[:drop] + r[drop + 1:] for r in rows]
same = open(f"{w}/roll_t1/probes.csv").read() == open(f"{w}/roll_t3/probes.csv").read() and \
    steps("roll_t1") == steps("roll_t3")
check(r1["threads"] == 1 and r3["threads"] == 3 and same and r1["metrics"] == r3["metrics"],
      f"1 and 3 threads: identical probes.csv, steps.csv (but wall_s) and metrics (s_final {r1['metrics']['s_final']!r} vs {r3['metrics']['s_final']!r})")
c = r["counts"]
check(r["effects"]["contact_points"] and not r["effects"]["contact"] and c["contact_point_holds"] > 0 and
      c["contact_point_releases"] > 0 and c["contact_points_unenforced"] == 0,
      f"contact at rim points: {c['contact_points']} points, held {c['contact_point_holds']} times and "
      f"let go {c['contact_point_releases']} times as the disk rolls over them, none without shape functions")
# Rim points: measured here s_final 2.4 % below s_ref, max horizontal
# deviation 0.0030 m (a fifth of the grid-node contact's, below). The
# bounds leave a margin of about 1.5x.
check(m["s_final"] > 0.965 * m["s_ref_final"] and m["s_final"] < 1.02 * m["s_ref_final"],
      f"rolls: s(0.3 s) = {m['s_final']:.4f} m against s_ref = {m['s_ref_final']:.4f} m (within -3.5 %/+2 %)")
check(m["error_max"] < 0.0045, f"centre follows the analytic curve: max |u_ref - u| = {m['error_max']:.4f} m < 0.0045 m")
check(abs(m["centre_uy"]) < 1e-3, f"the disk stays on the plane: centre uy = {m['centre_uy']:.2e} m")
check(rn["effects"]["contact"] and rn["counts"]["contact_resolves"] > 0,
      f"contact at grid nodes: nodes released where the disk lifts ({rn['counts']['contact_resolves']} re-solves)")
# Grid nodes: the particles of the bottom cell row (|x - x_c| < sqrt(2 R h)
# = 0.16 m) interpolate from held floor nodes, which delays rolling; the
# error falls with h (docs/theory.md). Measured here: s_final 12 % below
# s_ref, max horizontal deviation 0.0149 m. The bounds fail if the disk
# sticks (s_final ~ 0) or slides (s = 1.5 s_ref).
check(mn["s_final"] > 0.8 * mn["s_ref_final"] and mn["s_final"] < 1.1 * mn["s_ref_final"],
      f"grid nodes: rolls, s(0.3 s) = {mn['s_final']:.4f} m against s_ref = {mn['s_ref_final']:.4f} m (within -20 %/+10 %)")
check(mn["error_max"] < 0.025 and m["error_max"] < 0.5 * mn["error_max"],
      f"grid nodes: max |u_ref - u| = {mn['error_max']:.4f} m < 0.025 m, and more than twice the rim points' {m['error_max']:.4f} m")
# Woodbury on the kept factorisation solves with the same matrix as a
# new factorisation would, so only the iterates differ: measured s_final
# rel. diff 1.8e-10 (1.5e-9 when the case checked the set at 1e-3 of the
# reference: the anchors depend on the iterate), the same holds and
# releases, 57 factorisations against 84.
rr = json.load(open(f"{w}/roll_refactor/summary.json")); cr = rr["counts"]
dr = abs(rr["metrics"]["s_final"] - m["s_final"]) / abs(m["s_final"])
check(dr < 1e-7 and c["contact_low_rank"] == c["contact_resolves"] > 0 and cr["contact_low_rank"] == 0 and
      (c["contact_point_holds"], c["contact_point_releases"]) == (cr["contact_point_holds"], cr["contact_point_releases"]) and
      c["factorizations"] < cr["factorizations"] - 0.5 * cr["contact_resolves"],
      f"contact changes on the kept factorisation (solver.contact_rank): s_final rel. diff {dr:.1e} from "
      f"refactorising, {c['contact_low_rank']} of {c['contact_resolves']} changes kept, "
      f"{c['factorizations']} factorisations against {cr['factorizations']}")
r2 = json.load(open(f"{w}/roll_rank2/summary.json")); c2 = r2["counts"]
d2 = abs(r2["metrics"]["s_final"] - m["s_final"]) / abs(m["s_final"])
check(d2 < 1e-7 and 0 < c2["contact_low_rank"] < c2["contact_resolves"] and
      c["factorizations"] < c2["factorizations"] < cr["factorizations"],
      f"solver.contact_rank 2: {c2['contact_low_rank']} of {c2['contact_resolves']} changes kept, the rest "
      f"refactorised ({c2['factorizations']} factorisations), s_final rel. diff {d2:.1e}")
# Measured: error (67) rel. diff 5.5e-8, s_final 1.7e-10 (1420 and 807
# Newton iterations). With the set checked at 1e-3 of the reference (the
# default) the anchors carry that iterate's error: 1.5e-4 and 3.1e-7.
gk = json.load(open(f"{w}/gmm_kept/summary.json")); gr = json.load(open(f"{w}/gmm_refactor/summary.json"))
de = abs(gk["metrics"]["error"] - gr["metrics"]["error"]) / gr["metrics"]["error"]
ds = abs(gk["metrics"]["s_final"] - gr["metrics"]["s_final"]) / abs(gr["metrics"]["s_final"])
check(gk["scene"]["solver"]["contact_check"] == 1e-6 and gk["counts"]["patterns_kept"] > 0 and
      gr["counts"]["patterns_kept"] == 0 and gk["counts"]["contact_low_rank"] > 0 and
      gr["counts"]["contact_low_rank"] == 0 and de < 1e-6 and ds < 1e-8,
      f"GMM-MLS to 0.6 s on two solver paths (pattern and factorisation kept, contact changes on it; "
      f"refactorising, no pattern kept): error (67) rel. diff {de:.1e} < 1e-6, s_final {ds:.1e} < 1e-8")
mdisk = 7800.0 * math.pi * 0.25  # particle masses are constant; projection is tested in test_mpm
check(abs(m["mass_total"] - mdisk) < 5e-3 * mdisk, f"particles fill the disk: mass {m['mass_total']:.1f} kg vs rho pi R^2 = {mdisk:.1f} kg (0.5 %)")
s = json.load(open(f"{w}/slip/summary.json"))["metrics"]
# the rigid slide has constant acceleration, which the trapezoidal rule
# integrates exactly once it starts from the right a_0
s_exact = 0.5 * g * math.sin(a) * T * T
check(abs(s["centre_ux"] - s_exact) < 1e-4 * s_exact,
      f"slip floor, initial acceleration from equilibrium: s = {s['centre_ux']:.6f} m vs {s_exact:.6f} m (1e-4)")
check(abs(s["centre_uy"]) < 1e-3, f"slip floor: the disk stays on the plane (uy = {s['centre_uy']:.2e} m)")
s = json.load(open(f"{w}/slip_a0/summary.json"))["metrics"]
# Newmark with a_0 = 0 lags the exact solution by g sin(a) dt t / 2 (theory.md)
s_lag = s_exact - 0.5 * g * math.sin(a) * dt * T
check(abs(s["centre_ux"] - s_lag) < 2e-3 * s_lag and s["centre_ux"] < s_exact - 0.5 * (s_exact - s_lag),
      f"slip floor, a_0 = 0: s = {s['centre_ux']:.5f} m vs {s_lag:.5f} m with the start-up lag (0.2 %)")
print(f"{npass} passed, {nfail} failed")
sys.exit(1 if nfail else 0)
PY
