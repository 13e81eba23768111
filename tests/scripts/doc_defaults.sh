#!/usr/bin/env bash
# Every default docs/scene-format.md states is the one `mpgm check`
# resolves (issue 16, item 6: the page said dynamic gravity ramps and the
# initial acceleration is zero; neither was so): tests/tools/doc_defaults.py
# reads the page's tables and compares each default with minimal scenes.
# usage: doc_defaults.sh MPGM_EXE SOURCE_DIR WORK_DIR
set -uo pipefail
exe="$1"; src="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
python3 "$src/tests/tools/doc_defaults.py" "$exe" "$src" "$work"
