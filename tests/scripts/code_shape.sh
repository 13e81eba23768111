#!/usr/bin/env bash
# The house rules on size (docs/architecture.md): no function over 120 lines
# and no C file over 800 lines in the library and the command
# (tests/tools/code_shape.py finds the functions of every .c and .h).
# usage: code_shape.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
src="$2"
cd "$src"
if python3 tests/tools/code_shape.py base core io references discretisation fem gmm mpm frontends \
     shapefn materials solvers app; then
  echo "1 passed, 0 failed"
else
  echo "0 passed, 1 failed"; exit 1
fi
