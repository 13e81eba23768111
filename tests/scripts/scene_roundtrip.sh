#!/usr/bin/env bash
# scene_roundtrip.sh -- the resolved scene (what `mpgm check` prints and
# every run writes into summary.json) is itself a valid scene that resolves
# to the same tree: a run can be repeated from its summary, and a resumed
# study compares an old run's scene by reading it again (docs/studies.md).
# Every case in cases/, and a few --set variants (GMM with MLS and LME, FEM,
# a geostatic body), go round once.
# usage: scene_roundtrip.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$(realpath "$1")"; src="$(realpath "$2")"; work="$3"
rm -rf "$work"; mkdir -p "$work"; work="$(realpath "$work")"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"

# the first JSON object of `mpgm check`'s output (the resolved scene)
first_json() {
  python3 -c '
import json, sys
t = sys.stdin.read()
obj, _ = json.JSONDecoder().raw_decode(t[t.index("{"):])
json.dump(obj, sys.stdout, indent=1, sort_keys=True)'
}

roundtrip() { # NAME SCENE [--set ...]
  local name="$1"; shift
  if ! "$exe" check "$@" > "$name.check1" 2> "$name.err"; then
    ko "$name: mpgm check of the scene failed: $(cat "$name.err")"; return
  fi
  first_json < "$name.check1" > "$name.resolved.json"
  if ! "$exe" check "$name.resolved.json" > "$name.check2" 2> "$name.err2"; then
    ko "$name: the resolved scene does not load: $(cat "$name.err2")"; return
  fi
  first_json < "$name.check2" > "$name.resolved2.json"
  # the file name differs; nothing else may
  if diff <(grep -v '"description"' "$name.resolved.json") \
          <(grep -v '"description"' "$name.resolved2.json") > "$name.diff"; then
    ok "$name: the resolved scene loads and resolves to itself"
  else
    ko "$name: resolved twice differs: $(head -20 "$name.diff")"
  fi
}

for f in "$src"/cases/*.json; do
  roundtrip "$(basename "$f" .json)" "$f"
done
roundtrip cantilever_gmm_mls "$src/cases/cantilever.json" --set method=gmm --set shape.kind=mls
roundtrip cantilever_gmm_lme "$src/cases/cantilever.json" --set method=gmm --set shape.kind=lme --set shape.gamma=1.8
roundtrip cantilever_fem "$src/cases/cantilever.json" --set method=fem
roundtrip rolling_disk_mpm_lme "$src/cases/rolling_disk.json" --set shape.kind=lme
# the geostatic body's object must not come back as {} where it was absent
if grep -q '"geostatic"' cantilever.resolved.json; then
  ko "a body without geostatic stress has a \"geostatic\" object in its resolved scene"
else
  ok "a body without geostatic stress has no \"geostatic\" object in its resolved scene"
fi
grep -q '"geostatic"' column_collapse.resolved.json \
  && ok "the column's geostatic object is kept" || ko "the column's resolved scene lost its geostatic object"
echo "$npass passed, $nfail failed"
[ $nfail -eq 0 ]
