#!/usr/bin/env bash
# run_limits.sh -- runs are sized and bounded (docs/scene-format.md, "Runs
# are sized and bounded"): a fixed explicit time.dt above the stability
# limit fails the run (exit 1, summary.json "failed" naming time.dt) unless
# time.allow_unstable_dt; an unstable run allowed is stopped by the energy
# balance ("diverged"); a run of 1e150 steps stops at once; a run that
# reaches time.max_steps before its end fails cleanly with its outputs;
# `mpgm check` prints the memory estimate, and a run whose estimate exceeds
# what is available (here an RLIMIT_AS) is refused before anything is
# written.
#
# usage: bash tests/scripts/run_limits.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -u
exe=$1
src=$2
work=$3
rm -rf "$work"
mkdir -p "$work" || exit 1
npass=0
nfail=0
pass() { echo "PASS: $1"; npass=$((npass + 1)); }
fail() { echo "FAIL: $1"; nfail=$((nfail + 1)); }
bar="$src/cases/dyka_bar.json"
quiet=(--set output.vtk=none)

# run NAME ARGS...: `mpgm run ARGS --out WORK/NAME` within 30 s; exit code in
# NAME.rc, stderr in NAME.err
run() {
  local name=$1
  shift
  (timeout 30 "$exe" run "$@" --out "$work/$name" >/dev/null 2>"$work/$name.err") 2>/dev/null
  echo $? >"$work/$name.rc"
}
# summary NAME EXPR: the Python expression EXPR over summary.json's s
summary() {
  /usr/bin/python3 -c 'import json, sys
s = json.load(open(sys.argv[1]))
sys.exit(0 if eval(sys.argv[2]) else 1)' "$work/$1/summary.json" "$2" 2>/dev/null
}
# expect LABEL NAME RC EXPR TEXT: exit RC, summary.json's EXPR true, TEXT on stderr
expect() {
  local label=$1 name=$2 rc=$3 expr=$4 text=$5 got
  got=$(cat "$work/$name.rc")
  if [ "$got" != "$rc" ]; then
    fail "$label: exit $got, expected $rc ($(head -c 300 "$work/$name.err"))"
  elif [ -n "$expr" ] && ! summary "$name" "$expr"; then
    fail "$label: summary.json does not have $expr ($(head -c 300 "$work/$name/summary.json" 2>&1))"
  elif ! grep -qF -- "$text" "$work/$name.err"; then
    fail "$label: stderr does not say \"$text\" ($(head -c 300 "$work/$name.err"))"
  else
    pass "$label"
  fi
}

# 1. Dyka's bar: h / c = 6.595e-7 s. A fixed time.dt 3 % above it fails
# the first step; allowed, the 15 steps of 1e-5 s complete with a warning.
run unstable "$bar" --set time.dt=6.8e-7 --set time.end=1e-5 "${quiet[@]}"
expect "a fixed time.dt above h / c fails the run" unstable 1 \
  's["status"] == "failed" and s["failed_step"] == 1 and "time.dt" in s["message"] and "stability limit" in s["message"]' \
  "time.dt = 6.8e-07 s is 1.031 times the stability limit h / c = 6.59507e-07 s"
run allowed "$bar" --set time.dt=6.8e-7 --set time.end=1e-5 --set time.allow_unstable_dt=true "${quiet[@]}"
expect "time.allow_unstable_dt takes it, with a warning" allowed 0 \
  's["status"] == "completed" and s["counts"]["steps"] == 15' "taken, as time.allow_unstable_dt asks"

# 2. Three times the limit, allowed: the energy balance stops it as diverged.
run diverged "$bar" --set time.dt=2e-6 --set time.allow_unstable_dt=true "${quiet[@]}"
expect "an unstable run allowed is stopped by the energy balance" diverged 1 \
  's["status"] == "failed" and "diverged: the energy grew" in s["message"] and s["failed_step"] < 20' \
  "more than 10 times the largest of the start energy"
# its histories are written as for any failed run
if [ "$(wc -l <"$work/diverged/steps.csv" 2>/dev/null)" -ge 2 ]; then
  pass "the diverged run's steps.csv holds the steps before it"
else
  fail "the diverged run wrote no steps.csv rows"
fi

# 3. E = 1e300 with steps from the CFL condition: ~1e147 steps predicted at
# the first step, stopped at once.
start=$(date +%s)
run stiff "$bar" --set materials.steel.E=1e300 "${quiet[@]}"
expect "E = 1e300 stops at the first step's prediction" stiff 1 \
  's["status"] == "failed" and s["failed_step"] == 1 and "time.max_steps" in s["message"]' \
  "makes about 2.33e+147 steps to time.end"
if [ $(($(date +%s) - start)) -le 10 ]; then pass "... within 10 s"; else fail "E = 1e300 took over 10 s"; fi

# 4. time.max_steps reached before the end. The bar's CFL steps: 1040.2
# predicted from the first, 1043 taken with six output.times (each ends a
# step on it); at 1041 the run stops at step 1042.
run max_cfl "$bar" --set 'output.times=[1e-5,2e-5,3e-5,4e-5,5e-5,6e-5]' --set time.max_steps=1041 \
  "${quiet[@]}"
expect "CFL steps stop at time.max_steps" max_cfl 1 \
  's["status"] == "failed" and s["failed_step"] == 1042 and s["counts"]["steps"] == 1041 and "time.max_steps = 1041 steps done before time.end" in s["message"]' \
  "time.max_steps = 1041 steps done"
# static, 2 load steps, a cut made at step 1 (4 steps then) against 2
MPGM_TEST_FAULT=not_converged:1:1 run max_cut "$src/cases/cantilever.json" --set mesh.h=0.5 \
  --set time.load_steps=2 --set time.max_cuts=2 --set time.max_steps=2 "${quiet[@]}"
expect "cut steps stop at time.max_steps" max_cut 1 \
  's["status"] == "failed" and s["failed_step"] == 3 and s["counts"]["steps"] == 2 and len(s["step_cuts"]) == 1' \
  "time.max_steps = 2 steps done before the full load"
if [ -s "$work/max_cut/probes.csv" ] && [ -s "$work/max_cut/steps.csv" ]; then
  pass "the run stopped at time.max_steps wrote probes.csv and steps.csv"
else
  fail "the run stopped at time.max_steps wrote no histories"
fi

# 5. mpgm check prints the estimate and what is available.
if "$exe" check "$src/cases/cantilever.json" >"$work/check.out" 2>&1 &&
  grep -qE "^memory: the run needs about [0-9.]+ (KiB|MiB) \(2.05e\+03 points, 512 nodes.*; [0-9.]+ GiB available" \
    "$work/check.out"; then
  pass "mpgm check prints the memory estimate: $(grep '^memory:' "$work/check.out" | cut -c1-120)"
else
  fail "mpgm check does not print the estimate: $(tail -c 300 "$work/check.out")"
fi

# 6. Under an RLIMIT_AS of 300 MiB, the cantilever at h = 1/128 (about 500
# MiB estimated, 658 MiB at its peak) is refused as bad input before any
# output; without the limit the same scene checks.
# (a sanitized build cannot start under an address-space limit at all: its
# shadow memory reserves terabytes; there the check is left to the others)
if ! ( (ulimit -v 307200 && "$exe" check "$src/cases/cantilever.json" >/dev/null 2>&1) ) 2>/dev/null; then
  echo "SKIP: RLIMIT_AS: $exe does not run under ulimit -v (a sanitized build)"
else
(ulimit -v 307200 && timeout 30 "$exe" run "$src/cases/cantilever.json" --set mesh.h=0.0078125 \
  --out "$work/rlimit" >/dev/null 2>"$work/rlimit.err")
rc=$?
if [ "$rc" -eq 2 ] && grep -qF "mesh.h: the run needs about" "$work/rlimit.err" &&
  grep -qF "RLIMIT_AS" "$work/rlimit.err" && [ ! -e "$work/rlimit" ]; then
  pass "a run above RLIMIT_AS is refused before anything is written"
else
  fail "RLIMIT_AS: exit $rc, $(head -c 300 "$work/rlimit.err"), folder $(ls -d "$work/rlimit" 2>&1)"
fi
fi
if "$exe" check "$src/cases/cantilever.json" --set mesh.h=0.0078125 >/dev/null 2>"$work/nolimit.err"; then
  pass "the same scene checks without the limit"
else
  fail "the scene is refused without a limit: $(head -c 300 "$work/nolimit.err")"
fi

echo "$npass passed, $nfail failed"
[ "$nfail" -eq 0 ]
