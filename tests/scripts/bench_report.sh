#!/usr/bin/env bash
# docs/benchmarks.md is what `bench/report` assembles: every generated
# section under its <!-- bench/PART --> line, and every file of notes in
# bench/notes/ exactly as committed. Notes edited in the record (which the
# next report would throw away) or committed notes that never reached it
# fail here; so must bench/report's refusals of a bad option or part.
# usage: bench_report.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail=0
"$src/bench/report" --check || { echo "FAIL: docs/benchmarks.md is not what bench/report assembles"; fail=1; }
# the refusals: a non-zero exit and a message naming the mistake, nothing written
before=$(md5sum "$src/docs/benchmarks.md")
for args in "--check column_collapse" "--no-run no_such_part" "--bogus" "column_collapse"; do
  # (a timeout: were a refusal lost, a bare call would start every benchmark)
  # shellcheck disable=SC2086
  if timeout 60 "$src/bench/report" $args > "$work/out" 2> "$work/err"; then
    echo "FAIL: bench/report $args succeeded"; fail=1
  elif ! grep -q "bench/report:" "$work/err"; then
    echo "FAIL: bench/report $args: no message"; cat "$work/err"; fail=1
  fi
done
[ "$(md5sum "$src/docs/benchmarks.md")" = "$before" ] || { echo "FAIL: a refused call changed the record"; fail=1; }
# a copy of the tree with the record edited by hand is caught, naming the file to edit
mkdir -p "$work/tree/bench/notes" "$work/tree/docs"
cp "$src/bench/report" "$src/bench/compact.py" "$work/tree/bench/"
cp "$src/bench/notes/"*.md "$work/tree/bench/notes/"
sed 's|^The full record, the notes and the history: \[bench/notes/solvers.md\]|The notes: [bench/notes/solvers.md]|' "$src/docs/benchmarks.md" > "$work/tree/docs/benchmarks.md"
cmp -s "$work/tree/docs/benchmarks.md" "$src/docs/benchmarks.md" && { echo "FAIL: the hand edit of the test did not apply"; fail=1; }
if "$work/tree/bench/report" --check > "$work/out" 2> "$work/err"; then
  echo "FAIL: a hand edit of the notes in the record passed the check"; fail=1
elif ! grep -q "edit bench/notes/PART.md" "$work/err"; then
  echo "FAIL: the check did not say where to edit"; cat "$work/err"; fail=1
fi
# --notes puts the committed notes back; the record then passes again
"$work/tree/bench/report" --notes > /dev/null && "$work/tree/bench/report" --check > /dev/null \
  && cmp -s "$work/tree/docs/benchmarks.md" "$src/docs/benchmarks.md" \
  || { echo "FAIL: bench/report --notes did not restore the record"; fail=1; }
# the report a user reads: about 500 lines at most, and every picture it shows is there
n=$(wc -l < "$src/docs/benchmarks.md")
[ "$n" -le 550 ] || { echo "FAIL: docs/benchmarks.md has $n lines (at most about 500)"; fail=1; }
for img in $(grep -o '](img/[^)]*)' "$src/docs/benchmarks.md" | sed 's/^](//; s/)$//'); do
  [ -f "$src/docs/$img" ] || { echo "FAIL: docs/benchmarks.md shows $img, which does not exist"; fail=1; }
done
for f in $(grep -o '](../bench/notes/[^)]*)' "$src/docs/benchmarks.md" | sed 's/^](..\///; s/)$//'); do
  [ -f "$src/$f" ] || { echo "FAIL: docs/benchmarks.md links $f, which does not exist"; fail=1; }
done
[ $fail -eq 0 ] && echo "bench_report: ok"
exit $fail
