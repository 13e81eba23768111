#!/usr/bin/env bash
# `mpgm study` and `mpgm plot` (docs/studies.md): a tiny cantilever study
# (FEM and GMM-MLS at h = 0.5 and 0.25) gives study.csv with one row per
# run, the run keys, status and the summaries' metrics, the same numbers as
# `mpgm run`, and PNG + SVG plots; a second call skips every run; a study
# killed (SIGTERM, SIGKILL) and called again completes, re-running only what
# had no summary; a changed scene makes its runs stale, a summary from
# before a new scene key (at its default) does not; a run that fails at
# a step and one with bad input found at mesh time are rows, not the end of
# the study; bad study files stop with exit 2 and the JSON path; `mpgm plot`
# without gnuplot on PATH says so and exits 3.
# usage: study.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$(realpath "$1")"; src="$(realpath "$2")"; work="$3"
rm -rf "$work"; mkdir -p "$work"; work="$(realpath "$work")"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"
scene="$src/cases/cantilever.json"

# --- the tiny study: 2 configurations x 2 mesh sizes ------------------------
cat > tiny.json <<EOF
{"scene": "$scene",
 "runs": [{"method": "fem"}, {"method": "gmm", "shape.kind": "mls"}],
 "axes": {"mesh.h": [0.5, 0.25]},
 "set": {"output.vtk": "none"},
 "out": "tiny_out"}
EOF
"$exe" study tiny.json > tiny1.out 2> tiny1.err; rc=$?
[ $rc -eq 0 ] && ok "tiny study exits 0" || { ko "tiny study exit $rc:"; cat tiny1.err; }
grep -q "\[4/4\] completed" tiny1.err && ok "progress lines on stderr ([4/4] completed)" || ko "progress: $(cat tiny1.err)"
"$exe" run "$scene" --quiet --set output.vtk=none --set method=gmm --set shape.kind=mls --set mesh.h=0.25 \
  --out direct > /dev/null 2>&1
stamp=$(stat -c %Y.%N "tiny_out/runs/method=fem,mesh.h=0.25/summary.json" 2>/dev/null)
sleep 1.1
"$exe" study tiny.json > tiny2.out 2> tiny2.err; rc=$?
[ $rc -eq 0 ] && [ "$(grep -c "skip" tiny2.err)" -eq 4 ] && ! grep -q "running" tiny2.err \
  && ok "second call skips the 4 complete runs" || ko "second call (exit $rc): $(cat tiny2.err)"
[ -n "$stamp" ] && [ "$stamp" = "$(stat -c %Y.%N "tiny_out/runs/method=fem,mesh.h=0.25/summary.json")" ] \
  && ok "a skipped run's summary.json is untouched" || ko "summary.json rewritten on skip"
# a run whose outputs could not be written (status io_error) is not a
# result: the next call runs it again, and skips the others
io_run="tiny_out/runs/method=fem,mesh.h=0.5"
sed -i 's/"status":[[:space:]]*"completed"/"status": "io_error"/' "$io_run/summary.json"
"$exe" study tiny.json > tiny_io.out 2> tiny_io.err; rc=$?
[ $rc -eq 0 ] && [ "$(grep -c "skip" tiny_io.err)" -eq 3 ] && grep -q "\[.*\] completed" tiny_io.err \
  && grep -Eq '"status":[[:space:]]*"completed"' "$io_run/summary.json" \
  && ok "a run that ended in io_error runs again, the 3 others are skipped" \
  || ko "io_error run not rerun (exit $rc): $(cat tiny_io.err)"
for f in study_error_h.png study_error_time.png study_error_h.svg study_error_time.svg; do
  [ -s "tiny_out/$f" ] || ko "tiny_out/$f missing or empty"
done
rm -f tiny_out/study_error_*;
"$exe" plot tiny_out/study.csv > plot.out 2> plot.err; rc=$?
[ $rc -eq 0 ] && ok "mpgm plot redraws from study.csv" || ko "mpgm plot exit $rc: $(cat plot.err)"
expect 3 "gnuplot not found on PATH" "mpgm plot without gnuplot on PATH: message, exit 3" \
  env PATH="$work/nowhere" "$exe" plot tiny_out/study.csv
expect 2 "no metric \"nosuch\"" "mpgm plot --metric of no column: exit 2" "$exe" plot tiny_out/study.csv --metric nosuch
expect 3 "cannot open" "mpgm plot of a missing file: exit 3" "$exe" plot "$work/none.csv"
# a study.csv written by hand: units on the axes of known keys and metrics,
# none on an unknown one, --y for any metric, and nothing drawable is exit 2
mkdir -p hand
printf '%s\n' 'mesh.h,method,status,dir,metrics.error,metrics.tip_uy,metrics.frob,time_s.total' \
  '0.5,fem,completed,a,0.01,-0.2,1,1.5' '0.25,fem,completed,b,0.003,-0.21,2,3.1' '0.5,gmm,failed,c,,,,' > hand/study.csv
"$exe" plot hand/study.csv > hand.out 2> hand.err; rc=$?
[ $rc -eq 0 ] && grep -q "set xlabel 'mesh.h \[m\]" hand/study_error_h.gp && grep -q "set ylabel 'metrics.error \[m\]'" hand/study_error_h.gp \
  && grep -q "set xlabel 'wall time of the run \[s\]" hand/study_error_time.gp \
  && ok "plot: units on the axes (mesh.h [m], metrics.error [m], wall time [s])" || ko "plot units (exit $rc): $(cat hand.err)"
"$exe" plot hand/study.csv --y frob > hand2.out 2> hand2.err; rc=$?
[ $rc -eq 0 ] && grep -q "set ylabel 'metrics.frob' noenhanced" hand/study_error_h.gp \
  && ok "plot --y: an unknown metric gets no unit" || ko "plot --y frob (exit $rc): $(cat hand2.err)"
expect 2 "no completed run has a positive finite metrics.tip_uy" "plot: nothing drawable (negative on log axes): exit 2" \
  "$exe" plot hand/study.csv --y tip_uy
"$exe" plot hand/study.csv --y tip_uy --yscale signed --xscale linear > hand3.out 2> hand3.err; rc=$?
[ $rc -eq 0 ] && grep -q "set xzeroaxis" hand/study_error_h.gp && ! grep -q "logscale" hand/study_error_h.gp \
  && grep -q "ylabel 'metrics.tip_uy \[m\]'" hand/study_error_h.gp && grep -q -- "^0.25 -0.2" hand/study_error_h.gp \
  && ok "plot --yscale signed --xscale linear: a negative metric on linear axes" || ko "signed (exit $rc): $(cat hand3.err)"
"$exe" plot hand/study.csv --x time_s.total --y metrics.frob --xscale linear --yscale linear > hand4.out 2> hand4.err; rc=$?
[ $rc -eq 0 ] && grep -q "set xlabel 'time_s.total \[s\]" hand/study_error_total.gp \
  && ok "plot --x of a result column (time_s.total [s])" || ko "--x time_s.total (exit $rc): $(cat hand4.err)"
expect 2 "--yscale: expected linear, log or signed" "plot: bad --yscale: exit 2" "$exe" plot hand/study.csv --yscale cubic
expect 2 "--x nosuch: no such column" "plot: --x of no column: exit 2" "$exe" plot hand/study.csv --x nosuch
printf '%s\n' 'mesh.h,status,dir,metrics.error,time_s.total' '0.5,failed,a,,' > hand/none.csv
expect 2 "no completed run" "plot: no completed row: exit 2" "$exe" plot hand/none.csv
env PATH="$work/nowhere" "$exe" study tiny.json --out nognu > /dev/null 2> nognu.err; rc=$?
[ $rc -eq 3 ] && grep -q "gnuplot not found" nognu.err && grep -q "study.csv is complete" nognu.err \
  && [ -s nognu/study.csv ] && ok "mpgm study without gnuplot: runs done, study.csv written, exit 3" \
  || ko "mpgm study without gnuplot (exit $rc): $(cat nognu.err)"

# --- resume after a kill: 6 runs of 0.1-1 s, the study killed as soon as
# its first run has finished ----------------------------------------------
cat > slow.json <<EOF
{"scene": "$scene", "runs": [{"method": "gmm", "shape.kind": "lme"}],
 "axes": {"shape.gamma": [1.2, 1.8, 2.4], "mesh.h": [0.125, 0.0625]},
 "set": {"output.vtk": "none"}}
EOF
for sig in TERM KILL; do
  "$exe" study slow.json --out "slow_$sig" --no-plot > /dev/null 2> "slow_$sig.1.err" &
  pid=$!
  for i in $(seq 1 600); do
    ls slow_$sig/runs/*/summary.json > /dev/null 2>&1 && break
    sleep 0.05
  done
  kill -$sig $pid; wait $pid 2> /dev/null
  sleep 0.3
  left=$(pgrep -f -- "--out $work/slow_$sig/" | wc -l)
  [ "$left" -eq 0 ] && ok "SIG$sig of the study leaves no run behind" || ko "SIG$sig: $left runs still alive"
  # (a run the study stopped may leave a summary of status "interrupted":
  # not a result, it runs again)
  nsum=$(grep -l '"status":[[:space:]]*"completed"' slow_$sig/runs/*/summary.json 2>/dev/null | wc -l)
  "$exe" study slow.json --out "slow_$sig" --no-plot > /dev/null 2> "slow_$sig.2.err"; rc=$?
  nskip=$(grep -c " skip " "slow_$sig.2.err"); nrun=$(grep -c " running " "slow_$sig.2.err")
  [ $rc -eq 0 ] && [ "$nsum" -ge 1 ] && [ "$nsum" -lt 6 ] && [ "$nskip" -eq "$nsum" ] && [ $((nskip + nrun)) -eq 6 ] \
    && ok "killed by SIG$sig with $nsum of 6 summaries: the next call skips $nskip, runs $nrun, exit 0" \
    || ko "resume after SIG$sig: exit $rc, $nsum summaries, $nskip skipped, $nrun run: $(cat slow_$sig.2.err)"
done
grep -q "stopping" slow_TERM.1.err && ok "SIGTERM: the study says it stops its runs" || ko "SIGTERM message: $(cat slow_TERM.1.err)"

# --- a changed scene makes the runs stale ----------------------------------
cp "$scene" mine.json
cat > stale.json <<EOF
{"scene": "mine.json", "axes": {"mesh.h": [0.5]}, "set": {"output.vtk": "none"}}
EOF
"$exe" study stale.json --no-plot > /dev/null 2>&1
sed -i 's/"E": 90.0e6/"E": 95.0e6/' mine.json
"$exe" study stale.json --no-plot > /dev/null 2> stale.err; rc=$?
[ $rc -eq 0 ] && grep -q "stale" stale.err && grep -q "completed" stale.err \
  && ok "a run of a changed scene is stale and runs again" || ko "stale (exit $rc): $(cat stale.err)"
# a summary written before a scene key existed (the key absent; an absent
# optional object written as {}) is of the same scene when the key's default
# is the old behaviour: not stale; a value that differs still is
sum="results/stale/runs/mesh.h=0.5/summary.json"
python3 - "$sum" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
del s["scene"]["time"]["max_cuts"]
s["scene"]["bodies"][0]["geostatic"] = {}
json.dump(s, open(sys.argv[1], "w"))
PY
"$exe" study stale.json --no-plot > /dev/null 2> old.err; rc=$?
[ $rc -eq 0 ] && grep -q "\] skip " old.err && ! grep -q "\] running" old.err \
  && ok "a summary from before a new scene key (default = old behaviour) is not stale" || ko "old summary (exit $rc): $(cat old.err)"
python3 - "$sum" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["scene"]["time"]["max_cuts"] = 3
json.dump(s, open(sys.argv[1], "w"))
PY
"$exe" study stale.json --no-plot > /dev/null 2> old2.err; rc=$?
[ $rc -eq 0 ] && grep -q "\] stale " old2.err \
  && ok "a summary with another value of the new key is stale" || ko "new key changed (exit $rc): $(cat old2.err)"

# --- failed and bad-input runs are rows ------------------------------------
# (the bad input: MPM's grid of 5.9e7 nodes over a long domain, refused when
# the grid is made; a fine mesh.h is refused sooner, by the memory estimate
# when the scene loads, which stops the study before any run)
cat > fail.json <<EOF
{"scene": "$scene", "set": {"output.vtk": "none"},
 "runs": [{"mesh.h": 0.5},
          {"mesh.h": 0.25, "gravity": [0, 0], "time.load_steps": 10,
           "boundaries": [{"x": 0, "fix": ["x", "y"]}, {"x": 8, "fix": ["x"], "displacement": [-9, 0]}]},
          {"method": "mpm", "mesh.domain": {"min": [-0.5, -3], "max": [200000, 1.5]}}]}
EOF
"$exe" study fail.json --no-plot > /dev/null 2> fail.err; rc=$?
[ $rc -eq 1 ] && ok "a study with a failed run exits 1" || ko "failed runs: exit $rc: $(cat fail.err)"

# --- bad study files: exit 2 with the path ----------------------------------
printf '{"scene": "%s",\n "axes": {"mesh.h": [0.5,]}}\n' "$scene" > b1.json
expect 2 "b1.json: line 2, column" "JSON syntax error: line and column" "$exe" study b1.json
echo '[1]' > b2.json
expect 2 "b2.json: (root): expected an object, found an array" "root not an object" "$exe" study b2.json
echo '{"axes": {"mesh.h": [0.5]}}' > b3.json
expect 2 "b3.json: scene: required key is missing" "scene missing" "$exe" study b3.json
echo "{\"scene\": \"$scene\", \"axes\": {\"mesh.h\": 0.5}}" > b4.json
expect 2 "b4.json: axes.mesh.h: expected a non-empty array of values, found a number" "axis not an array" \
  "$exe" study b4.json
echo "{\"scene\": \"$scene\", \"axes\": {\"mesh.h\": [0.5]}, \"frobnicate\": 1}" > b5.json
expect 2 "b5.json: frobnicate: unknown key" "unknown key" "$exe" study b5.json
echo "{\"scene\": \"$scene\", \"axes\": {\"mesh.h\": [0.5]}, \"jobs\": 0}" > b6.json
expect 2 "b6.json: jobs: expected an integer in [1, 64], found 0" "jobs out of range" "$exe" study b6.json
echo "{\"scene\": \"$scene\", \"axes\": {\"mesh.hh\": [0.5, 0.25]}, \"out\": \"b7_out\"}" > b7.json
expect 2 "mesh.hh: unknown path" "a typo in an axis key stops the study before any run" "$exe" study b7.json
[ ! -e b7_out ] && ok "nothing was run or written for a bad axis key" || ko "b7_out was created"
echo "{\"scene\": \"$scene\", \"axes\": {\"mesh.h\": [0.5, -1]}}" > b8.json
expect 2 "mesh.h: expected a number in (0, inf), found -1" "a bad value in an axis" "$exe" study b8.json
echo "{\"scene\": \"$scene\", \"axes\": {\"mesh.h\": [0.5]}, \"set\": {\"mesh.h\": 1}}" > b9.json
expect 2 "b9.json: set.mesh.h: also an axis" "a key both in axes and set" "$exe" study b9.json
echo "{\"scene\": \"$scene\"}" > b10.json
expect 2 "no runs" "no axes and no runs" "$exe" study b10.json
echo "{\"scene\": \"$scene\", \"runs\": [{\"method\": \"fem\"}, 3]}" > b11.json
expect 2 "b11.json: runs.1: expected an object" "a runs entry not an object" "$exe" study b11.json
echo "{\"scene\": \"nope.json\", \"axes\": {\"mesh.h\": [0.5]}}" > b12.json
expect 3 "nope.json: cannot open" "a missing scene: exit 3" "$exe" study b12.json
expect 3 "missing.json: cannot open" "a missing study file: exit 3" "$exe" study missing.json
expect 2 "--jobs: expected an integer" "--jobs 0" "$exe" study tiny.json --jobs 0
expect 2 "unknown option" "unknown option" "$exe" study tiny.json --frobnicate
expect 2 "no STUDY" "no study file" "$exe" study

/usr/bin/python3 - "$work" "$src" <<'PY'
import csv, json, sys
sys.path.insert(0, sys.argv[2] + "/tests/tools")
from script_check import check, done
w = sys.argv[1]
rows = list(csv.DictReader(open(f"{w}/tiny_out/study.csv")))
head = next(csv.reader(open(f"{w}/tiny_out/study.csv")))
check(len(rows) == 4, f"study.csv: one row per run ({len(rows)})")
check(head[:6] == ["method", "mesh.h", "shape.kind", "output.vtk", "status", "message"],
      f"study.csv starts with the run keys, the set keys, status, message: {head[:6]}")
check(all(r["status"] == "completed" and r["exit_code"] == "0" for r in rows), "every run completed, exit code 0")
check([(r["method"], r["shape.kind"], r["mesh.h"]) for r in rows] ==
      [("fem", "", "0.5"), ("fem", "", "0.25"), ("gmm", "mls", "0.5"), ("gmm", "mls", "0.25")],
      "run order: the runs entries, the axis varying fastest; empty cell for a key a run lacks")
check(all(c in head for c in ("counts.dofs", "time_s.total", "metrics.error", "metrics.tip_uy", "summary.method")),
      "summary columns: counts, time split, metrics (a summary value named like a key gets summary.)")
d = json.load(open(f"{w}/direct/summary.json"))["metrics"]["error"]
check(float(rows[3]["metrics.error"]) == d, f"the study's metric is the direct run's to the last digit ({d})")
check(rows[3]["dir"] == "runs/method=gmm,shape.kind=mls,mesh.h=0.25", f"run folder named by its keys: {rows[3]['dir']}")
s = json.load(open(f"{w}/tiny_out/study.json"))
check(len(s["run_list"]) == 4 and s["metric"] == "error", "study.json records the resolved study")
for name in ("study_error_h", "study_error_time"):
    png = open(f"{w}/tiny_out/{name}.png", "rb").read()
    svg = open(f"{w}/tiny_out/{name}.svg").read()
    check(png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000, f"{name}.png is a PNG ({len(png)} bytes)")
    check("<svg" in svg and "</svg>" in svg and "GMM-MLS" in svg, f"{name}.svg is an SVG with the series")
out = open(f"{w}/plot.out").read()
check("observed order, FEM: 1.87" in out, "mpgm plot prints the observed order (FEM 0.5 -> 0.25: 1.87)")
rows = list(csv.DictReader(open(f"{w}/results/fail/study.csv")))
st = [r["status"] for r in rows]
check(st == ["completed", "failed", "bad input"], f"failed and bad-input runs are rows: {st}")
check("step 9" in rows[1]["message"] and rows[1]["exit_code"] == "1", f"failed run: message {rows[1]['message'][:60]}")
check("mesh.h" in rows[2]["message"] and rows[2]["exit_code"] == "2", f"bad input run: {rows[2]['message'][:70]}")
# the failed run's metrics are apart from the completed run's, with the
# load factor and step they were taken at (step 8 of 10 converged)
f = rows[1]
check(rows[0]["metrics.tip_uy"] != "" and f.get("metrics.tip_uy", "") == "" and f["metrics_at_stop.tip_uy"] != ""
      and abs(float(f["metrics_at_stop.t"]) - 0.8) < 1e-12 and f["metrics_at_stop.step"] == "8",
      f"failed run: metrics_at_stop (t {f.get('metrics_at_stop.t')}, step {f.get('metrics_at_stop.step')}), "
      f"no metrics.* ({f.get('metrics.tip_uy')!r})")
check(all(len(list(csv.DictReader(open(f"{w}/slow_{s}/study.csv")))) == 6 and
          all(r["status"] == "completed" for r in csv.DictReader(open(f"{w}/slow_{s}/study.csv")))
          for s in ("TERM", "KILL")), "resumed studies: 6 rows, all completed")
done()
PY
pyrc=$?
echo "$npass passed, $nfail failed (shell checks)"
[ $nfail -eq 0 ] && [ $pyrc -eq 0 ]
