#!/usr/bin/env bash
# threads.sh -- mpgm's loops on the pool's threads give the results of one
# thread to the last bit (scene key "threads"; docs/architecture.md,
# "Threads"): the shape functions built by point ranges
# (mpgm_conn_par_build), the projection, npc's predictor and the nodal
# forces gathered node by node through the transpose (mpgm_conn_gathers),
# the update of the points by point ranges, the meshfree clouds.
#
# 1. Explicit MPM on an elastic block of 3,200 points (12 point ranges) under
#    gravity, 30 steps, with Q4, uGIMP, CPDI, LME (gamma 1.8) and npc, and
#    CPLS with usl: threads 1 and 2 give the same steps.csv (but its wall
#    time) and probes.csv, and the same counts.
# 2. Implicit: MPM with LME (clouds of grid nodes) on the cantilever, and GMM
#    (MLS clouds of its own nodes) on the rolling disk, 2 steps each: the same.
# 3. 3-D explicit MPM (the run sums of core/mpgm_data.h: on one thread the
#    force added right after each point's update, on two gathered through
#    the transpose) on a block of 8 x 4 x 4 H8 cells, 8 points each, with
#    fe and npc, fe, usl, uGIMP and CPDI; and with mesh.min_node_mass 0.2,
#    which drops the body's corner and edge nodes (fewer nodes than with
#    the default) and renormalises their points' lists every step.
#
# usage: threads.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"

cat > block.json <<'EOF'
{"description": "tests/scripts/threads.sh: an elastic block of 40 x 20 cells, 4 points per cell",
 "method": "mpm", "mesh": {"h": 0.025, "domain": {"min": [-0.05, -0.05], "max": [1.1, 0.7]}},
 "kinematics": "small",
 "time": {"analysis": "explicit", "end": 0.0075, "dt": 2.5e-4},
 "materials": {"soil": {"type": "linear_elastic", "density": 2000, "E": 1e6, "nu": 0.3}},
 "bodies": [{"material": "soil", "rectangle": {"min": [0, 0], "max": [1.0, 0.5]}, "velocity": [0.5, 0.2]}],
 "boundaries": [{"y": 0, "condition": "slip"}],
 "gravity": [0, -9.81], "probes": {"corner": [0.99, 0.49]},
 "output": {"vtk": "none", "every": 1}}
EOF

# the same results, but wall times: steps.csv without its wall_s column,
# probes.csv, and summary.json's counts
same() {
  local a="$1" b="$2"
  python3 - "$a" "$b" <<'EOF'
import csv, json, sys
def steps(d):
    rows = list(csv.reader(open(f"{d}/steps.csv")))
    w = rows[0].index("wall_s")
    return [r[:w] + r[w + 1:] for r in rows]
a, b = sys.argv[1], sys.argv[2]
ok = steps(a) == steps(b) and open(f"{a}/probes.csv").read() == open(f"{b}/probes.csv").read()
sa, sb = json.load(open(f"{a}/summary.json")), json.load(open(f"{b}/summary.json"))
# clock_reads counts the timers' own clock reads, which the threads add to
ca = {k: v for k, v in sa["counts"].items() if k != "clock_reads"}
cb = {k: v for k, v in sb["counts"].items() if k != "clock_reads"}
ok = ok and ca == cb and sa["metrics"] == sb["metrics"]
ok = ok and sa["status"] == "completed" and len(steps(a)) >= 3
sys.exit(0 if ok else 1)
EOF
}

check_pair() {
  local name="$1"; shift
  local rc=0
  for t in 1 2; do
    "$exe" run "$@" --set threads=$t --out "$work/${name}_$t" --quiet > "$work/${name}_$t.log" 2>&1 || rc=$?
  done
  if [ $rc -ne 0 ]; then
    ko "$name: a run failed (exit $rc): $(tail -c 300 "$work/${name}_2.log")"
  elif same "$work/${name}_1" "$work/${name}_2"; then
    ok "$name: threads 1 and 2 give the same steps, probes, counts and metrics to the bit"
  else
    ko "$name: threads 1 and 2 differ"
  fi
}

# ---- 1: explicit MPM --------------------------------------------------------------
check_pair q4 block.json --set shape.kind=fe
check_pair ugimp block.json --set shape.kind=ugimp --set mesh.layout=centres
check_pair cpdi block.json --set shape.kind=cpdi
check_pair lme block.json --set shape.kind=lme --set shape.gamma=1.8
check_pair cpls block.json --set shape.kind=cpls --set time.scheme=usl

# ---- 2: implicit, clouds ----------------------------------------------------------
check_pair mpm_lme "$src/cases/cantilever.json" --set method=mpm --set shape.kind=lme \
  --set time.load_steps=2 --set output.vtk=none
check_pair gmm "$src/cases/rolling_disk_gmm.json" --set time.end=0.005 --set output.vtk=none

# ---- 3: explicit MPM in 3-D ------------------------------------------------------
cat > block3.json <<'EOF'
{"description": "tests/scripts/threads.sh: an elastic block of 8 x 4 x 4 H8 cells, 8 points per cell",
 "method": "mpm", "mesh": {"h": 0.05, "domain": {"min": [-0.1, -0.1, -0.1], "max": [0.55, 0.35, 0.35]}},
 "kinematics": "small",
 "time": {"analysis": "explicit", "end": 0.005, "dt": 2.5e-4},
 "materials": {"soil": {"type": "linear_elastic", "density": 2000, "E": 1e6, "nu": 0.3}},
 "bodies": [{"material": "soil", "box": {"min": [0, 0, 0], "max": [0.4, 0.2, 0.2]}, "velocity": [0.5, 0.2, -0.3]}],
 "boundaries": [{"y": 0, "condition": "slip"}],
 "gravity": [0, -9.81, 0], "probes": {"corner": [0.39, 0.19, 0.19]},
 "output": {"vtk": "none", "every": 1}}
EOF
if [ -x "${exe}-3d" ]; then
  check_pair fe_3d block3.json
  check_pair fe_scheme_3d block3.json --set time.scheme=fe
  check_pair usl_3d block3.json --set time.scheme=usl
  check_pair ugimp_3d block3.json --set shape.kind=ugimp --set mesh.layout=centres
  check_pair cpdi_3d block3.json --set shape.kind=cpdi
  check_pair light_3d block3.json --set mesh.min_node_mass=0.2
  nodes='import json, sys; print(json.load(open(sys.argv[1] + "/summary.json"))["counts"]["nodes"])'
  n0=$(python3 -c "$nodes" "$work/fe_3d_1" 2> /dev/null); n1=$(python3 -c "$nodes" "$work/light_3d_1" 2> /dev/null)
  if [ -n "$n0" ] && [ -n "$n1" ] && [ "$n1" -lt "$n0" ]; then
    ok "min_node_mass 0.2 drops nodes in 3-D: $n1 nodes against $n0"
  else
    ko "min_node_mass 0.2 in 3-D: nodes '$n1' against '$n0'"
  fi
else
  ko "no 3-D build beside $exe"
fi

echo "threads: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
