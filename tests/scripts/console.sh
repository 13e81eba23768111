#!/usr/bin/env bash
# console.sh -- what a run prints when its console is a file: no escape
# codes, no carriage returns, progress as plain lines (every
# MPGM_PROGRESS_INTERVAL seconds), the summary line last (also of a failed
# run); help for every command; a folder holding another scene's run is
# refused unless --force.
#
# usage: console.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$(realpath "$1")"; src="$(realpath "$2")"; work="$3"
rm -rf "$work"; mkdir -p "$work"; work="$(realpath "$work")"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"
scene="$src/cases/cantilever.json"

clean() { ! grep -q $'\033' "$1" && ! grep -q $'\r' "$1"; }

MPGM_PROGRESS_INTERVAL=0 "$exe" run "$scene" --set time.load_steps=4 --out a > out.txt 2> err.txt; rc=$?
last=$(tail -n 1 out.txt)
if [ $rc -eq 0 ] && clean out.txt && clean err.txt && [[ "$last" == "summary: completed, 4 steps, 0 step cuts, metrics: error = "*", wall "*" s, results $work/a" ]]; then
  ok "a run into a file: no escape codes, the summary line last ($last)"
else ko "run into a file: rc $rc, last line '$last'"; fi
[ "$(grep -c '^step [0-9]' err.txt)" -ge 2 ] && ok "plain progress lines" || ko "progress lines: $(cat err.txt)"
grep -q "ETA --" err.txt && ok "no ETA from the first step" || ko "first ETA: $(head -1 err.txt)"

"$exe" run "$scene" --set time.load_steps=4 --out a > out.txt 2> err.txt; rc=$?
[ $rc -eq 0 ] && grep -q "running it again in place" err.txt && ok "the same scene runs again in place, said" || ko "same scene again: rc $rc"
"$exe" run "$scene" --set mesh.h=0.5 --out a > out.txt 2> err.txt; rc=$?
[ $rc -eq 2 ] && grep -q "a holds a completed run of another scene" err.txt && grep -q -- "--force" err.txt \
  && ok "another scene refused (exit 2)" || ko "refusal: rc $rc $(cat err.txt)"
"$exe" run "$scene" --set mesh.h=0.5 --out a --force > out.txt 2> err.txt; rc=$?
[ $rc -eq 0 ] && grep -q "replacing it (--force)" err.txt && ok "--force replaces it" || ko "--force: rc $rc"

MPGM_TEST_FAULT=not_converged:2:1000 "$exe" run "$scene" --set time.load_steps=4 --out f > out.txt 2> err.txt; rc=$?
last=$(tail -n 1 out.txt)
if [ $rc -eq 1 ] && clean out.txt && clean err.txt && [[ "$last" == "summary: failed, "*"results $work/f" ]]; then
  ok "a failed run ends with the summary line"
else ko "failed run: rc $rc, last '$last'"; fi

for c in run check material study plot render bench-solvers help version; do
  "$exe" "$c" --help > h.txt 2>&1; r1=$?
  "$exe" help "$c" > h2.txt 2>&1; r2=$?
  "$exe" "$c" -h > h3.txt 2>&1; r3=$?
  if [ $r1 -eq 0 ] && [ $r2 -eq 0 ] && [ $r3 -eq 0 ] && grep -q "usage: mpgm $c" h.txt && cmp -s h.txt h2.txt \
    && { [ "$c" = help ] || [ "$c" = version ] || grep -q -- "  --" h.txt; }; then
    ok "help for $c"
  else ko "help for $c: $r1 $r2 $r3"; fi
done
grep -q -- "--yscale" <("$exe" plot --help) && ok "plot's help names --x --y --yscale" || ko "plot help"
"$exe" help > h.txt; [ $? -eq 0 ] && grep -q "usage: mpgm run" h.txt && ok "mpgm help" || ko "mpgm help"
echo "$npass passed, $nfail failed"
[ "$nfail" -eq 0 ]
