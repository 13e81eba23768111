#!/usr/bin/env python3
"""same_run.py A B -- are two results folders of one scene the same run?

Compared to the bit: probes.csv; steps.csv with its wall-clock column
(wall_s) left out; every file under vtk/ and every collection (.pvd, .vtk.series); in
summary.json the status and message, the failed step, the resolved scene,
the metrics, the probes, the step cuts, the last step's Newton record and
the counts (clock_reads and solver_memory_peak left out: they
count the process's clock reads and memory, not the run's work). Used by
tests/scripts/restart.sh. Prints what differs; exit 0 when nothing does.
"""
import csv
import filecmp
import io
import json
import os
import sys

PROCESS_COUNTS = {"clock_reads", "solver_memory_peak"}


def steps_without_wall(path):
    rows = list(csv.reader(io.StringIO(open(path).read())))
    if not rows:
        return rows
    drop = [i for i, name in enumerate(rows[0]) if name == "wall_s"]
    return [[v for i, v in enumerate(r) if i not in drop] for r in rows]


def files(root):
    out = []
    for d, _, names in os.walk(root):
        for n in names:
            out.append(os.path.relpath(os.path.join(d, n), root))
    return sorted(out)


def main(a, b):
    diffs = []
    if not filecmp.cmp(f"{a}/probes.csv", f"{b}/probes.csv", shallow=False):
        diffs.append("probes.csv")
    if steps_without_wall(f"{a}/steps.csv") != steps_without_wall(f"{b}/steps.csv"):
        diffs.append("steps.csv")
    fa = [f for f in files(a) if f.startswith("vtk/") or f.endswith((".pvd", ".series"))]
    fb = [f for f in files(b) if f.startswith("vtk/") or f.endswith((".pvd", ".series"))]
    if fa != fb:
        diffs.append(f"VTK files: {sorted(set(fa) ^ set(fb))}")
    for f in fa:
        if f in fb and not filecmp.cmp(f"{a}/{f}", f"{b}/{f}", shallow=False):
            diffs.append(f)
    sa = json.load(open(f"{a}/summary.json"))
    sb = json.load(open(f"{b}/summary.json"))
    for key in ("status", "message", "failed_step", "scene", "metrics", "probes", "step_cuts",
                "newton_last_step"):
        if sa.get(key) != sb.get(key):
            diffs.append(f"summary.json {key}: {sa.get(key)} / {sb.get(key)}")
    ca, cb = sa.get("counts", {}), sb.get("counts", {})
    for k in sorted(set(ca) | set(cb)):
        if k not in PROCESS_COUNTS and ca.get(k) != cb.get(k):
            diffs.append(f"counts.{k}: {ca.get(k)} / {cb.get(k)}")
    for d in diffs:
        print(f"  differs: {d}")
    return 1 if diffs else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
