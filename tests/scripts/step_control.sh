#!/usr/bin/env bash
# Step control (issue 5, item 3): a step that fails recoverably is rejected
# and retried with half the step, down to dt / 2^time.max_cuts; the
# step doubles back after time.grow_after steps converge; every cut is
# logged on stderr and listed in summary.json; at the limit the run stops
# with exit 1, a message naming the limit, and its output intact. Also: a
# recoverable Newton failure is the step's failure (it used to restart
# Newton silently, as if the contact set had changed).
# The static cantilever needs 4 Newton iterations for the full load in one
# step; solver.max_iterations = 3 makes the large increments fail.
# usage: step_control.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
scene="$src/cases/cantilever.json"
base=(--quiet --set mesh.h=0.25 --set output.vtk=none)
tight=(--set solver.max_iterations=3 --set time.grow_after=2)
run() { # NAME ARGS...: exit code in NAME.rc, stderr in NAME.err
  local name="$1"; shift
  "$exe" run "$scene" "${base[@]}" --out "$work/$name" "$@" > "$work/$name.out" 2> "$work/$name.err"
  echo $? > "$work/$name.rc"
}
run ref
run cuts "${tight[@]}" --set time.max_cuts=6
run limit "${tight[@]}" --set time.max_cuts=1
run nocut "${tight[@]}"
# output.times: steps end on the requested load factors, VTK is written there
"$exe" run "$scene" --quiet --set mesh.h=0.25 --set time.load_steps=4 --set output.every=1000 \
  --set 'output.times=[0.3,0.55]' --out "$work/times" > "$work/times.out" 2>&1; echo $? > "$work/times.rc"
/usr/bin/python3 - "$work" "$src" <<'PY'
import csv, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done, summary
w = sys.argv[1]
rc = lambda n: int(open(f"{w}/{n}.rc").read())
err = lambda n: open(f"{w}/{n}.err").read()
ref, cut = summary(w, "ref"), summary(w, "cuts")
check(rc("ref") == 0 and ref["counts"]["step_cuts"] == 0 and "step_cuts" not in ref,
      "reference (one load step, 25 iterations allowed): no cut, no cut list")
check(rc("cuts") == 0 and cut["status"] == "completed", f"max_cuts 6: the run completes (exit {rc('cuts')})")
a, b = cut["metrics"]["tip_uy"], ref["metrics"]["tip_uy"]
check(abs(a - b) <= 1e-9 * abs(b), f"same equilibrium as one load step: tip_uy {a:.12f} vs {b:.12f}")
n, lst, lines = cut["counts"]["step_cuts"], cut.get("step_cuts", []), err("cuts").count("rejected")
check(n > 0 and n == len(lst) == lines,
      f"every cut counted, listed and logged: counts {n}, summary list {len(lst)}, stderr lines {lines}")
check(all(c["code"] == 2 and "did not converge in 3 iterations" in c["reason"] for c in lst),
      "each cut records its reason (Newton iteration limit, code 2)")
rows = list(csv.DictReader(open(f"{w}/cuts/steps.csv")))
inc = [float(r["load_increment"]) for r in rows]
check(abs(sum(inc) - 1.0) < 1e-12 and abs(float(rows[-1]["load_factor"]) - 1.0) < 1e-12,
      f"steps.csv: {len(rows)} steps whose increments add up to the full load ({sum(inc):.15f})")
check(inc[0] == 0.25 and min(inc) == 0.0625, f"increments halved: first 0.25, smallest {min(inc)}")
# after grow_after = 2 converged steps the step doubles: a later cut then
# starts from a larger increment than the step before it had
grew = any(c["dt"] > inc[c["step"] - 2] for c in lst if c["step"] >= 2)
check(grew, "the increment grows back after 2 converged steps (a cut from a doubled increment is logged)")
lim = summary(w, "limit")
check(rc("limit") == 1 and lim["status"] == "failed" and lim["counts"]["step_cuts"] == 1,
      f"max_cuts 1: exit 1 after one cut (exit {rc('limit')}, cuts {lim['counts']['step_cuts']})")
check("time.max_cuts" in err("limit") and "did not converge" in err("limit"),
      "the message names the reason and the limit: " + err("limit").strip().splitlines()[-2][:150])
check("output written up to the last completed step" in err("limit") and lim.get("failed_step") == 1,
      "the output is kept and summary.json says where the run stopped")
no = summary(w, "nocut")
check(rc("nocut") == 1 and no["counts"]["step_cuts"] == 0 and no["counts"]["newton_iterations"] == 0
      and "did not converge in 3 iterations" in err("nocut"),
      "max_cuts 0 (default): the first Newton failure stops the run; no silent restart of Newton")
import re
rows = list(csv.DictReader(open(f"{w}/times/steps.csv")))
lf = [float(r["load_factor"]) for r in rows]
pvd = re.findall(r'timestep="([^"]+)"', open(f"{w}/times/points.pvd").read())
check(rc("times") == 0 and lf == [0.25, 0.3, 0.55, 0.8, 1.0],
      f"output.times [0.3, 0.55] with 4 load steps: steps end at {lf}")
check([float(x) for x in pvd] == [0.0, 0.3, 0.55, 1.0], f"VTK written at the start, the requested times and the end: {pvd}")
done()
PY
