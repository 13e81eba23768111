#!/usr/bin/env bash
# A run stopped by SIGINT (Ctrl-C) or SIGTERM (a batch system's time limit,
# a study being stopped) ends after the step in progress: exit code 128 +
# the signal, summary.json with status "interrupted" saying after which
# step, the histories up to that step, and a checkpoint that
# `mpgm run --restart` continues to the end. MPM reuses nothing across
# steps, so its continued run is the uninterrupted one to the last bit;
# GMM rebuilds its kept pattern at the stop, and agrees to Newton's
# tolerance (a few 1e-7 relative on the disk's error, 1e-9 on its centre).
# usage: interrupt.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail=0
check() { if [ "$1" != 0 ]; then echo "FAIL: $2"; fail=1; fi; }

# NAME SIGNAL TOL ARGS...: the reference run, the stopped one, its restart
case_run() {
  local name="$1" sig="$2" tol="$3"; shift 3
  "$exe" run "$@" --set output.vtk=none --out "$work/$name.ref" > /dev/null 2>&1
  check $? "$name: the reference run"
  local wall
  wall=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['time_s']['total'])" \
    "$work/$name.ref/summary.json" 2>/dev/null || echo 1)
  "$exe" run "$@" --set output.vtk=none --out "$work/$name" > "$work/$name.out" 2> "$work/$name.err" &
  local pid=$!
  # once the results folder exists the run is set up, and a signal stops it
  # with its records (before, in the set-up, it ends the process at once)
  for _ in $(seq 1 600); do [ -d "$work/$name" ] && break; sleep 0.05; done
  sleep "$(python3 -c "print(max(0.2, $wall / 3))")"
  kill "-$sig" "$pid"
  wait "$pid"
  local rc=$? want=$((128 + $(kill -l "$sig")))
  check $((rc != want)) "$name: exit code $rc after SIG$sig, expected $want"
  grep -q "interrupted after step .*continue with: mpgm run --restart" "$work/$name.err"
  check $? "$name: no message saying where the run stopped and how to continue"
  python3 - "$work/$name" <<'PY'
import csv, json, os, sys
d = sys.argv[1]
s = json.load(open(f"{d}/summary.json"))
assert s["status"] == "interrupted", f"status {s['status']}"
k = s["counts"]["steps"]
assert f"after step {k} " in s["message"], s["message"]
rows = list(csv.DictReader(open(f"{d}/steps.csv")))
assert rows and int(rows[-1]["step"]) == k, f"steps.csv ends at {rows[-1]['step'] if rows else None}, not {k}"
assert os.path.exists(f"{d}/checkpoint.mpgm"), "no checkpoint"
PY
  check $? "$name: the stopped run's records"
  "$exe" run --restart "$work/$name" > /dev/null 2> "$work/$name.restart.err"
  check $? "$name: the restart"
  python3 - "$work/$name.ref" "$work/$name" "$tol" <<'PY'
import json, sys
a, b = (json.load(open(f"{d}/summary.json")) for d in sys.argv[1:3])
tol = float(sys.argv[3])
assert b["status"] == "completed", b["status"]
assert a["counts"]["steps"] == b["counts"]["steps"], (a["counts"]["steps"], b["counts"]["steps"])
for k, v in a["metrics"].items():
    w = b["metrics"][k]
    # tol relative, with 1e-8 absolute (Newton's tolerance) for values near 0
    assert abs(v - w) <= tol * abs(v) + (1e-8 if tol else 0.0), f"{k}: {v!r} against {w!r} (tolerance {tol:g})"
PY
  check $? "$name: the restarted run against the uninterrupted one"
}

case_run mpm_column INT 0 "$src/cases/column_collapse.json" --set mesh.h=0.1
case_run gmm_disk TERM 1e-6 "$src/cases/rolling_disk.json" --set method=gmm --set shape.kind=mls \
  --set mesh.h=0.05 --set time.end=0.3

[ $fail -eq 0 ] && echo "interrupt: ok"
exit $fail
