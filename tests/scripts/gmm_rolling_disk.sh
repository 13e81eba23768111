#!/usr/bin/env bash
# Rolling disk with GMM (issue 4), coarse: cases/rolling_disk_gmm.json at
# h = 0.025, dt = 0.005, T = 0.3 s, with MLS (R = 2h) and LME (gamma = 1.8).
# - the disk is filled on the grid exactly as MPM fills it (same points and
#   mass as method mpm on the same grid: one fill function, mpgm_bodies_fill);
# - the incline is a rigid obstacle (two layers of fixed nodes below y = 0):
#   the disk rolls, s within a band of s_ref = g sin(a) t^2 / 3, and its
#   centre stays on the plane;
# - no NaN; the cloud counters and the search / shape times are reported.
# usage: gmm_rolling_disk.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
scene="$src/cases/rolling_disk_gmm.json"
coarse=(--quiet --set mesh.h=0.025 --set time.dt=0.005 --set time.end=0.3 --set output.vtk=none)
fail=0
source "$src/tests/tools/run_case.bash"
run() { run_case "$@"; }
run mls "$scene" "${coarse[@]}" --set shape.kind=mls
run lme "$scene" "${coarse[@]}" --set shape.kind=lme --set shape.gamma=1.8
# contact at the disk's rim points instead of obstacle nodes (cases/rolling_disk.json
# with method gmm: "enforce": "points")
run mls_cp "$src/cases/rolling_disk.json" "${coarse[@]}" --set method=gmm --set shape.kind=mls
run lme_cp "$src/cases/rolling_disk.json" "${coarse[@]}" --set method=gmm --set shape.kind=lme --set shape.gamma=1.8
# method mpm on the same grid (from y = 0, as the gmm case's), one step: its particles
run mpm "$src/cases/rolling_disk.json" "${coarse[@]}" --set time.end=0.005 --set 'mesh.domain.min=[0,0]'
# the cantilever meshed (rectangles only) and on the grid (a far-away
# obstacle switches to the grid discretisation): the same points and nodes
cl=("$src/cases/cantilever.json" --quiet --set output.vtk=none --set method=gmm --set shape.kind=mls)
run cl_mesh "${cl[@]}"
run cl_grid "${cl[@]}" --set 'obstacles=[{"y":-2.5,"side":"below","layers":1}]'
[ $fail -eq 0 ] || { echo "0 passed, 1 failed"; exit 1; }
/usr/bin/python3 - "$work" "$src" <<'PY'
import csv, json, math, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done, finite, summary
w = sys.argv[1]
S = lambda n: summary(w, n)
h = 0.025
mpm = S("mpm")
mdisk = 7800.0 * math.pi * 0.25
for kind in ("mls", "lme"):
    s = S(kind); m, c, t = s["metrics"], s["counts"], s["time_s"]
    print(f"  {kind}: s(0.3 s) = {m['s_final']:.4f} m (s_ref {m['s_ref_final']:.4f} m, ratio "
          f"{m['s_final'] / m['s_ref_final']:.3f}), centre uy {m['centre_uy']:+.5f} m, error_max "
          f"{m['error_max']:.4f} m; points {c['points']}, nodes {c['nodes']}, dofs {c['dofs']}, "
          f"analyses {c['analyses']}, Newton {c['newton_iterations']}; radius_growths "
          f"{c['radius_growths']}, cloud_enlargements {c['cloud_enlargements']}, shape_cold_restarts "
          f"{c['shape_cold_restarts']}; search {t['search']:.3f} s, shape {t['shape']:.3f} s, "
          f"total {t['total']:.2f} s")
    check(s["status"] == "completed" and s["method"] == "gmm" and s["shape"] == kind and c["steps"] == 60,
          f"{kind}: 60 steps completed, method gmm, shape {kind}")
    check(finite(s["metrics"]) and finite(s["probes"]) and finite(s["newton_last_step"]),
          f"{kind}: no NaN or Inf in metrics, probes, Newton statistics")
    check(all(k in c for k in ("radius_growths", "cloud_enlargements", "shape_cold_restarts"))
          and t["search"] > 0 and t["shape"] > 0,
          f"{kind}: counters and search / shape times in summary.json")
    # the same material points as method mpm (mpgm_bodies_fill): same count,
    # same masses summed in the same order; point masses never change
    check(c["points"] == mpm["counts"]["points"] and m["mass_total"] == mpm["metrics"]["mass_total"]
          and abs(m["mass_total"] - mdisk) < 5e-3 * mdisk,
          f"{kind}: points and mass of method mpm ({c['points']} points, {m['mass_total']:.3f} kg; "
          f"rho pi R^2 = {mdisk:.1f} kg within 0.5 %)")
    # Rolls: measured s = 0.715 (MLS) and 0.771 (LME) of s_ref at this h
    # and dt. The points next to the plane are held by the fixed obstacle
    # nodes in their clouds, which resists rolling, the more so on coarse
    # grids (h = 0.01: 0.96 s_ref at 0.9 s; docs/theory.md, section 13).
    # MPM's test (rolling_disk.sh) has the band -20 %/+10 % (MPM measured
    # -14 %); here -35 %/+10 %, the measured -28 % with a margin of 1.25x.
    # It fails if the disk sticks (s ~ 0) or slides (s = 1.5 s_ref).
    # error_max: measured 0.036 m (MLS) and 0.029 m (LME); band 0.045 m
    # (MPM: 0.0175 m, band 0.025 m). This test covers 0.3 s only.
    r = m["s_final"] / m["s_ref_final"]
    check(0.65 < r < 1.1, f"{kind}: rolls: s(0.3 s) = {m['s_final']:.4f} m = {r:.3f} s_ref (within -35 %/+10 %)")
    check(m["error_max"] < 0.045,
          f"{kind}: centre follows the analytic curve: max |u_ref - u| = {m['error_max']:.4f} m < 0.045 m")
    # on the plane: the disk rests on the obstacle's nodes through the
    # clouds, and rides over its rows of nodes; measured max |uy| over the
    # run 0.0079 m (MLS) and 0.0053 m (LME) = 0.3 h; band h / 2
    uy = [abs(float(row["centre_uy"])) for row in csv.DictReader(open(f"{w}/{kind}/probes.csv"))]
    check(max(uy) < 0.5 * h, f"{kind}: the centre stays on the plane: max |uy| = {max(uy):.4f} m < h/2 = {h / 2} m")
for kind in ("mls", "lme"):
    # Contact at rim points (docs/theory.md section 17): the obstacle's
    # resistance to rolling is gone. Measured s = 1.0024 (MLS) and 1.0026
    # (LME) s_ref, error_max 0.00031 and 0.00037 m (obstacle nodes: 0.036
    # and 0.029 m); bands -1.5 %/+1.5 % and 0.0006 m.
    s = S(kind + "_cp"); m, c = s["metrics"], s["counts"]
    r = m["s_final"] / m["s_ref_final"]
    check(s["status"] == "completed" and s["method"] == "gmm" and s["effects"]["contact_points"]
          and c["contact_point_holds"] > 0 and c["contact_point_releases"] > 0 and finite(m),
          f"{kind}, contact at rim points: completed, {c['contact_point_holds']} holds, "
          f"{c['contact_point_releases']} releases, {c['contact_points_unenforced']} point-steps without functions")
    check(0.985 < r < 1.015 and m["error_max"] < 0.0006 and m["error_max"] < 0.1 * S(kind)["metrics"]["error_max"],
          f"{kind}, contact at rim points: s(0.3 s) = {r:.4f} s_ref (within 1.5 %), max |u_ref - u| = "
          f"{m['error_max']:.5f} m < 0.0006 m and under a tenth of the obstacle's {S(kind)['metrics']['error_max']:.4f} m")
a, b = S("cl_mesh"), S("cl_grid")
ta, tb = a["metrics"]["tip_uy"], b["metrics"]["tip_uy"]
# same nodes and points in another numbering: the sums run in another
# order (measured difference 6e-16 relative)
check(a["counts"]["points"] == b["counts"]["points"] and
      b["counts"]["nodes"] == a["counts"]["nodes"] + 77 and abs(ta - tb) <= 1e-12 * abs(ta),
      f"cantilever, GMM-MLS meshed and on the grid (+ 77 obstacle nodes far below): tip_uy {ta!r} vs {tb!r}")
done()
PY
