#!/usr/bin/env bash
# one_process.sh -- mpgm runs on one process (issue 54 brings runs on many):
# started as one of several by an MPI launcher (mpiexec -n 2; the
# launcher's environment: Open MPI's OMPI_COMM_WORLD_SIZE, PMI_SIZE of
# MPICH, Intel MPI and Slurm's PMI, MVAPICH's MV2_COMM_WORLD_SIZE) every
# command but help and version is refused, exit 2, with the reason from
# rank 0 only, before anything is read or written: no results folder. One
# process (no launcher, or -n 1) runs as always. With Open MPI's mpiexec on
# PATH, also under mpiexec -n 2 itself.
# usage: one_process.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$(realpath "$1")"; src="$(realpath "$2")"; work="$3"
rm -rf "$work"; mkdir -p "$work"; work="$(realpath "$work")"
cd "$work" || exit 1
source "$src/tests/tools/checks.bash"
cl="$src/cases/cantilever.json"
quick=(--set mesh.h=0.5 --set output.vtk=none --quiet)

expect 2 "started as one of 2 processes (OMPI_COMM_WORLD_SIZE=2): mpgm runs on one process" \
  "Open MPI's rank 0 of 2: run refused" env OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 \
  "$exe" run "$cl" "${quick[@]}" --out ompi
[ ! -e ompi ] && ok "nothing written (no results folder)" || ko "a results folder: $(ls ompi)"
env PMI_SIZE=3 PMI_RANK=1 "$exe" check "$cl" > pmi.out 2> pmi.err; rc=$?
[ $rc -eq 2 ] && [ ! -s pmi.err ] && [ ! -s pmi.out ] && ok "PMI rank 1 of 3: check refused quietly (exit 2)" \
  || ko "PMI rank 1 of 3: exit $rc, $(head -c 300 pmi.err)"
expect 2 "started as one of 4 processes (MV2_COMM_WORLD_SIZE=4)" "MVAPICH's 4: study refused" \
  env MV2_COMM_WORLD_SIZE=4 "$exe" study nosuch.json
env OMPI_COMM_WORLD_SIZE=1 OMPI_COMM_WORLD_RANK=0 "$exe" run "$cl" "${quick[@]}" --out one > one.log 2>&1; rc=$?
[ $rc -eq 0 ] && [ -s one/summary.json ] && ok "one process of one: the run completes" \
  || ko "one of one: exit $rc, $(head -c 300 one.log)"
env OMPI_COMM_WORLD_SIZE=2 "$exe" version > version.out 2>&1 && grep -q "^mpgm " version.out \
  && ok "version answers under a launcher" || ko "version: $(cat version.out)"

mpx=$(command -v mpiexec || true)
if [ -n "$mpx" ] && "$mpx" --version 2>&1 | grep -qE "Open MPI|OpenRTE"; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  "$mpx" --oversubscribe -n 2 "$exe" run "$cl" "${quick[@]}" --out two > two.out 2> two.err; rc=$?
  n=$(grep -c "mpgm runs on one process" two.err)
  [ $rc -ne 0 ] && [ "$n" -eq 1 ] && [ ! -e two ] \
    && ok "mpiexec -n 2: refused once (exit $rc), no results folder" \
    || ko "mpiexec -n 2: exit $rc, $n messages, $(ls -d two 2>/dev/null) $(head -c 300 two.err)"
else
  echo "note: no Open MPI mpiexec on PATH: the launcher's own run is not tried"
fi
echo "one_process: $npass passed, $nfail failed"
[ $nfail -eq 0 ]
