#!/usr/bin/env bash
# strict_input.sh -- input that bad_scenes.sh cannot hold in a file: a scene
# that is a device, a folder or a pipe (refused with exit 2, the path
# named, memory bounded), a --set value that is not UTF-8, and a scene
# with non-ASCII (valid UTF-8) text whose summary.json must stay JSON.
#
# usage: strict_input.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
scene="$src/cases/cantilever.json"
npass=0; nfail=0
pass() { echo "PASS: $1"; npass=$((npass + 1)); }
fail() { echo "FAIL: $1"; nfail=$((nfail + 1)); }

# an ASan build? (grep -c reads all of nm's output: with pipefail, grep -q
# would end the pipe early and fail it)
asan=0
if nm -an "$exe" 2>/dev/null | grep -c __asan_init > /dev/null; then asan=1; fi

# expect CODE NEEDLE WHAT CMD...: exit CODE, NEEDLE on stderr, within 60 s,
# with at most 1 GiB of address space beyond what ASan reserves.
expect() {
  local code="$1" needle="$2" what="$3"; shift 3
  (
    # ASan reserves terabytes of virtual memory: limit only a plain build
    if [ "$asan" -eq 0 ]; then ulimit -v 1048576; fi
    timeout 60 "$@" > "$work/out" 2> "$work/err"
  ) 2>/dev/null
  local rc=$?
  if [ $rc -eq "$code" ] && { [ -z "$needle" ] || grep -qF -- "$needle" "$work/err"; }; then
    pass "$what (exit $rc)"
  else
    fail "$what: exit $rc (expected $code with '$needle'), stderr: $(head -c 300 "$work/err")"
  fi
}

for cmd in check run; do
  expect 2 "/dev/zero: is a character device, not a regular file" \
    "mpgm $cmd /dev/zero is refused, memory bounded" "$exe" $cmd /dev/zero --out "$work/x"
  expect 2 "$src/cases: is a folder, not a regular file" \
    "mpgm $cmd on a folder is refused" "$exe" $cmd "$src/cases" --out "$work/x"
done
# a pipe, endless or not, is no regular file: refused before any read
# (a read could wait for its writer for ever; special_files.sh has more)
expect 2 ": is a pipe or FIFO, not a regular file" "an endless pipe is refused unread" \
  bash -c "exec \"\$0\" check <(yes ' ')" "$exe"
expect 2 ": is a pipe or FIFO, not a regular file" "a scene through a pipe is refused" \
  bash -c "exec \"\$0\" check <(cat \"\$1\")" "$exe" "$scene"

# a --set value that is not UTF-8 (Latin-1 e-acute) never reaches the outputs
bad=$(printf 'caf\xe9')
expect 2 "description: --set value is not UTF-8" "a --set value that is not UTF-8 is refused" \
  "$exe" run "$scene" --set "description=$bad" --set mesh.h=0.5 --out "$work/latin1"
if [ ! -e "$work/latin1/summary.json" ]; then pass "nothing written for the refused --set"
else fail "a summary.json was written for the refused --set"; fi

# valid UTF-8 text goes through unchanged and summary.json stays JSON
printf -v good 'beam \xc3\xa9\xe2\x80\x93\xf0\x9f\x98\x80'
python3 - "$scene" "$work/utf8.json" "$good" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
d["description"] = sys.argv[3]
d["mesh"]["h"] = 0.5
json.dump(d, open(sys.argv[2], "w", encoding="utf-8"), ensure_ascii=False)
EOF
expect 0 "" "a scene with UTF-8 text runs" "$exe" run "$work/utf8.json" --quiet --out "$work/utf8"
if python3 - "$work/utf8/summary.json" "$good" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1], encoding="utf-8"))
sys.exit(0 if s["status"] == "completed" and s["scene"]["description"] == sys.argv[2] else 1)
EOF
then pass "summary.json is JSON and keeps the UTF-8 description"
else fail "summary.json of the UTF-8 scene: not JSON, or the description changed"; fi

rm -rf "$work/x"
echo "$npass passed, $nfail failed"
[ "$nfail" -eq 0 ]
