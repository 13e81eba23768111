# run_case.bash -- sourced by tests/scripts/*.sh (needs exe, work, fail):
#   run_case NAME SCENE [ARGS...]
# runs `mpgm run SCENE --quiet --set output.vtk=none --out WORK/NAME ARGS`
# with its output in WORK/NAME.log; on failure prints the log and sets
# fail=1.
run_case() {
  local name="$1" scene="$2"; shift 2
  "$exe" run "$scene" --quiet --set output.vtk=none --out "$work/$name" "$@" > "$work/$name.log" 2>&1 \
    || { echo "FAIL: run $name ($*):"; cat "$work/$name.log"; fail=1; }
}
