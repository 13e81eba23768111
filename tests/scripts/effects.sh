#!/usr/bin/env bash
# Effects are decided when the scene loads; absent effects do no work.
# usage: effects.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
scene="$src/cases/cantilever.json"
common=(--quiet --set mesh.h=0.5 --set output.vtk=none)
"$exe" check "$scene" > "$work/check.txt" 2>&1 || echo "check failed"
"$exe" run "$scene" "${common[@]}" --out "$work/static" > /dev/null 2>&1
"$exe" run "$scene" "${common[@]}" --out "$work/small" --set kinematics=small > /dev/null 2>&1
# no gravity, the load is a prescribed tip displacement instead
"$exe" run "$scene" "${common[@]}" --out "$work/nograv" --set 'gravity=[0,0]' \
  --set 'boundaries=[{"x":0,"fix":["x","y"]},{"x":8,"fix":["y"],"displacement":[0,-0.1]}]' > "$work/nograv.log" 2>&1
"$exe" run "$scene" "${common[@]}" --out "$work/dyn" --set time.analysis=dynamic \
  --set time.dt=0.01 --set time.end=0.03 > "$work/dyn.log" 2>&1
/usr/bin/python3 - "$work" <<'PY'
import json, sys
w = sys.argv[1]
npass = nfail = 0
def check(ok, msg):
    global npass, nfail
    print(("PASS: " if ok else "FAIL: ") + msg); npass += ok; nfail += (not ok)
txt = open(f"{w}/check.txt").read()
check('"inertia":\tfalse' in txt and '"gravity":\ttrue' in txt and '"geometric_stiffness":\ttrue' in txt,
      "mpgm check lists the effects of the static cantilever")
S = {k: json.load(open(f"{w}/{k}/summary.json")) for k in ("static", "small", "nograv", "dyn")}
for k, s in S.items():
    check(s["status"] == "completed", f"{k}: run completed ({s['message']})")
for k, s in S.items():  # processor time of the run beside its wall time
    check(0 < s["cpu_s"] < 10 * s["time_s"]["total"] * s["threads"] + 1,
          f"{k}: cpu_s {s['cpu_s']:.3g} s beside wall {s['time_s']['total']:.3g} s")
s = S["static"]
check(s["effects"]["inertia"] is False and s["counts"]["inertia_loops"] == 0 and s["time_s"]["mass"] == 0,
      "static: no inertia loop ran, mass timer is zero")
check(s["counts"]["body_force_loops"] == s["counts"]["steps"] and s["time_s"]["body_force"] > 0,
      "static with gravity: one body-force loop per step")
s = S["nograv"]
check(s["effects"]["gravity"] is False and s["counts"]["body_force_loops"] == 0 and s["time_s"]["body_force"] == 0,
      "no gravity: no body-force loop ran, its timer is zero")
check(s["effects"]["prescribed_displacement"] is True and abs(s["metrics"]["tip_uy"] + 0.1) < 1e-12,
      f"prescribed tip displacement reached: tip_uy = {s['metrics']['tip_uy']}")
s = S["small"]
check(s["effects"]["geometric_stiffness"] is False and s["effects"]["configuration_update"] is False,
      "small kinematics: no geometric stiffness, no configuration update")
check(abs(s["metrics"]["volume_total"] - 8.0) < 1e-12, f"small kinematics: volume unchanged ({s['metrics']['volume_total']})")
s = S["dyn"]
check(s["effects"]["inertia"] is True and s["counts"]["inertia_loops"] > 0 and s["counts"]["steps"] == 3,
      f"dynamic: inertia loops ran ({s['counts']['inertia_loops']}), 3 steps")
for k, s in S.items():
    check(abs(s["metrics"]["mass_total"] - 8000.0) < 1e-9, f"{k}: mass conserved ({s['metrics']['mass_total']})")
print(f"{npass} passed, {nfail} failed")
sys.exit(1 if nfail else 0)
PY
