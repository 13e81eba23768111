#!/usr/bin/env bash
# A file named where mpgm expects one of its own (a scene, a study's scene,
# a frame of a .pvd) is not repeated in an error when it is not what was
# expected, and a .pvd cannot name a frame outside its run's folder: a file
# from elsewhere (a study, a results folder) must not make mpgm read or show
# /etc/shadow (docs/scene-format.md, "Files a run reads and writes").
# usage: no_echo.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$(realpath "$1")"; src="$(realpath "$2")"; work="$3"
rm -rf "$work"; mkdir -p "$work"; work="$(realpath "$work")"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"
secret="s3cr3t-token-$$"
printf '%s:x:0:0\n' "$secret" > secret.txt

# refused CODE LABEL CMD...: exit CODE, and the secret nowhere in what it said
refused() {
  local code="$1" what="$2"; shift 2
  "$@" > out.txt 2> err.txt; local rc=$?
  if [ $rc -eq "$code" ] && ! grep -q "$secret" out.txt err.txt; then ok "$what (exit $rc)"
  else ko "$what: exit $rc, said: $(head -c 300 err.txt)"; fi
}

refused 2 "a scene that is not JSON is not repeated" "$exe" check secret.txt
refused 2 "... nor by mpgm run" "$exe" run secret.txt --out r0
refused 2 "a material input that is not JSON is not repeated" "$exe" material secret.txt --out m.csv
printf '{"scene": "%s/secret.txt", "axes": {"mesh.h": [0.5]}}\n' "$work" > study.json
"$exe" study study.json --out st --no-plot > /dev/null 2> study.err
! grep -rq "$secret" study.err st 2>/dev/null && ok "a study naming it as its scene leaves it out of its records" \
  || ko "the study repeated the file: $(grep -rl "$secret" study.err st)"

"$exe" run "$src/cases/cantilever.json" --set mesh.h=0.5 --quiet --out run > /dev/null 2>&1
cp run/points.pvd points.keep
sed -i "s#vtk/points_000001.vtu#../secret.txt#" run/points.pvd
refused 2 "a .pvd frame outside the run's folder is refused" "$exe" render run
grep -q "inside the run's folder" err.txt && ok "... saying why" || ko "message: $(head -c 300 err.txt)"
sed -i "s#../secret.txt#$work/secret.txt#" run/points.pvd
refused 2 "a .pvd frame by an absolute path is refused" "$exe" render run
cp points.keep run/points.pvd
cp secret.txt run/vtk/points_000001.vtu
refused 2 "a frame that is not VTK is not repeated" "$exe" render run

echo "$npass passed, $nfail failed"
[ $nfail -eq 0 ]
