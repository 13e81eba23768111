"""script_check.py -- what the Python parts of tests/scripts/*.sh share.

    sys.path.insert(0, SOURCE_DIR + "/tests/tools")
    from script_check import check, summary, finite, done

check(ok, msg) prints one PASS/FAIL line and counts it; summary(work, name)
reads WORK/NAME/summary.json; finite(x) is True when every number in a
JSON value is finite; done() prints "N passed, M failed" and exits 1 on a
failure (the line tests/scripts report by).
"""
import json
import math
import sys

_count = {"pass": 0, "fail": 0}


def check(ok, msg):
    print(("PASS: " if ok else "FAIL: ") + msg)
    _count["pass" if ok else "fail"] += 1
    return ok


def summary(work, name):
    with open(f"{work}/{name}/summary.json") as f:
        return json.load(f)


def finite(x):
    if isinstance(x, dict):
        return all(finite(v) for v in x.values())
    if isinstance(x, list):
        return all(finite(v) for v in x)
    if isinstance(x, (int, float)):
        return math.isfinite(x)
    return x is not None


def done():
    print(f"{_count['pass']} passed, {_count['fail']} failed")
    sys.exit(1 if _count["fail"] else 0)
