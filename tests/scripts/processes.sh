#!/usr/bin/env bash
# processes.sh -- mpgm under an MPI launcher (issue 54). mpgm run and check
# start MPI and PETSc (mpgm_par.so) when the launcher's environment says
# the process is one of several (Open MPI's OMPI_COMM_WORLD_SIZE, PMI_SIZE
# of MPICH, Intel MPI and Slurm's PMI, MVAPICH's MV2_COMM_WORLD_SIZE); a
# scene whose method cannot yet run its analysis on many processes is
# refused at load, naming the method and the analysis, exit 2, from rank 0
# only, with nothing written. The other commands run on one process and
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
# 2, the explicit MPM column on 3, a 3-D scene (handed to mpgm-3d before
# MPI starts) on 2
"${mpx[@]}" -n 2 "$exe" run "$cl" "${quick[@]}" --out two > two.out 2> two.err; rc=$?
n=$(grep -c "method fem runs its implicit analyses on one process only so far, and this run was started on 2" two.err)
[ $rc -ne 0 ] && [ "$n" -eq 1 ] && [ ! -e two ] \
  && ok "mpiexec -n 2: the implicit UL-FEM run refused once (exit $rc), no results folder" \
  || ko "mpiexec -n 2: exit $rc, $n messages, $(ls -d two 2>/dev/null) $(head -c 300 two.err)"
"${mpx[@]}" -n 3 "$exe" check "$src/cases/column_collapse.json" --set time.analysis=explicit \
  > three.out 2> three.err; rc=$?
n=$(grep -c "method mpm runs its explicit analyses on one process only so far, and this run was started on 3" three.err)
[ $rc -ne 0 ] && [ "$n" -eq 1 ] && [ ! -s three.out ] \
  && ok "mpiexec -n 3: the explicit MPM column refused once at load (exit $rc)" \
  || ko "mpiexec -n 3: exit $rc, $n messages, $(head -c 300 three.err)"
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
# -n 1: no MPI, the same result as without a launcher
"${mpx[@]}" -n 1 "$exe" run "$cl" "${quick[@]}" --out n1 > n1.log 2>&1; rc=$?
"$exe" run "$cl" "${quick[@]}" --out n0 > n0.log 2>&1
[ $rc -eq 0 ] && [ "$(summary_metric n1 error)" = "$(summary_metric n0 error)" ] \
  && ok "mpiexec -n 1: the run completes with the one-process result ($(summary_metric n1 error))" \
  || ko "mpiexec -n 1: exit $rc, error $(summary_metric n1 error) against $(summary_metric n0 error)"
echo "processes: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
