#!/usr/bin/env bash
# no_overwrite.sh -- no command writes over its own input: an output that is
# the input (--out naming it, a symbolic or a hard link of it, a default
# output name that is the input's), or a results folder holding the scene
# under a name the run writes, is refused with exit 2 before anything is
# written, naming both, and the input is byte-identical afterwards (sha256).
# A scene kept in its results folder under another name, and a restart that
# rewrites its own folder, still run.
#
# usage: no_overwrite.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$(realpath "$1")"; src="$(realpath "$2")"; work="$3"
rm -rf "$work"; mkdir -p "$work"; work="$(realpath "$work")"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"
scene="$src/cases/cantilever.json"

# refused INPUT NEEDLE WHAT CMD...: exit 2, NEEDLE and INPUT's name on
# stderr, INPUT byte-identical afterwards
refused() {
  local input="$1" needle="$2" what="$3"; shift 3
  local before; before=$(sha256sum < "$input")
  timeout 60 "$@" > out.txt 2> err.txt < /dev/null; local rc=$?
  local after; after=$(sha256sum < "$input")
  if [ $rc -eq 2 ] && grep -qF -- "$needle" err.txt && grep -qF -- "$(basename "$input")" err.txt \
    && [ "$before" = "$after" ] && ! grep -qE "Sanitizer|runtime error" err.txt; then
    ok "$what (exit $rc, input unchanged)"
  else
    ko "$what: exit $rc (expected 2 with '$needle'), input $([ "$before" = "$after" ] && echo unchanged || echo CHANGED), stderr: $(head -c 400 err.txt)"
  fi
}

# --- mpgm material -----------------------------------------------------------
mkdir -p md && cp "$src/tests/material_driver/shear_path.json" md/in.json
refused md/in.json "md/in.json: the output would overwrite the input md/in.json" "material --out the input" \
  "$exe" material md/in.json --out md/in.json
ln md/in.json md/hard.csv
refused md/in.json "md/hard.csv: the output is a hard link of the input md/in.json" \
  "material --out a hard link of the input" "$exe" material md/in.json --out md/hard.csv
ln -s in.json md/soft.csv
refused md/in.json "the output would overwrite the input" "material --out a symbolic link to the input" \
  "$exe" material md/in.json --out md/soft.csv
# the default output is the input's name with .csv, in the current folder
cp md/in.json md/path.csv
refused md/path.csv "is the default output" "material: an input named like its default output" \
  bash -c 'cd md && exec "$0" material path.csv' "$exe"
(cd md && "$exe" material in.json > /dev/null 2>&1) && [ -s md/in.csv ] \
  && ok "material: the default output beside an input of another name is written" || ko "material default output"

# --- mpgm run ----------------------------------------------------------------
mkdir -p res/vtk
for name in summary.json probes.csv steps.csv points.pvd mesh.pvd grid.pvd points.vtk.series \
  mesh.vtk.series grid.vtk.series points.xdmf mesh.xdmf results.h5 checkpoint.mpgm; do
  cp "$scene" "res/$name"
  refused "res/$name" "res/$name: the output would overwrite the input res/$name" \
    "run: the scene is the results folder's $name" "$exe" run "res/$name" --out res --quiet --set mesh.h=0.5
  rm "res/$name"
done
cp "$scene" res/vtk/scene.json
refused res/vtk/scene.json "res/vtk: holds the input res/vtk/scene.json" "run: the scene inside the results' vtk/" \
  "$exe" run res/vtk/scene.json --out res --quiet --set mesh.h=0.5
cp "$scene" res/steps.csv.tmp
refused res/steps.csv.tmp "the temporary of an output would overwrite the input" \
  "run: the scene where an output's temporary goes" "$exe" run res/steps.csv.tmp --out res --quiet --set mesh.h=0.5
cp "$scene" scene.json && ln scene.json res/probes.csv
refused scene.json "res/probes.csv: the output is a hard link of the input scene.json" \
  "run: the results' probes.csv a hard link of the scene" "$exe" run scene.json --out res --quiet --set mesh.h=0.5
refused scene.json "scene.json: the output would overwrite the input scene.json" "run --out the scene file itself" \
  "$exe" run scene.json --out scene.json --quiet --set mesh.h=0.5
rm -rf res && mkdir -p res && cp "$scene" res/scene.json
"$exe" run res/scene.json --out res --quiet --set mesh.h=0.5 --set time.load_steps=3 \
  --set output.checkpoint_every=1 > run.log 2>&1 && [ -s res/summary.json ] \
  && ok "run: a scene in its results folder under another name runs" || ko "run in place: $(cat run.log)"
"$exe" run --restart res res/scene.json --quiet --set mesh.h=0.5 --set time.load_steps=3 \
  --set output.checkpoint_every=1 > rs.log 2>&1 \
  && ok "restart: the run rewrites its own folder, checkpoint.mpgm included" || ko "restart: $(cat rs.log)"

# --- mpgm study --------------------------------------------------------------
# a study file called study.json in the folder its results go to (the
# default results folder, results/STEM, relative to the current folder)
mkdir -p results/study
printf '{"scene": "%s", "axes": {"mesh.h": [0.5]}, "set": {"output.vtk": "none"}}\n' "$scene" \
  > results/study/study.json
refused results/study/study.json "results/study/study.json: the output would overwrite the input" \
  "study: the study file where its default results folder writes study.json" "$exe" study results/study/study.json
mkdir -p sr/runs && cp "$scene" sr/runs/base.json
printf '{"scene": "runs/base.json", "axes": {"mesh.h": [0.5]}, "out": "."}\n' > sr/st.json
refused sr/runs/base.json "sr/runs: holds the input $work/sr/runs/base.json" "study: the scene inside the study's runs/" \
  "$exe" study sr/st.json

# --- mpgm plot ---------------------------------------------------------------
printf '{"scene": "%s", "axes": {"mesh.h": [0.5]}, "set": {"output.vtk": "none"}}\n' "$scene" > tiny.json
"$exe" study tiny.json --out tiny --no-plot > study.log 2>&1 || ko "the study for plot: $(cat study.log)"
refused tiny/study.csv "tiny/study.csv: the output would overwrite the input tiny/study.csv" "plot --out the CSV" \
  "$exe" plot tiny/study.csv --out tiny/study.csv
mkdir -p pl && cp tiny/study.csv pl/study_error_h.svg
refused pl/study_error_h.svg "pl/study_error_h.svg: the output would overwrite the input" \
  "plot: a CSV named like the picture it draws" "$exe" plot pl/study_error_h.svg
ln tiny/study.csv pl/study_error_time.png
refused tiny/study.csv "pl/study_error_time.png: the output is a hard link of the input tiny/study.csv" \
  "plot --out: a picture a hard link of the CSV" "$exe" plot tiny/study.csv --out pl

# --- mpgm render -------------------------------------------------------------
"$exe" run "$scene" --quiet --set mesh.h=0.5 --set time.load_steps=2 --out rr > rr.log 2>&1 || ko "run: $(cat rr.log)"
refused rr/points.pvd "rr/points.pvd: the output would overwrite the input rr/points.pvd" \
  "render --sheet the run's points.pvd" "$exe" render rr --sheet rr/points.pvd
refused rr/vtk/points_000002.vtu "the output would overwrite the input rr/vtk/points_000002.vtu" \
  "render --sheet the frame it draws" "$exe" render rr --sheet rr/vtk/points_000002.vtu
refused rr/summary.json "rr/summary.json: the output would overwrite the input rr/summary.json" \
  "render --out the run's summary.json" "$exe" render rr --out rr/summary.json
ln rr/vtk/points_000002.vtu rr/frame.png
refused rr/vtk/points_000002.vtu "is a hard link of the input rr/vtk/points_000002.vtu" \
  "render --sheet a hard link of the frame" "$exe" render rr --sheet rr/frame.png

# --- mpgm bench-solvers ------------------------------------------------------
"$exe" run "$scene" --quiet --set mesh.h=0.5 --set time.load_steps=1 --set output.vtk=none \
  --set output.matrices=1 --out mx > mx.log 2>&1 || ko "run for bench-solvers: $(cat mx.log)"
k=$(cd mx/matrices && ls *_K.mtx | head -1)
refused "mx/matrices/$k" "the output would overwrite the input mx/matrices/$k" "bench-solvers --out a matrix" \
  "$exe" bench-solvers mx --out "mx/matrices/$k" --only umfpack --repeat 1
ln "mx/matrices/${k%_K.mtx}_b.mtx" rhs.csv
refused "mx/matrices/${k%_K.mtx}_b.mtx" "rhs.csv: the output is a hard link of the input" \
  "bench-solvers --out a hard link of a right-hand side" "$exe" bench-solvers mx --out rhs.csv --only umfpack --repeat 1

echo "$npass passed, $nfail failed"
[ "$nfail" -eq 0 ]
