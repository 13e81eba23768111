#!/usr/bin/env bash
# special_files.sh -- regular files only, everywhere a file is read: a FIFO
# (whose open or first read would wait for a writer for ever), a folder,
# /dev/zero (a character device without end), a socket and a symbolic link
# to a FIFO, given in place of the scene of check and run, a study file and
# a study's scene, the CSV of `mpgm plot`, the files of a run folder that
# `mpgm render` reads, a checkpoint, the material driver's input and a
# matrix of bench-solvers: each refused with exit 2 within seconds, the file
# and its kind named, no sanitizer report; a scene larger than its bound (a
# sparse file: refused from its size, without reading it); and FIFOs where
# outputs go: an I/O error at once (exit 3), or replaced (a temporary).
#
# usage: special_files.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$(realpath "$1")"; src="$(realpath "$2")"; work="$3"
rm -rf "$work"; mkdir -p "$work"; work="$(realpath "$work")"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"
scene="$src/cases/cantilever.json"

# refused CODE NEEDLE WHAT CMD...: exit CODE within 10 s (timeout's 124
# otherwise), NEEDLE on stderr, and no sanitizer report there
refused() {
  local code="$1" needle="$2" what="$3"; shift 3
  timeout 10 "$@" > out.txt 2> err.txt < /dev/null; local rc=$?
  if [ $rc -eq "$code" ] && grep -qF -- "$needle" err.txt && ! grep -qE "Sanitizer|runtime error" err.txt; then
    ok "$what (exit $rc)"
  else
    ko "$what: exit $rc (expected $code with '$needle'), stderr: $(head -c 400 err.txt)"
  fi
}

# special FOLDER NAME: make the five kinds as FOLDER/NAME.KIND and print
# "PATH KIND-MESSAGE" lines (the socket when python3 can make one)
special() {
  local d="$1" n="$2"
  mkdir -p "$d"
  mkfifo "$d/$n.fifo" && echo "$d/$n.fifo|is a pipe or FIFO"
  mkdir -p "$d/$n.folder" && echo "$d/$n.folder|is a folder"
  ln -sf /dev/zero "$d/$n.zero" && echo "$d/$n.zero|is a character device"
  ln -sf "$n.fifo" "$d/$n.link" && echo "$d/$n.link|is a pipe or FIFO"
  if python3 -c 'import socket, sys; socket.socket(socket.AF_UNIX).bind(sys.argv[1])' "$d/$n.sock" 2>/dev/null; then
    echo "$d/$n.sock|is a socket"
  fi
}

# --- the scene of check and run ----------------------------------------------
while IFS='|' read -r p kind; do
  refused 2 "$p: $kind, not a regular file" "check: ${p##*/}" "$exe" check "$p"
  refused 2 "$p: $kind, not a regular file" "run: ${p##*/}" "$exe" run "$p" --out "$work/never"
done < <(special "$work/s" scene)
[ ! -e "$work/never" ] && ok "no results folder made for a refused scene" || ko "a results folder was made"
# /dev/zero itself and a pipe for standard input
refused 2 "/dev/zero: is a character device, not a regular file" "check /dev/zero" "$exe" check /dev/zero
refused 2 "/dev/stdin: is a pipe or FIFO, not a regular file" "check /dev/stdin fed by a pipe" \
  bash -c 'exec "$0" check /dev/stdin < <(cat "$1")' "$exe" "$scene"

# --- size bounds: refused from the size, unread -------------------------------
truncate -s 65M big.json
refused 2 "big.json: larger than 64 MiB, the most this file may have" "a scene of 65 MiB" "$exe" check big.json

# --- a study file, and a study's scene ---------------------------------------
while IFS='|' read -r p kind; do
  refused 2 "$p: $kind, not a regular file" "study file: ${p##*/}" "$exe" study "$p" --out "$work/st_never"
done < <(special "$work/st" study)
mkfifo "$work/st/base.json"
printf '{"scene": "%s", "axes": {"mesh.h": [0.5]}}\n' "$work/st/base.json" > st.json
refused 2 "$work/st/base.json: is a pipe or FIFO, not a regular file" "a study's scene that is a FIFO" \
  "$exe" study st.json --out "$work/st_never"
[ ! -e "$work/st_never" ] && ok "no study folder made" || ko "a study folder was made"

# an earlier run's summary.json that is a FIFO: passed over as absent, the
# run runs again and replaces it
printf '{"scene": "%s", "axes": {"mesh.h": [0.5]}, "set": {"output.vtk": "none"}}\n' "$scene" > st_ok.json
"$exe" study st_ok.json --out st_ok --no-plot > /dev/null 2>&1
rm -f st_ok/runs/*/summary.json && mkfifo st_ok/runs/mesh.h=0.5/summary.json
timeout 60 "$exe" study st_ok.json --out st_ok --no-plot > out.txt 2> err.txt < /dev/null; rc=$?
[ $rc -eq 0 ] && [ -f st_ok/runs/mesh.h=0.5/summary.json ] && grep -q "1 now" err.txt \
  && ok "study: an earlier summary.json that is a FIFO is passed over, the run runs again" \
  || ko "study with a FIFO summary.json: exit $rc, $(head -c 300 err.txt)"

# --- the CSV of mpgm plot ------------------------------------------------------
while IFS='|' read -r p kind; do
  refused 2 "$p: $kind, not a regular file" "plot CSV: ${p##*/}" "$exe" plot "$p" --out "$work/pl_never"
done < <(special "$work/pl" study_csv)

# --- the files of a run folder that render and restart read ------------------
"$exe" run "$scene" --quiet --set mesh.h=0.5 --set time.load_steps=3 --set output.checkpoint_every=1 \
  --out run > run.log 2>&1 || { ko "the run for render"; cat run.log; }
cp -r run r_pvd; rm r_pvd/points.pvd; mkfifo r_pvd/points.pvd
refused 2 "r_pvd/points.pvd: is a pipe or FIFO, not a regular file" "render: points.pvd a FIFO" "$exe" render r_pvd
cp -r run r_vtk; rm r_vtk/vtk/points_000003.vtu; mkfifo r_vtk/vtk/points_000003.vtu
refused 2 "r_vtk/vtk/points_000003.vtu: is a pipe or FIFO, not a regular file" "render: a frame a FIFO" \
  "$exe" render r_vtk
cp -r run r_dev; rm r_dev/vtk/points_000003.vtu; ln -s /dev/zero r_dev/vtk/points_000003.vtu
refused 2 "points_000003.vtu: is a character device, not a regular file" "render: a frame a link to /dev/zero" \
  "$exe" render r_dev
# summary.json is optional for render (the view and the discs' size): a
# FIFO there is passed over as an absent one, never waited on
cp -r run r_sum; rm r_sum/summary.json; mkfifo r_sum/summary.json
timeout 10 "$exe" render r_sum > out.txt 2> err.txt < /dev/null; rc=$?
[ $rc -eq 0 ] && [ -s r_sum/render/displacement_t1.png ] && ! grep -qE "Sanitizer|runtime error" err.txt \
  && ok "render: summary.json a FIFO is passed over, the picture drawn (exit $rc)" \
  || ko "render with summary.json a FIFO: exit $rc, $(head -c 300 err.txt)"
cp -r run r_ck; rm r_ck/checkpoint.mpgm; mkfifo r_ck/checkpoint.mpgm
refused 2 "r_ck/checkpoint.mpgm: is a pipe or FIFO, not a regular file" "restart: checkpoint.mpgm a FIFO" \
  "$exe" run --restart r_ck --quiet

# --- the material driver's input ---------------------------------------------
while IFS='|' read -r p kind; do
  refused 2 "$p: $kind, not a regular file" "material input: ${p##*/}" "$exe" material "$p" --out "$work/m.csv"
done < <(special "$work/md" material)
[ ! -e "$work/m.csv" ] && ok "no CSV written for a refused input" || ko "a CSV was written"

# --- a matrix and a right-hand side of bench-solvers -------------------------
"$exe" run "$scene" --quiet --set mesh.h=0.5 --set time.load_steps=1 --set output.vtk=none \
  --set output.matrices=1 --out mx > mx.log 2>&1 || { ko "the run for bench-solvers"; cat mx.log; }
mkdir -p bk bb
k=$(cd mx/matrices && ls *_K.mtx | head -1); b="${k%_K.mtx}_b.mtx"
mkfifo "bk/$k"; cp "mx/matrices/$b" "bk/$b"
cp "mx/matrices/$k" "bb/$k"; ln -s /dev/zero "bb/$b"
refused 2 "bk/$k: is a pipe or FIFO, not a regular file" "bench-solvers: a matrix a FIFO" \
  "$exe" bench-solvers bk --only umfpack --repeat 1
refused 2 "bb/$b: is a character device, not a regular file" "bench-solvers: a right-hand side a link to /dev/zero" \
  "$exe" bench-solvers bb --only umfpack --repeat 1

# --- special files where an output goes: never waited on ---------------------
mkfifo out.fifo
refused 3 "out.fifo: cannot write: a pipe or FIFO that nobody reads" "material --out a FIFO nobody reads" \
  "$exe" material "$src/tests/material_driver/shear_path.json" --out out.fifo
mkdir -p run/render && mkfifo run/render/displacement_t1.png
refused 3 "run/render/displacement_t1.png: is a pipe or FIFO, not a regular file" \
  "render: a FIFO where the picture goes (gnuplot would wait on it)" "$exe" render run
printf 'mesh.h,status,time_s.total,error\n0.5,completed,1,0.1\n0.25,completed,2,0.03\n' > pl/ok.csv
mkfifo pl/study_error_time.svg
refused 3 "pl/study_error_time.svg: is a pipe or FIFO, not a regular file" \
  "plot: a FIFO where a picture goes" "$exe" plot pl/ok.csv
# an atomic output's temporary is a new file: a FIFO there is replaced
mkdir -p tmpf && mkfifo tmpf/summary.json.tmp tmpf/probes.csv.tmp
timeout 60 "$exe" run "$scene" --quiet --set mesh.h=0.5 --set time.load_steps=1 --set output.vtk=none \
  --out tmpf > out.txt 2> err.txt < /dev/null; rc=$?
[ $rc -eq 0 ] && [ -f tmpf/summary.json ] && [ ! -e tmpf/summary.json.tmp ] \
  && ok "run: FIFOs where the temporaries go are replaced, the run completes" \
  || ko "run with FIFO temporaries: exit $rc, $(head -c 300 err.txt)"

echo "$npass passed, $nfail failed"
[ "$nfail" -eq 0 ]
