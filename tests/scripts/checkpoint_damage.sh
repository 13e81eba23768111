#!/usr/bin/env bash
# checkpoint_damage.sh -- damaged checkpoints are refused before anything
# is touched (issue 51; docs/scene-format.md, "Checkpoints are verified").
#
# Three short runs that complete and leave a checkpoint behind: the static
# cantilever (UL-FEM, load steps), Dyka's bar (explicit MPM) and the rolling
# disk (GMM-LME with a pattern skin). Copies of their results folders get a
# damaged checkpoint.mpgm, one kind of damage each: a bit flipped in a
# double array, in the scene, in the header (the CRC of the section finds
# it); an index or a count out of range with the section's CRC made good
# (tests/tools/checkpoint_edit.py; the checks of what the section holds
# must find it); truncation inside a section, bytes appended, an empty
# file, a FIFO or a folder in its place, a checkpoint of format 1. Each
# restart must exit 2 with a message naming the file and the section or
# what is wrong, and leave every file of the folder as it was (sha256 of
# each, and the listing with types and sizes, before and after). The
# undamaged copy still restarts and ends as the run that was not restarted
# did, to the bit (tests/tools/same_run.py).
#
# usage: checkpoint_damage.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$(cd "$2" && pwd)"; work="$3"
rm -rf "$work"; mkdir -p "$work"
edit="$src/tests/tools/checkpoint_edit.py"
npass=0; nfail=0
pass() { echo "PASS: $1"; npass=$((npass + 1)); }
fail() { echo "FAIL: $1"; nfail=$((nfail + 1)); }

# The folder's state: every entry with its type and size, and the sha256 of
# every regular file (not read from a FIFO: that would block).
snapshot() {
  (cd "$1" && find . -printf '%p %y %s\n' | LC_ALL=C sort &&
     find . -type f -print0 | LC_ALL=C sort -z | xargs -0 -r sha256sum)
}

# The three runs: each completes, its last checkpoint a few steps before
# its end.
run() { # NAME SCENE ARGS...
  local name="$1" scene="$2"; shift 2
  if "$exe" run "$scene" --quiet "$@" --out "$work/$name" > "$work/$name.log" 2>&1 &&
     [ -f "$work/$name/checkpoint.mpgm" ] && [ -f "$work/$name/summary.json" ]; then
    pass "$name: a completed run with a checkpoint"
  else
    fail "$name: no completed run with a checkpoint: $(head -c 300 "$work/$name.log")"
  fi
}
run fem "$src/cases/cantilever.json" --set time.load_steps=6 --set output.checkpoint_every=2
run mpm_explicit "$src/cases/dyka_bar.json" --set output.checkpoint_every=150 --set output.every=100 \
  --set output.vtk=ascii
run gmm_skin "$src/cases/rolling_disk.json" --set method=gmm --set shape.kind=lme --set mesh.h=0.05 \
  --set time.dt=0.004 --set time.end=0.024 --set output.every=2 --set output.checkpoint_every=2 \
  --set shape.skin=0.25

# damaged WHAT RUN PATTERN DAMAGE...: a copy of RUN's folder, DAMAGE done to
# its checkpoint.mpgm (a command run in the copy's folder), then a restart:
# exit 2, the message names the file and matches PATTERN, the folder as it
# was.
k=0
damaged() {
  local what="$1" run="$2" pat="$3"; shift 3
  k=$((k + 1))
  local d="$work/case_$k"
  rm -rf "$d"; cp -a "$work/$run" "$d"
  if ! (cd "$d" && "$@") > "$d.edit" 2>&1; then
    fail "$what: the damage could not be made: $(head -c 300 "$d.edit")"
    return
  fi
  local before after rc
  before=$(snapshot "$d")
  # under timeout: a FIFO must not block the restart
  timeout 20 "$exe" run --restart "$d" --quiet > "$d.out" 2> "$d.err"
  rc=$?
  after=$(snapshot "$d")
  local msg; msg=$(head -c 400 "$d.err")
  if [ $rc -ne 2 ]; then
    fail "$what: exit $rc (expected 2): $msg"
  elif ! grep -q "checkpoint.mpgm" "$d.err" || ! grep -Eq -- "$pat" "$d.err"; then
    fail "$what: exit 2, but the message does not name the file and /$pat/: $msg"
  elif [ "$before" != "$after" ]; then
    fail "$what: exit 2, but the folder changed: $(diff <(echo "$before") <(echo "$after") | head -5)"
  else
    pass "$what: exit 2, the folder untouched: $msg"
  fi
}

ck=checkpoint.mpgm
damaged "a bit flipped in the velocities (pts.v)" fem "section 'pts.v' is damaged \(CRC 0x[0-9a-f]{8} recorded, 0x[0-9a-f]{8} found\)" \
  python3 "$edit" $ck flip pts.v 1001 3
damaged "a bit flipped in the scene" fem "section 'scene.json' is damaged \(CRC" \
  python3 "$edit" $ck flip scene.json 40 0
damaged "a bit flipped in the header's version" fem "section 'header' is damaged \(CRC" \
  python3 "$edit" $ck flip header 26 1
damaged "a material index out of range, CRC made good" fem "section 'pts.mat': point 3 has material 7; the scene has 1" \
  python3 "$edit" $ck put pts.mat '#3' i 7 --crc
damaged "a negative material index, CRC made good" fem "section 'pts.mat': point 0 has material -2" \
  python3 "$edit" $ck put pts.mat '#0' i -2 --crc
damaged "a node's equation number out of range, CRC made good" fem "section 'nodes.dof': node 4 component 1 has equation 99999999" \
  python3 "$edit" $ck put nodes.dof '#9' i 99999999 --crc
damaged "a negative count of history rows, CRC made good" fem "section 'out.counts': -1 rows of probes" \
  python3 "$edit" $ck put out.counts '#2' i -1 --crc
damaged "a time that is not a number, CRC made good" fem "section 'core': load factor at the start nan" \
  python3 "$edit" $ck put core 0 d nan --crc
damaged "a point id twice, CRC made good" fem "section 'pts.id': point 1 has id 0, which another point has" \
  python3 "$edit" $ck put pts.id '#1' i 0 --crc
damaged "truncated inside a section" fem "section 'pts.v' \(at byte [0-9]+\) of [0-9]+ bytes runs past the end of the file" \
  python3 -c "import os, sys, subprocess
at = [l.split() for l in subprocess.check_output([sys.executable, '$edit', '$ck', 'list'], text=True).splitlines()]
off = next(int(r[1]) for r in at if r[2] == 'pts.v')
os.truncate('$ck', off + 36 + 100)"
damaged "bytes appended" fem "7 bytes after the last section 'run.cuts', too few for a section" \
  sh -c "printf 'garbage' >> $ck"
damaged "a whole section's worth of zeros appended" fem "section [0-9]+ \(at byte [0-9]+, after 'run.cuts'\) is damaged: its tag '' is not a name" \
  sh -c "head -c 64 /dev/zero >> $ck"
damaged "an empty file" fem "not an mpgm checkpoint \(an empty file\)" \
  sh -c ": > $ck"
damaged "a FIFO in place of the checkpoint" fem "checkpoint.mpgm: is a pipe or FIFO, not a regular file" \
  sh -c "rm $ck && mkfifo $ck"
damaged "a folder in place of the checkpoint" fem "checkpoint.mpgm: is a folder, not a regular file" \
  sh -c "rm $ck && mkdir $ck"
damaged "a checkpoint of format 1 (before the CRCs)" fem "written by mpgm .* \(checkpoint format 1\); this is mpgm .* \(format 2\)" \
  python3 "$edit" $ck format1
damaged "explicit MPM: a bit flipped in the velocities" mpm_explicit "section 'pts.v' is damaged \(CRC" \
  python3 "$edit" $ck flip pts.v 200 6
damaged "explicit MPM: a body index out of range, CRC made good" mpm_explicit "section 'pts.body': point 5 is of body 3; the scene has 2" \
  python3 "$edit" $ck put pts.body '#5' i 3 --crc
damaged "explicit MPM: a velocity that is infinite, CRC made good" mpm_explicit "section 'pts.v': point 2 holds inf, not a finite number" \
  python3 "$edit" $ck put pts.v '#5' d inf --crc
damaged "GMM: a skin list's node out of range, CRC made good" gmm_skin "section 'skin.node': point 0's list holds node 1000000" \
  python3 "$edit" $ck put skin.node '#0' i 1000000 --crc
damaged "GMM: a negative count of warm starts, CRC made good" gmm_skin "section 'clouds.m': warm starts of -5 points" \
  python3 "$edit" $ck put clouds.m 0 i -5 --crc
damaged "GMM: a grid node's fixity of 2, CRC made good" gmm_skin "section 'gmm.fix': node 3 component 0 holds 2" \
  python3 "$edit" $ck put gmm.fix 6 B 2 --crc

# the undamaged checkpoint: the restart completes the run again, to the bit
d="$work/pristine"; cp -a "$work/fem" "$d"
if "$exe" run --restart "$d" --quiet > "$d.log" 2>&1 && python3 "$src/tests/tools/same_run.py" "$work/fem" "$d"; then
  pass "the undamaged checkpoint restarts and ends as the run did, to the bit"
else
  fail "the undamaged checkpoint: $(head -c 300 "$d.log")"
fi

echo "checkpoint_damage: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
