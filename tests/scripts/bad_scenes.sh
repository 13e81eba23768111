#!/usr/bin/env bash
# bad_scenes.sh -- every malformed scene in tests/bad_scenes (and every bad
# --set of tests/bad_scenes/expected.txt) must be rejected as bad input:
# exit code 2 from both `mpgm check` and `mpgm run`, a message on stderr that
# names the scene file and the JSON path (or "line N" for syntax errors), and
# no crash or sanitizer report.
#
# usage: bash tests/scripts/bad_scenes.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -u

if [ $# -ne 3 ]; then
  echo "usage: $0 MPGM_EXE SOURCE_DIR WORK_DIR" >&2
  exit 2
fi
exe=$1
src=$2
work=$3
dir="$src/tests/bad_scenes"
list="$dir/expected.txt"
base="$src/cases/cantilever.json"
mkdir -p "$work" || exit 1

npass=0
nfail=0
pass() { echo "PASS: $1"; npass=$((npass + 1)); }
fail() { echo "FAIL: $1"; nfail=$((nfail + 1)); }

# One-line excerpt of a file for FAIL messages.
excerpt() { tr '\n' ' ' <"$1" | cut -c1-400; }

# run_case LABEL SCENE_NAME JSON_PATH CMD...: the command must exit 2 with
# SCENE_NAME and JSON_PATH on stderr and no sanitizer report.
run_case() {
  local label=$1 name=$2 path=$3
  shift 3
  local err="$work/stderr.txt" rc why=""
  # (subshell: keeps bash's own "Segmentation fault" notices off the log)
  (timeout 60 "$@" >/dev/null 2>"$err") 2>/dev/null
  rc=$?
  if [ "$rc" -eq 124 ]; then why="timed out"
  elif [ "$rc" -ge 128 ]; then why="crashed"
  elif grep -q -e "ERROR: AddressSanitizer" -e "ERROR: LeakSanitizer" -e "runtime error:" "$err"; then
    why="sanitizer report"
  elif [ "$rc" -ne 2 ]; then why="expected exit 2"
  elif ! grep -qF -- "$name" "$err"; then why="message does not name $name"
  elif ! grep -qF -- "$path" "$err"; then why="message does not name $path"
  fi
  if [ -z "$why" ]; then
    pass "$label"
  else
    fail "$label: $why (exit $rc, stderr: $(excerpt "$err"))"
  fi
}

if [ ! -x "$exe" ]; then
  fail "mpgm executable $exe not found"
  echo "$npass passed, $nfail failed"
  exit 1
fi
if [ ! -f "$list" ]; then
  fail "$list not found"
  echo "$npass passed, $nfail failed"
  exit 1
fi

# The reference scene itself must be valid, or the --set cases prove nothing.
if (timeout 60 "$exe" check "$base" >/dev/null 2>"$work/stderr.txt") 2>/dev/null; then
  pass "check cantilever.json (reference scene is valid)"
else
  fail "check cantilever.json: reference scene rejected (stderr: $(excerpt "$work/stderr.txt"))"
fi

nfiles=0
while IFS= read -r line || [ -n "$line" ]; do
  case "$line" in '' | '#'*) continue ;; esac
  IFS=$'\t' read -r f1 f2 f3 <<<"$line"
  if [ "$f1" = "@set" ]; then
    if [ -z "${f2:-}" ] || [ -z "${f3:-}" ]; then
      fail "expected.txt: malformed line: $line"
      continue
    fi
    # ARGS are split on blanks: "--set a=1 --set b=2"
    read -r -a args <<<"$f2"
    run_case "check cantilever.json $f2 -> $f3" cantilever.json "$f3" \
      "$exe" check "$base" "${args[@]}"
    rm -rf "$work/x"
    run_case "run cantilever.json $f2 -> $f3" cantilever.json "$f3" \
      "$exe" run "$base" "${args[@]}" --out "$work/x"
  else
    if [ -z "${f2:-}" ] || [ -n "${f3:-}" ]; then
      fail "expected.txt: malformed line: $line"
      continue
    fi
    if [ ! -f "$dir/$f1" ]; then
      fail "$f1: listed in expected.txt but missing"
      continue
    fi
    nfiles=$((nfiles + 1))
    run_case "check $f1 -> $f2" "$f1" "$f2" "$exe" check "$dir/$f1"
    rm -rf "$work/x"
    run_case "run $f1 -> $f2" "$f1" "$f2" "$exe" run "$dir/$f1" --out "$work/x"
  fi
done <"$list"

# Every scene file has an expectation, and there are enough of them.
for f in "$dir"/*.json; do
  [ -e "$f" ] || continue
  b=$(basename "$f")
  if cut -f1 "$list" | grep -qxF -- "$b"; then
    pass "$b is listed in expected.txt"
  else
    fail "$b has no line in expected.txt"
  fi
done
if [ "$nfiles" -ge 20 ]; then
  pass "$nfiles bad scene files (at least 20)"
else
  fail "only $nfiles bad scene files (expected at least 20)"
fi

rm -rf "$work/x"
echo "$npass passed, $nfail failed"
[ "$nfail" -eq 0 ]
