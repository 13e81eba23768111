# checks.bash -- sourced by tests/scripts/*.sh: pass/fail counting and the
# exit-code-and-message check shared by the command-line tests.
#   ok DESCRIPTION / ko DESCRIPTION     count a check (npass, nfail)
#   summary_metric DIR NAME            print metrics.NAME of DIR/summary.json
#                                      (nan when the run left none)
#   sanitized EXE                      true when EXE is built with AddressSanitizer
#                                      (scripts/test --sanitize): tests then run
#                                      their coarser levels only
#   expect CODE NEEDLE DESCRIPTION CMD...
#     runs CMD with stdout in out.txt and stderr in err.txt (current folder);
#     passes when it exits with CODE and stderr contains NEEDLE.
npass=0; nfail=0
ok() { echo "PASS: $1"; npass=$((npass + 1)); }
ko() { echo "FAIL: $1"; nfail=$((nfail + 1)); }
expect() { # code, needle, description, command...
  local code="$1" needle="$2" what="$3"; shift 3
  "$@" > out.txt 2> err.txt; local rc=$?
  if [ $rc -eq "$code" ] && grep -qF -- "$needle" err.txt; then ok "$what (exit $rc)"
  else ko "$what: exit $rc (expected $code), stderr: $(head -c 400 err.txt)"; fi
}
summary_metric() {
  python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["metrics"][sys.argv[2]])' \
    "$1/summary.json" "$2" 2> /dev/null || echo nan
}
# grep -c reads all of nm's output (with pipefail, grep -q may not)
sanitized() { nm -an "$1" 2> /dev/null | grep -c __asan_init > /dev/null; }
