#!/usr/bin/env bash
# processes.sh -- mpgm under an MPI launcher (issue 54). mpgm run and check
# start MPI and PETSc (mpgm_par.so) when the launcher's environment says
# the process is one of several (Open MPI's OMPI_COMM_WORLD_SIZE, PMI_SIZE
# of MPICH, Intel MPI and Slurm's PMI, MVAPICH's MV2_COMM_WORLD_SIZE); a
# scene whose method cannot yet run its analysis on many processes is
# refused at load, naming the method and the analysis, exit 2, from rank 0
# only, with nothing written (and so is a scene asking for what a run on
# many does not do yet: another shape kind, other output formats). Explicit
# MPM runs on 2 and 3 processes, in 2-D and 3-D, with the one-process
# answers (tests/tools/same_ranks.py, 1e-10), one .pvtu per frame over the
# processes' pieces, and a failure on one process stops every one. The other commands run on one process and
# are refused under a launcher. A launcher of another MPI than mpgm's
# (its processes each see MPI of one) is refused too: the copies would
# write the same results. One process (no launcher, or -n 1) runs as
# always, without MPI.
# usage: processes.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$(realpath "$1")"; src="$(realpath "$2")"; work="$3"
rm -rf "$work"; mkdir -p "$work"; work="$(realpath "$work")"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"
cl="$src/cases/cantilever.json"
quick=(--set mesh.h=0.5 --set output.vtk=none --quiet)

# a launcher's environment without its MPI: each process is MPI's one
expect 2 "the launcher started 2 processes (OMPI_COMM_WORLD_SIZE=2), and MPI sees 1" \
  "Open MPI's variables without its launcher: run refused" env OMPI_COMM_WORLD_SIZE=2 \
  OMPI_COMM_WORLD_RANK=0 "$exe" run "$cl" "${quick[@]}" --out ompi
[ ! -e ompi ] && ok "nothing written (no results folder)" || ko "a results folder: $(ls ompi)"
env PMI_SIZE=3 PMI_RANK=1 "$exe" check "$cl" > pmi.out 2> pmi.err; rc=$?
# (quietly: no line of mpgm's; a sanitizer's report at exit may follow)
[ $rc -eq 2 ] && ! grep -q "^mpgm" pmi.err && [ ! -s pmi.out ] && ok "PMI rank 1 of 3: check refused quietly (exit 2)" \
  || ko "PMI rank 1 of 3: exit $rc, $(head -c 300 pmi.err)"
expect 2 "started as one of 4 processes (MV2_COMM_WORLD_SIZE=4): mpgm study runs on one process" \
  "MVAPICH's 4: study refused before MPI" env MV2_COMM_WORLD_SIZE=4 "$exe" study nosuch.json
env OMPI_COMM_WORLD_SIZE=1 OMPI_COMM_WORLD_RANK=0 "$exe" run "$cl" "${quick[@]}" --out one > one.log 2>&1; rc=$?
[ $rc -eq 0 ] && [ -s one/summary.json ] && ok "one process of one: the run completes" \
  || ko "one of one: exit $rc, $(head -c 300 one.log)"
env OMPI_COMM_WORLD_SIZE=2 "$exe" version > version.out 2>&1 && grep -q "^mpgm " version.out \
  && ok "version answers under a launcher" || ko "version: $(cat version.out)"

mpx=$(command -v mpiexec || true)
if [ -z "$mpx" ] || ! "$mpx" --version 2>&1 | grep -qE "Open MPI|OpenRTE"; then
  echo "note: no Open MPI mpiexec on PATH: the launcher's own runs are not tried"
  echo "processes: $npass passed, $nfail failed"
  [ $nfail -eq 0 ]; exit
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpx=("$mpx" --oversubscribe)
# refused at load, once, nothing written: the implicit UL-FEM cantilever on
# 2, explicit MPM with LME on 3 and with a reference that observes every
# point (Dyka's bar) on 2, a 3-D scene (handed to mpgm-3d before MPI
# starts) on 2
"${mpx[@]}" -n 2 "$exe" run "$cl" "${quick[@]}" --out two > two.out 2> two.err; rc=$?
n=$(grep -c "method fem runs its implicit analyses on one process only so far, and this run was started on 2" two.err)
[ $rc -ne 0 ] && [ "$n" -eq 1 ] && [ ! -e two ] \
  && ok "mpiexec -n 2: the implicit UL-FEM run refused once (exit $rc), no results folder" \
  || ko "mpiexec -n 2: exit $rc, $n messages, $(ls -d two 2>/dev/null) $(head -c 300 two.err)"
discs="$src/cases/colliding_discs.json"
"${mpx[@]}" -n 3 "$exe" check "$discs" --set shape.kind=lme > three.out 2> three.err; rc=$?
n=$(grep -c 'shape.kind: method mpm runs shape.kind "lme" on one process only so far, and this run was started on 3' three.err)
[ $rc -eq 2 ] && [ "$n" -eq 1 ] && [ ! -s three.out ] \
  && ok "mpiexec -n 3: explicit MPM with LME refused once at load (exit $rc)" \
  || ko "mpiexec -n 3, LME: exit $rc, $n messages, $(head -c 300 three.err)"
"${mpx[@]}" -n 2 "$exe" run "$src/cases/dyka_bar.json" --out bar > bar.out 2> bar.err; rc=$?
n=$(grep -c 'reference: reference "dyka_bar" observes every material point, which a run on many processes does not do so far' bar.err)
[ $rc -eq 2 ] && [ "$n" -eq 1 ] && [ ! -e bar ] \
  && ok "mpiexec -n 2: Dyka's bar (its reference observes every point) refused once, nothing written" \
  || ko "mpiexec -n 2, Dyka's bar: exit $rc, $n messages, $(head -c 300 bar.err)"
"${mpx[@]}" -n 2 "$exe" check "$src/cases/column_wave_3d.json" > td.out 2> td.err; rc=$?
n=$(grep -c "column_wave_3d.json: method: method mpm runs its implicit analyses on one process only" td.err)
[ $rc -ne 0 ] && [ "$n" -eq 1 ] && ok "mpiexec -n 2 with a 3-D scene: mpgm-3d refuses it (exit $rc)" \
  || ko "mpiexec -n 2, 3-D: exit $rc, $n messages, $(head -c 300 td.err)"
# the collectives of the context's communicator, the sums at shared nodes of a
# partitioned grid (DMDA) and the points' migration (DMSwarm), in 2-D and
# 3-D, on 2, 3 and 4 processes (slabs, and boxes with corners on 4),
# and explicit MPM (the three schemes; 2-D, and 3-D by test_parallel_3d)
# against one process: every point by its id after 100 steps
for t in test_parallel test_parallel_3d; do
  tp="$(dirname "$exe")/tests/$t"
  for n in 2 3 4; do
    "${mpx[@]}" -n $n "$tp" > $t$n.log 2>&1; rc=$?
    [ $rc -eq 0 ] && [ "$(grep -c "0 failed" $t$n.log)" -eq $n ] \
      && ok "$t on $n processes: every rank's checks pass" \
      || ko "$t on $n: exit $rc, $(grep -m3 FAIL $t$n.log) $(tail -c 300 $t$n.log)"
  done
done
# explicit MPM on 1, 2 and 3 processes, the same answers (same_ranks.py:
# probes, energies, momenta, metrics to 1e-10 of their scale): the two
# colliding discs (fe, npc; to t = 1.5 s, 350 steps: they meet on the grid
# and points cross between processes), with uGIMP and usl on 3 (100
# steps), and the 3-D
# Mohr-Coulomb column (H8, 40 steps) on 2
same_runs() { # NAME NPROCS SCENE ARGS...
  local name="$1" np="$2" scene="$3"; shift 3
  "$exe" run "$scene" "$@" --quiet --out ${name}1 > ${name}1.log 2>&1 || { ko "$name: one process: $(tail -c 300 ${name}1.log)"; return; }
  for n in $np; do
    "${mpx[@]}" -n $n "$exe" run "$scene" "$@" --quiet --out $name$n > $name$n.log 2>&1; rc=$?
    if [ $rc -eq 0 ] && python3 "$src/tests/tools/same_ranks.py" ${name}1 $name$n > $name$n.cmp 2>&1; then
      ok "$name on $n processes: the one-process answers ($(grep -o 'worst difference [^ ]*' $name$n.cmp | sort -k3 -g | tail -1))"
    else
      ko "$name on $n: exit $rc, $(grep DIFFERS $name$n.cmp | head -3) $(tail -c 300 $name$n.log)"
    fi
  done
}
same_runs discs "2 3" "$discs" --set time.end=1.5 --set output.every=50
same_runs ugimp "3" "$discs" --set time.end=0.43 --set output.every=25 --set shape.kind=ugimp \
  --set time.scheme=usl
same_runs col3d "2" "$src/cases/column_collapse_3d.json" --set time.analysis=explicit --set time.dt=0.0005 \
  --set time.end=0.02 --set output.times=[] --set output.every=20
# the pieces: one .vtu per process and frame, and a .pvtu of them listed in points.pvd
n=$(ls discs3/vtk/*.pvtu 2>/dev/null | wc -l); m=$(ls discs3/vtk/points_000000_*.vtu 2>/dev/null | wc -l)
[ "$n" -eq "$(ls discs1/vtk/*.vtu | wc -l)" ] && [ "$m" -eq 3 ] && grep -q 'file="vtk/points_000000.pvtu"' discs3/points.pvd \
  && ok "3 processes: $n frames, each a .pvtu of 3 pieces, listed in points.pvd" \
  || ko "3 processes: $n .pvtu, $m pieces of frame 0, $(head -c 300 discs3/points.pvd)"
last=$(ls discs1/vtk/points_*.vtu | tail -1); last=${last##*/}
python3 - discs1/vtk/$last discs3/vtk/${last%.vtu} 3 <<'PY' > pieces.log 2>&1 \
  && ok "3 processes: the pieces of the last frame hold the one-process points ($(cat pieces.log))" \
  || ko "pieces: $(cat pieces.log)"
import re, sys
def count(path):
    return int(re.search(r'NumberOfPoints="(\d+)"', open(path, errors="replace").read(4096)).group(1))
one, stem, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
parts = [count(f"{stem}_{r}.vtu") for r in range(n)]
first = [count(f"{stem[:-6]}000000_{r}.vtu") for r in range(n)]
print(f"{sum(parts)} points: {' + '.join(map(str, parts))}, at the start {' + '.join(map(str, first))}")
sys.exit(0 if sum(parts) == count(one) and min(parts) > 0 else 1)
PY
# steps.csv on many processes ends with the points' imbalance after each
# step (most on a process / mean), the last row's equal to summary.json's;
# the discs meeting crowd one process's slab: a step that leaves the
# imbalance above 1.2 is followed by a cut of the slabs (the next row back
# under 1.2)
python3 - discs3 discs1 <<'PY' > imbalance.log 2>&1 && ok "3 processes: steps.csv's imbalance column ($(cat imbalance.log))" || ko "imbalance: $(cat imbalance.log)"
import csv, json, sys
many, one = sys.argv[1], sys.argv[2]
rows = list(csv.DictReader(open(f"{many}/steps.csv")))
last = json.load(open(f"{many}/summary.json"))["counts"]["processes"]["imbalance"]
imb = [float(r["imbalance"]) for r in rows]
plain = "imbalance" not in open(f"{one}/steps.csv").readline()
high = [i for i in range(len(imb) - 1) if imb[i] > 1.2]
held = all(imb[i + 1] <= 1.2 for i in high)
print(f"from {imb[0]:.4f} to {imb[-1]:.4f} over {len(imb)} steps, at most {max(imb):.4f}; {len(high)} "
      f"step(s) above 1.2, each followed by a cut: {held}; none on one process: {plain}")
sys.exit(0 if plain and held and high and min(imb) >= 1.0 and abs(imb[-1] - last) <= 1e-12 * last else 1)
PY
# a step that fails on one process (a point's Jacobian inverted on purpose
# on rank 2 of 3) fails on every one: no process waits for it, and the
# first's summary.json names the process and its reason
flt=(run "$discs" --set time.end=0.1 --quiet --out fault)
timeout 120 "${mpx[@]}" -n 2 "$exe" "${flt[@]}" : -n 1 env MPGM_TEST_FAULT=jacobian:5:100 "$exe" "${flt[@]}" \
  > fault.log 2>&1; rc=$?
[ $rc -ne 0 ] && [ $rc -ne 124 ] && grep -q '"failed_step":	5' fault/summary.json \
  && grep -q 'step 5 (t = [0-9.e-]*) failed: process 2 of 3: point [0-9]* at .*det(dF) = -1' fault/summary.json \
  && ok "a failure on process 2 of 3: every process stops at step 5 (exit $rc), summary.json names it" \
  || ko "a failure on process 2: exit $rc, $(grep -m2 '"message"\|failed_step' fault/summary.json 2>/dev/null) $(tail -c 300 fault.log)"
# -n 1: no MPI, the same result as without a launcher
"${mpx[@]}" -n 1 "$exe" run "$cl" "${quick[@]}" --out n1 > n1.log 2>&1; rc=$?
"$exe" run "$cl" "${quick[@]}" --out n0 > n0.log 2>&1
[ $rc -eq 0 ] && [ "$(summary_metric n1 error)" = "$(summary_metric n0 error)" ] \
  && ok "mpiexec -n 1: the run completes with the one-process result ($(summary_metric n1 error))" \
  || ko "mpiexec -n 1: exit $rc, error $(summary_metric n1 error) against $(summary_metric n0 error)"
echo "processes: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
