#!/usr/bin/python3
"""top_history.py OUTDIR CSV

OUTDIR: a case directory written by make_column.py (contains mpm.json and
results/<uuid>/particlesNNN.h5), or directly the directory holding the
particlesNNN.h5 files (then dt is taken from ../../mpm.json or --dt).
Writes CSV with columns t,uy_top: mean y displacement of the top layer of
particles (those whose initial y is the largest), t = step*dt.
"""
import argparse
import glob
import json
import os
import re
import sys

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("outdir")
    ap.add_argument("csv")
    ap.add_argument("--dt", type=float, default=None)
    a = ap.parse_args()

    d = a.outdir
    cfg = None
    if os.path.isfile(os.path.join(d, "mpm.json")):
        with open(os.path.join(d, "mpm.json")) as f:
            cfg = json.load(f)
        res = os.path.join(d, cfg["post_processing"].get("path", "results/"),
                           cfg["analysis"]["uuid"])
    else:
        res = d
        for cand in (os.path.join(d, "..", "..", "mpm.json"),):
            if os.path.isfile(cand):
                with open(cand) as f:
                    cfg = json.load(f)
    dt = a.dt if a.dt is not None else (cfg["analysis"]["dt"] if cfg else None)
    if dt is None:
        sys.exit("dt unknown: give --dt")

    files = []
    for fn in glob.glob(os.path.join(res, "particles*.h5")):
        m = re.fullmatch(r"particles(\d+)\.h5", os.path.basename(fn))
        if m:
            files.append((int(m.group(1)), fn))
    files.sort()
    if not files:
        sys.exit(f"no particles*.h5 in {res}")

    top_ids = None
    rows = []
    for step, fn in files:
        with h5py.File(fn, "r") as f:
            t = f["table"]
            ids = t["id"][:]
            y = t["coord_y"][:]
            uy = t["displacement_y"][:]
        y0 = y - uy                       # initial (reference) y
        if top_ids is None:
            ymax = y0.max()
            top_ids = np.sort(ids[np.abs(y0 - ymax) < 1e-9 * max(1.0, ymax)])
            print(f"top layer: {top_ids.size} particles at y0={ymax:.6g}",
                  file=sys.stderr)
        sel = np.isin(ids, top_ids)
        if sel.sum() != top_ids.size:
            print(f"warning: step {step}: {sel.sum()} of {top_ids.size} top "
                  "particles present", file=sys.stderr)
        rows.append((step * dt, float(uy[sel].mean())))

    steps = [s for s, _ in files]
    gaps = np.diff(steps)
    if gaps.size and (gaps != gaps[0]).any():
        print("warning: irregular output steps", file=sys.stderr)

    with open(a.csv, "w") as f:
        f.write("t,uy_top\n")
        for t, u in rows:
            f.write(f"{t:.10g},{u:.10e}\n")
    arr = np.array(rows)
    i = arr[:, 1].argmin()
    print(f"{len(rows)} outputs, steps {steps[0]}..{steps[-1]}; "
          f"min uy_top = {arr[i,1]:.6f} at t = {arr[i,0]:.4f}", file=sys.stderr)


if __name__ == "__main__":
    main()
