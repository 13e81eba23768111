#!/usr/bin/env bash
# Exit codes of the command line: 3 for I/O errors, 2 for bad usage, with a
# message naming the path; steps.csv reports every step's Newton norms.
# usage: io_errors.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
scene="$src/cases/cantilever.json"
npass=0; nfail=0
expect() { # code, needle, description, command...
  local code="$1" needle="$2" what="$3"; shift 3
  "$@" > "$work/out" 2> "$work/err"; local rc=$?
  if [ $rc -eq "$code" ] && grep -qF -- "$needle" "$work/err"; then
    echo "PASS: $what (exit $rc)"; npass=$((npass + 1))
  else
    echo "FAIL: $what: exit $rc (expected $code), stderr: $(head -c 300 "$work/err")"; nfail=$((nfail + 1))
  fi
}
touch "$work/a_file"
expect 3 "$work/missing.json" "missing scene file is an I/O error naming it" "$exe" run "$work/missing.json"
expect 3 "$work/a_file" "output folder that is a file is an I/O error naming it" \
  "$exe" run "$scene" --quiet --set mesh.h=0.5 --out "$work/a_file/sub"
expect 2 "usage" "no command: usage and exit 2" "$exe"
expect 2 "unknown command" "unknown command" "$exe" frobnicate "$scene"
expect 2 "unknown option" "unknown option" "$exe" run "$scene" --frobnicate
expect 2 "needs a value" "--set without its value" "$exe" run "$scene" --set
expect 2 "no SCENE" "run without a scene" "$exe" run
"$exe" run "$scene" --quiet --set mesh.h=0.5 --set time.load_steps=3 --out "$work/ok" > /dev/null 2>&1
rows=$(tail -n +2 "$work/ok/steps.csv" 2>/dev/null | wc -l)
if [ "$rows" -eq 3 ] && head -1 "$work/ok/steps.csv" | grep -q "newton_iterations,residual_initial,residual,residual_relative,increment_relative"; then
  echo "PASS: steps.csv has one row of Newton norms per step"; npass=$((npass + 1))
else
  echo "FAIL: steps.csv ($rows rows)"; nfail=$((nfail + 1))
fi
# The outputs of step 2 cannot be written (a folder stands where its VTK
# file's temporary goes: the same as a full disk for the writer): exit 3,
# and summary.json says io_error at step 2 with the path, not "completed";
# the outputs of step 1 are kept.
mkdir -p "$work/full/vtk/points_000002.vtu.tmp/busy"
echo '{"status": "completed"}' > "$work/full/summary.json" # an earlier run's
"$exe" run "$scene" --quiet --set mesh.h=0.5 --set time.load_steps=4 --out "$work/full" > "$work/out" 2> "$work/err"
rc=$?
/usr/bin/python3 - "$work/full" "$rc" <<'PY' && npass=$((npass + 1)) || nfail=$((nfail + 1))
import json, os, sys
d, rc = sys.argv[1], int(sys.argv[2])
s = json.load(open(f"{d}/summary.json"))
ok = (rc == 3 and s["status"] == "io_error" and s.get("failed_step") == 2 and "points_000002.vtu" in s["message"]
      and s["counts"]["steps"] == 2 and os.path.exists(f"{d}/vtk/points_000001.vtu"))
print(("PASS" if ok else "FAIL") + f": outputs of step 2 cannot be written: exit {rc} (3), status {s['status']} "
      f"(io_error) at step {s.get('failed_step')} (2), message '{s['message'][:90]}', step 1's VTK kept")
sys.exit(0 if ok else 1)
PY
echo "$npass passed, $nfail failed"
[ $nfail -eq 0 ]
