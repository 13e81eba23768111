#!/usr/bin/env python3
"""same_ranks.py ONE MANY [TOL] -- does a run on many processes give the
one-process run's answers (issue 54)?

ONE and MANY are results folders of the same scene, MANY written under
mpiexec. The sums over the points and at the nodes shared by processes
are taken in another order, so the runs agree to rounding, not to the
bit: every number below must agree to TOL (default 1e-10) relative to the
largest magnitude of its column over the run (a column that is zero
throughout must stay zero to 1e-300):
  - probes.csv: every column (time, and each probe's u and v);
  - steps.csv: time, dt and the energies and momenta (the Newton columns
    are zero in explicit runs; wall_s is the clock's); a momentum relative
    to sqrt(2 M K) at least, the momentum of the whole mass M at the
    points' largest kinetic energy K (a momentum that is zero but for
    rounding, as two discs colliding head on have, has no scale of its
    own), and an energy relative to the largest of any energy column (the
    work of the stresses of a body in rigid motion is rounding too);
  - summary.json: status, the steps, the point count, and every metric.
The row counts and headers must be equal (but for steps.csv's last column
on many processes, imbalance, which must be 1 or more). Prints what differs, and the
worst relative difference of each file; exit 0 when everything agrees."""
import csv
import json
import sys

ENERGY = ("kinetic_energy", "internal_work", "external_work", "energy_total")
STEP_COLS = ("time", "dt", "kinetic_energy", "internal_work", "external_work", "energy_total",
             "momentum_x", "momentum_y", "momentum_z", "node_momentum_x", "node_momentum_y",
             "node_momentum_z")


def table(path):
    rows = list(csv.reader(open(path)))
    return rows[0], [[float(x) for x in r] for r in rows[1:]]


def columns(one, many, name, cols, tol, bad, pscale=0.0):
    ha, ra = table(f"{one}/{name}")
    hb, rb = table(f"{many}/{name}")
    if hb and hb[-1] == "imbalance" and ha[-1:] != ["imbalance"]:  # steps.csv on many processes
        imb = [r[-1] for r in rb]
        hb, rb = hb[:-1], [r[:-1] for r in rb]
        if not all(v >= 1.0 for v in imb):
            bad.append(f"{name}: an imbalance below 1: {min(imb)}")
    if ha != hb or len(ra) != len(rb):
        bad.append(f"{name}: {len(ra)} rows of {len(ha)} columns against {len(rb)} of {len(hb)}")
        return 0.0
    worst = 0.0
    for i, h in enumerate(ha):
        if i == 0 or (cols and h not in cols):
            continue
        scale = max(abs(r[i]) for r in ra)
        if "momentum" in h:
            scale = max(scale, pscale)
        if h in ENERGY:
            scale = max([scale] + [abs(r[ha.index(e)]) for e in ENERGY if e in ha for r in ra])
        for k, (x, y) in enumerate(zip(ra, rb)):
            d = abs(x[i] - y[i]) / scale if scale > 0 else (0.0 if abs(y[i]) <= 1e-300 else 1.0)
            worst = max(worst, d)
            if d > tol:
                bad.append(f"{name}: {h} of row {k}: {x[i]!r} against {y[i]!r} ({d:.3g} of the "
                           "column's largest)")
                break
    print(f"{name}: {len(ra)} rows, worst difference {worst:.3g} of a column's largest")
    return worst


def summary(one, many, tol, bad):
    a = json.load(open(f"{one}/summary.json"))
    b = json.load(open(f"{many}/summary.json"))
    for key in ("status",):
        if a[key] != b[key]:
            bad.append(f"summary.json: {key} {a[key]!r} against {b[key]!r}")
    for key in ("steps", "points", "probes"):
        if a["counts"][key] != b["counts"][key]:
            bad.append(f"summary.json: counts.{key} {a['counts'][key]} against {b['counts'][key]}")
    ma, mb = a.get("metrics", {}), b.get("metrics", {})
    if sorted(ma) != sorted(mb):
        bad.append(f"summary.json: metrics {sorted(ma)} against {sorted(mb)}")
    for k, v in ma.items():
        w = mb.get(k)
        if w is None or abs(v - w) > tol * max(abs(v), 1e-300):
            bad.append(f"summary.json: metrics.{k} {v!r} against {w!r}")
    print(f"summary.json: {len(ma)} metrics, {a['counts']['points']} points, "
          f"processes {b['counts'].get('processes', {}).get('count', 1)}")


def main():
    if len(sys.argv) not in (3, 4):
        print(__doc__)
        return 2
    one, many = sys.argv[1], sys.argv[2]
    tol = float(sys.argv[3]) if len(sys.argv) == 4 else 1e-10
    bad = []
    columns(one, many, "probes.csv", None, tol, bad)
    h, rows = table(f"{one}/steps.csv")
    mass = json.load(open(f"{one}/summary.json")).get("metrics", {}).get("mass_total", 0.0)
    kmax = max((r[h.index("kinetic_energy")] for r in rows), default=0.0) if "kinetic_energy" in h else 0.0
    columns(one, many, "steps.csv", STEP_COLS, tol, bad, (2.0 * mass * kmax) ** 0.5)
    summary(one, many, tol, bad)
    for b in bad:
        print("DIFFERS:", b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
