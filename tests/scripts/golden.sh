#!/usr/bin/env bash
# Same answers to the bit: every run of tests/golden/runs.txt (cantilever
# with every front end, Q4 and T3; rolling disk and column collapse, coarse;
# geostatic column, contact blocks; a Matrix Market dump; the material
# driver) is compared exactly with its golden record tests/golden/NAME.json
# (tests/tools/golden.py: metrics, counts, probe and step histories, hashes
# of the last VTK files and of the matrices). A refactor keeps every record;
# a deliberate change of a number regenerates the records in a commit of its
# own that says why:
#   bash tests/scripts/golden.sh build/mpgm . /tmp/golden --update
# usage: golden.sh MPGM_EXE SOURCE_DIR WORK_DIR [--update]
set -uo pipefail
# The bits of a run depend on the processor through two libraries that pick
# their code by CPU at load time: OpenBLAS's kernels (the dense blocks of
# CHOLMOD's supernodal and UMFPACK's factors: SkylakeX, Haswell and Zen
# kernels sum in different orders) and glibc's libm (exp, log, pow, sin have
# FMA and AVX variants). Pinned here to code every x86-64 processor runs,
# so that the records test our code, not the machine the test lands on.
export OPENBLAS_CORETYPE=Prescott
export GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX,-AVX2,-FMA,-FMA4
exe="$1"; src="$2"; work="$3"; update="${4:-}"
rm -rf "$work"; mkdir -p "$work"
pass=0; failed=0
while read -r name kind file rest; do
  case "$name" in ''|'#'*) continue ;; esac
  read -ra args <<< "$rest"
  out="$work/$name"
  if [ "$kind" = material ]; then
    mkdir -p "$out"
    "$exe" material "$src/$file" --out "$out/out.csv" > "$out.log" 2>&1
  else
    # exit 1 is a simulation that stopped (a golden may record that); the
    # records hash legacy frames (runs.txt says why)
    "$exe" run "$src/$file" --quiet --out "$out" --set output.format=vtk "${args[@]}" > "$out.log" 2>&1
  fi
  rc=$?
  if [ $rc -gt 1 ] || [ ! -e "$out/summary.json" -a "$kind" = run ] || [ ! -e "$out/out.csv" -a "$kind" = material ]; then
    echo "FAIL: $name: mpgm exited $rc:"; cat "$out.log"; failed=$((failed + 1)); continue
  fi
  gold="$src/tests/golden/$name.json"
  if [ "$update" = --update ]; then
    python3 "$src/tests/tools/golden.py" write "$out" "$kind" "$gold" && echo "WROTE: $gold"
    continue
  fi
  if [ ! -e "$gold" ]; then
    echo "FAIL: $name: no golden record $gold"; failed=$((failed + 1)); continue
  fi
  if diff=$(python3 "$src/tests/tools/golden.py" compare "$out" "$kind" "$gold"); then
    echo "PASS: $name: same as tests/golden/$name.json to the bit"; pass=$((pass + 1))
  else
    echo "FAIL: $name differs from tests/golden/$name.json:"; echo "$diff"; failed=$((failed + 1))
  fi
done < "$src/tests/golden/runs.txt"
echo "$pass passed, $failed failed"
[ $failed -eq 0 ]
