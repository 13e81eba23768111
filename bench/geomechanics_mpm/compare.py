#!/usr/bin/env python3
"""compare.py MPGM_PROBES_CSV GEOMECH_TOP_CSV [--json OUT]

The top displacement of the elastic column (cases/column_wave_3d.json)
from mpgm (probes.csv, column top_uy) and from geomechanics/mpm (the mean
y displacement of its top layer of particles, written by top_history.py),
row by row at the common times, and each against the closed form of the
laterally confined column under gravity applied at t = 0 (the reference
kind column_wave, references/reference_column_wave.c): the top falls
freely until the wave from the base arrives at H/c, stops at
-rho g H^2 / M at 2H/c and returns to 0 at 4H/c. Prints one line per
quantity; --json writes them for the report."""
import argparse
import csv
import json
import math

H, E, NU, RHO, G = 10.0, 1.0e7, 0.3, 2000.0, 9.81
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))


def exact(t):
    c = math.sqrt(M / RHO)
    T = 4 * H / c
    tau = math.fmod(t, T)
    if tau > 0.5 * T:
        tau = T - tau
    t1, wmax = H / c, RHO * G * H * H / M
    if tau <= t1:
        return -0.5 * G * tau * tau
    s = 2 * t1 - tau
    return -(wmax - 0.5 * G * s * s)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mpgm")
    ap.add_argument("geomech")
    ap.add_argument("--json")
    a = ap.parse_args()
    ours = {round(float(r["time"]), 9): float(r["top_uy"]) for r in csv.DictReader(open(a.mpgm))}
    theirs = {round(float(r["t"]), 9): float(r["uy_top"]) for r in csv.DictReader(open(a.geomech))}
    times = sorted(set(ours) & set(theirs))
    if len(times) < 2:
        raise SystemExit("compare.py: fewer than two common times")
    amp = RHO * G * H * H / M
    out = {
        "rows": len(times),
        "amplitude_ref": amp,
        "mpgm_amplitude": max(ours[t] for t in times) - min(ours[t] for t in times),
        "geomech_amplitude": max(theirs[t] for t in times) - min(theirs[t] for t in times),
        "difference_max": max(abs(ours[t] - theirs[t]) for t in times),
        "mpgm_error_max": max(abs(ours[t] - exact(t)) for t in times),
        "geomech_error_max": max(abs(theirs[t] - exact(t)) for t in times),
    }
    for k in ("difference_max", "mpgm_error_max", "geomech_error_max"):
        out[k + "_relative"] = out[k] / amp
    for k, v in out.items():
        print(f"{k} = {v:.6g}")
    if a.json:
        json.dump(out, open(a.json, "w"), indent=1)


if __name__ == "__main__":
    main()
