#!/usr/bin/env bash
# restart.sh -- checkpoint and restart (issue 16, item 8).
#
# Each case is run twice with output.checkpoint_every set: A to its end,
# B killed with SIGKILL at a random moment after its first checkpoint and
# continued with `mpgm run --restart B`. B must then hold, to the bit, what
# A holds: probes.csv, steps.csv (its wall-clock column aside), every VTK
# file and collection (.pvd, .vtk.series, .xdmf: gmm_lme_disk writes every
# format, fem_static .vtu and XDMF deflated, mpm_explicit legacy frames
# only), the contents of results.h5 (XDMF), the metrics, the counts (clock reads and the
# solver's memory peak aside: they measure the process, not the run), the
# step cuts and the status. The cases are coarse and dynamic:
#   fem_mc        UL-FEM, Mohr-Coulomb column collapse (FEM has no contact)
#   fem_krylov    the same with Newton-Krylov and Eisenstat-Walker forcing
#                 (the factorisation kept across steps: the pattern stays)
#   mpm_mc        MPM, Mohr-Coulomb block dropped on a floor, contact at
#                 its surface points
#   gmm_mls_mc    the same block, GMM-MLS
#   gmm_lme_mc    the same block, GMM-LME (the LME multipliers are warm
#                 starts kept across steps)
#   gmm_lme_nodes GMM-LME gamma 0.8 column collapse, its nodes moved by the
#                 interpolated field (mesh.node_motion)
#   gmm_lme_disk  GMM-LME rolling disk: bodies filled on the grid, light
#                 nodes parked, contact at surface points
#   gmm_lme_cc    GMM-LME column collapse: Mohr-Coulomb, obstacle nodes
#   gmm_skin_disk the rolling disk with a pattern skin (shape.skin): the
#                 lists the pattern is kept from are in the checkpoint
#   mpm_cuts      the block with MPM and two step cuts made on purpose at
#                 step 3 (MPGM_TEST_FAULT): the checkpoint at step 4 holds
#                 a quartered step that grows back after it
#   fem_static    the cantilever, static (load steps)
#   mpm_explicit  Dyka's bar, explicit npc (energy columns included)
#   mpm_kinetic   the same with kinetic damping (time.kinetic_damping: the
#                 kinetic energy of the last step is in the checkpoint);
#                 and, not left to the kill's timing, a run whose last
#                 checkpoint is the step before a reset, restarted from it
#   mpm_cpdi      MPM column collapse with CPDI (the points' initial domains
#                 are kept and reordered with them)
#   mpm_threads   the MPM block, B started on two threads and continued on
#                 one (threads may change at a restart), A on one
# Then the refusals, each with exit 2 and a message that says why: a
# checkpoint restarted with another scene or another --set, a checkpoint
# whose version bytes were altered, a truncated checkpoint, a folder
# without a checkpoint.
#
# The kill time is random (RESTART_SEED fixes it; the seed is printed).
#
# usage: restart.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
seed="${RESTART_SEED:-$RANDOM}"
echo "RESTART_SEED=$seed"
RANDOM=$seed
npass=0; nfail=0
# Debian's python (h5py reads results.h5), whatever python3 is first on PATH
py=/usr/bin/python3; [ -x "$py" ] || py=python3
restart_sets=()  # --set values given to A and to the restart of B, not to B's start
pass() { echo "PASS: $1"; npass=$((npass + 1)); }
fail() { echo "FAIL: $1"; nfail=$((nfail + 1)); }

mc='materials={"soft":{"type":"mohr_coulomb","density":1000,"E":1e6,"nu":0.3,"c":1500,"phi":25,"psi":0}}'
block="$src/tests/scenes/block_on_floor.json"
block_sets=(--set "$mc" --set time.end=0.2 --set output.every=10)

# one_case NAME SCENE ARGS...: A, B killed, B restarted, compared
one_case() {
  local name="$1" scene="$2"; shift 2
  local d="$work/$name" t0 t1 ms pid killed=0
  mkdir -p "$d"
  t0=$(date +%s%N)
  "$exe" run "$scene" --quiet --set output.vtk=ascii "$@" "${restart_sets[@]}" --out "$d/A" \
    > "$d/A.log" 2>&1
  local rca=$?
  t1=$(date +%s%N)
  "$exe" run "$scene" --quiet --set output.vtk=ascii "$@" --out "$d/B" > "$d/B.log" 2>&1 &
  pid=$!
  # after the first checkpoint, at a random moment of the rest of the run
  while kill -0 "$pid" 2> /dev/null && [ ! -e "$d/B/checkpoint.mpgm" ]; do sleep 0.005; done
  ms=$(( (t1 - t0) / 1000000 * (RANDOM % 70) / 100 ))
  sleep "$(printf '%d.%03d' $((ms / 1000)) $((ms % 1000)))"
  if kill -9 "$pid" 2> /dev/null; then killed=1; fi
  wait "$pid" 2> /dev/null
  "$exe" run --restart "$d/B" --quiet "${restart_sets[@]}" > "$d/R.log" 2>&1
  local rcr=$?
  local how="killed after ${ms} ms past its first checkpoint"
  [ $killed -eq 1 ] || how="ended before the kill (${ms} ms); restarted from its last checkpoint"
  if [ $rcr -ne $rca ]; then
    fail "$name: uninterrupted exit $rca, restarted exit $rcr ($how): $(head -c 300 "$d/R.log")"
    return
  fi
  if "$py" "$src/tests/tools/same_run.py" "$d/A" "$d/B"; then
    pass "$name: B $how, restarted: the same to the bit (exit $rca)"
  else
    fail "$name: B $how, restarted: differs from the uninterrupted run (above)"
  fi
}

one_case fem_mc "$src/cases/column_collapse.json" --set method=fem --set mesh.h=0.2 \
  --set time.end=0.3 --set output.checkpoint_every=7 --set output.every=10 \
  --set 'boundaries=[{"x":0,"condition":"slip"},{"y":0,"condition":"stick"}]'
one_case fem_krylov "$src/cases/column_collapse.json" --set method=fem --set mesh.h=0.2 \
  --set time.end=0.3 --set output.checkpoint_every=7 --set output.every=10 \
  --set 'boundaries=[{"x":0,"condition":"slip"},{"y":0,"condition":"stick"}]' \
  --set solver.linear=auto --set solver.newton=krylov --set solver.forcing=eisenstat_walker
one_case mpm_mc "$block" "${block_sets[@]}" --set output.checkpoint_every=6 --set output.grid=true \
  --set 'output.format=["vtu","vtk"]'
one_case gmm_mls_mc "$block" "${block_sets[@]}" --set method=gmm --set shape.kind=mls \
  --set output.checkpoint_every=6
one_case gmm_lme_mc "$block" "${block_sets[@]}" --set method=gmm --set shape.kind=lme \
  --set output.checkpoint_every=6
one_case gmm_lme_nodes "$src/cases/column_collapse_gmm.json" --set shape.kind=lme \
  --set shape.gamma=0.8 --set mesh.node_motion=interpolated --set mesh.h=0.2 --set time.dt=0.005 --set time.end=0.3 \
  --set output.checkpoint_every=5 --set output.times=[0.1]
one_case gmm_lme_disk "$src/cases/rolling_disk.json" --set method=gmm --set shape.kind=lme \
  --set mesh.h=0.05 --set time.dt=0.004 --set time.end=0.2 --set output.every=5 \
  --set output.checkpoint_every=4 --set 'output.format=["vtu","vtk","xdmf"]'
one_case gmm_lme_cc "$src/cases/column_collapse_gmm.json" --set shape.kind=lme --set mesh.h=0.2 \
  --set time.dt=0.005 --set time.end=0.3 --set output.checkpoint_every=5 --set output.times=[0.1]
one_case gmm_skin_disk "$src/cases/rolling_disk.json" --set method=gmm --set shape.kind=lme \
  --set mesh.h=0.05 --set time.dt=0.004 --set time.end=0.2 --set output.every=5 \
  --set output.checkpoint_every=4 --set shape.skin=0.25
MPGM_TEST_FAULT=nan:3:2 one_case mpm_cuts "$block" --set time.max_cuts=4 --set time.grow_after=3 \
  --set time.end=0.04 --set output.checkpoint_every=4 --set output.every=5
if grep -q '"step":\s*3' "$work/mpm_cuts/B/summary.json" 2> /dev/null; then
  pass "mpm_cuts: the cuts made before the checkpoint are listed after the restart"
else
  fail "mpm_cuts: summary.json of the restarted run lists no cut at step 3"
fi
one_case fem_static "$src/cases/cantilever.json" --set time.load_steps=6 \
  --set output.checkpoint_every=2 --set 'output.format=["vtu","xdmf"]' --set output.compress=zlib
one_case mpm_explicit "$src/cases/dyka_bar.json" --set output.checkpoint_every=150 \
  --set output.every=200 --set output.format=vtk
one_case mpm_kinetic "$src/cases/dyka_bar.json" --set output.checkpoint_every=20 \
  --set output.every=200 --set time.kinetic_damping=true
# the step before a reset: a reset is decided against the kinetic energy
# of the step before, so a restart from a checkpoint written there must
# know it (without it, the restart misses the reset and differs)
d="$work/mpm_kinetic_peak"; mkdir -p "$d"
"$exe" run "$src/cases/dyka_bar.json" --quiet --set time.kinetic_damping=true \
  --set output.vtk=none --set output.every=1 --out "$d/steps" > "$d/steps.log" 2>&1
read -r r t < <(python3 -c '
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
resets = [int(x["step"]) for x in rows if float(x["kinetic_energy"]) == 0.0 and int(x["step"]) > 50]
r = resets[0] if resets else 0
print(r, rows[min(r + 40, len(rows) - 1)]["time"] if r else 0)' "$d/steps/steps.csv")
if [ "${r:-0}" -gt 0 ]; then
  "$exe" run "$src/cases/dyka_bar.json" --quiet --set time.kinetic_damping=true \
    --set output.vtk=ascii --set time.end="$t" --set output.checkpoint_every=$((r - 1)) \
    --out "$d/A" > "$d/A.log" 2>&1
  cp -r "$d/A" "$d/B"
  if "$exe" run --restart "$d/B" --quiet > "$d/R.log" 2>&1 && python3 "$src/tests/tools/same_run.py" "$d/A" "$d/B"; then
    pass "mpm_kinetic_peak: restarted from step $((r - 1)), the step before a reset: the same to the bit"
  else
    fail "mpm_kinetic_peak: restarted from step $((r - 1)), the step before a reset: differs (above)"
  fi
else
  fail "mpm_kinetic_peak: no reset after step 50 in $d/steps/steps.csv"
fi
one_case mpm_cpdi "$src/cases/column_collapse.json" --set shape.kind=cpdi --set mesh.h=0.2 \
  --set time.end=0.3 --set output.checkpoint_every=5 --set output.times=[0.1]
# threads may change at a restart (the bits do not depend on them): A on
# one thread, B started on two and continued on one
restart_sets=(--set threads=1)
one_case mpm_threads "$block" "${block_sets[@]}" --set output.checkpoint_every=6 --set threads=2
restart_sets=()

# ---- refusals -------------------------------------------------------------
d="$work/mpm_mc/B"
# expect_refusal WHAT PATTERN ARGS...: exit 2, the message matches PATTERN
expect_refusal() {
  local what="$1" pat="$2"; shift 2
  "$exe" run "$@" --quiet > "$work/refusal.out" 2> "$work/refusal.err"
  local rc=$?
  if [ $rc -eq 2 ] && grep -Eq "$pat" "$work/refusal.err"; then
    pass "$what: exit 2: $(head -c 200 "$work/refusal.err")"
  else
    fail "$what: exit $rc (expected 2 and /$pat/): $(head -c 300 "$work/refusal.err")"
  fi
}
before=$(sha256sum "$d/probes.csv")
expect_refusal "restart with another scene" "written for another scene" --restart "$d" \
  "$src/cases/cantilever.json"
expect_refusal "restart with another --set" "written for another scene \(time.end differs\)" \
  --restart "$d" --set time.end=0.5
[ "$before" = "$(sha256sum "$d/probes.csv")" ] && pass "a refused restart leaves the results" \
  || fail "a refused restart changed probes.csv"
cp -r "$d" "$work/altered"
# another version in the header, its CRC made good: the version is refused,
# not the damage
python3 "$src/tests/tools/checkpoint_edit.py" "$work/altered/checkpoint.mpgm" put header 24 64s \
  "0.0.9 (000000000000)" --crc
expect_refusal "a checkpoint of another version" "written by mpgm .* this is mpgm" \
  --restart "$work/altered"
cp -r "$d" "$work/truncated"
python3 - "$work/truncated/checkpoint.mpgm" <<'EOF'
import os, sys
os.truncate(sys.argv[1], os.path.getsize(sys.argv[1]) // 2)
EOF
expect_refusal "a truncated checkpoint" "checkpoint.mpgm: .*(past the end|end of the data)" \
  --restart "$work/truncated"
mkdir -p "$work/empty"
expect_refusal "a folder without a checkpoint" "holds no checkpoint.mpgm" --restart "$work/empty"
expect_refusal "--restart with --out elsewhere" "continues in its own folder" --restart "$d" \
  --out "$work/elsewhere"

echo "restart: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
