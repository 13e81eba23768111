#!/usr/bin/env python3
"""Write a geomechanics/mpm (CB-Geo fork) input set for the elastic column.

usage: make_column.py H OUTDIR [options]

Column 1 x 10 x 1 m (x in [0,1], y in [0,10] vertical, z in [0,1]), cubic
H8 cells of size H, 2x2x2 particles per cell at the Gauss points
(+-1/sqrt(3) in local coordinates), volume H^3/8 each.  LinearElastic3D
E=1e7, nu=0.3, rho=2000, zero initial stress, gravity (0,-9.81,0) from t=0.
BCs (displacement constraints = the only nodal BCs the implicit solver
applies): y=0 fixed in x,y,z; x=0 and x=1: ux=0; z=0 and z=1: uz=0.
Implicit Newmark beta=0.25, gamma=0.5, dt=0.0025, 400 steps.

Files written to OUTDIR:
  mpm.json, mesh.txt, particles.txt, particles-cells.txt,
  particles-volumes.txt, displacement-constraints.txt
Run:  mpm -f OUTDIR/ -i mpm.json -p 1      (results in OUTDIR/results/column/)
"""
import argparse
import json
import math
import os


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("H", type=float)
    ap.add_argument("outdir")
    ap.add_argument("--dt", type=float, default=0.0025)
    ap.add_argument("--nsteps", type=int, default=400)
    ap.add_argument("--output-steps", type=int, default=1)
    ap.add_argument("--no-extend", action="store_true",
                    help="do not add the extra layer of cells above y=10")
    ap.add_argument("--solver", default="ldlt",
                    choices=["ldlt", "lu", "cg", "bicgstab", "lscg"],
                    help="ldlt/lu -> DirectEigen, cg/bicgstab/lscg -> "
                         "IterativeEigen")
    ap.add_argument("--lin-tol", type=float, default=1e-10,
                    help="IterativeEigen relative tolerance (ignored by direct)")
    ap.add_argument("--lin-maxiter", type=int, default=10000)
    ap.add_argument("--linear", action="store_true",
                    help="scheme_settings.nonlinear=false: one linear solve "
                         "per step, no Newton check")
    ap.add_argument("--verbosity", type=int, default=2,
                    help="Newton verbosity (1: iteration count, 2: norms)")
    a = ap.parse_args()

    H = a.H
    nx = round(1.0 / H)
    ny = round(10.0 / H)
    nz = round(1.0 / H)
    for n, L in ((nx, 1.0), (ny, 10.0), (nz, 1.0)):
        if abs(n * H - L) > 1e-12 * L:
            raise SystemExit("H must divide 1 and 10 exactly")
    nyc = ny if a.no_extend else ny + 1      # mesh cell layers in y
    os.makedirs(a.outdir, exist_ok=True)
    d = a.outdir

    # ---- nodes: id = i + (nx+1)*(j + (nyc+1)*k)
    NX, NY = nx + 1, nyc + 1

    def nid(i, j, k):
        return i + NX * (j + NY * k)

    nnodes = NX * NY * (nz + 1)
    ncells = nx * nyc * nz
    lines = ["! elementShape hexahedron", "! elementNumPoints 8",
             f"{nnodes}\t{ncells}"]
    coords = [None] * nnodes
    for k in range(nz + 1):
        for j in range(nyc + 1):
            for i in range(nx + 1):
                coords[nid(i, j, k)] = (i * H, j * H, k * H)
    lines += ["%.16g\t%.16g\t%.16g" % c for c in coords]
    # ---- cells: id = i + nx*(j + nyc*k); CB-Geo H8 order
    # 0:(0,0,0) 1:(1,0,0) 2:(1,1,0) 3:(0,1,0) 4:(0,0,1) 5:(1,0,1) 6:(1,1,1) 7:(0,1,1)
    def cid(i, j, k):
        return i + nx * (j + nyc * k)

    cells = [None] * ncells
    for k in range(nz):
        for j in range(nyc):
            for i in range(nx):
                cells[cid(i, j, k)] = (
                    nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k),
                    nid(i, j + 1, k), nid(i, j, k + 1), nid(i + 1, j, k + 1),
                    nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1))
    lines += ["\t".join(str(n) for n in c) for c in cells]
    with open(os.path.join(d, "mesh.txt"), "w") as f:
        f.write("\n".join(lines) + "\n")

    # ---- particles (only in material cells y<10)
    g = 1.0 / math.sqrt(3.0)
    loc = ((1 - g) * 0.5, (1 + g) * 0.5)   # Gauss points in [0,1] cell coords
    pts, pcell = [], []
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                c = cid(i, j, k)
                for lk in loc:
                    for lj in loc:
                        for li in loc:
                            pts.append(((i + li) * H, (j + lj) * H, (k + lk) * H))
                            pcell.append(c)
    with open(os.path.join(d, "particles.txt"), "w") as f:
        f.write(f"{len(pts)}\n")
        f.write("".join("%.16g\t%.16g\t%.16g\n" % p for p in pts))
    with open(os.path.join(d, "particles-cells.txt"), "w") as f:
        f.write("".join(f"{p}\t{c}\n" for p, c in enumerate(pcell)))
    vol = H ** 3 / 8.0
    with open(os.path.join(d, "particles-volumes.txt"), "w") as f:
        f.write("".join("%d\t%.16g\n" % (p, vol) for p in range(len(pts))))

    # ---- displacement constraints: "node dir value"
    cons = set()
    eps = 1e-9
    for n, (x, y, z) in enumerate(coords):
        if y < eps:
            cons.update({(n, 0), (n, 1), (n, 2)})
        if x < eps or x > 1 - eps:
            cons.add((n, 0))
        if z < eps or z > 1 - eps:
            cons.add((n, 2))
    with open(os.path.join(d, "displacement-constraints.txt"), "w") as f:
        f.write("".join(f"{n}\t{dr}\t0\n" for n, dr in sorted(cons)))

    # ---- JSON
    if a.solver in ("ldlt", "lu"):
        solver_type = "DirectEigen"
    else:
        solver_type = "IterativeEigen"
    cfg = {
        "title": f"Elastic column H={H}",
        "mesh": {
            "mesh": "mesh.txt",
            "io_type": "Ascii3D",
            "check_duplicates": False,
            "isoparametric": False,
            "node_type": "N3D",
            "cell_type": "ED3H8",
            "particle_cells": "particles-cells.txt",
            "particles_volumes": "particles-volumes.txt",
            "boundary_conditions": {
                "displacement_constraints": [
                    {"file": "displacement-constraints.txt"}]
            },
        },
        "particles": [{
            "generator": {
                "type": "file",
                "io_type": "Ascii3D",
                "location": "particles.txt",
                "particle_type": "P3D",
                "material_id": 0,
                "pset_id": 0,
                "check_duplicates": False,
            }
        }],
        "materials": [{
            "id": 0,
            "type": "LinearElastic3D",
            "density": 2000.0,
            "youngs_modulus": 1.0e7,
            "poisson_ratio": 0.3,
        }],
        "external_loading_conditions": {"gravity": [0.0, -9.81, 0.0]},
        "analysis": {
            "type": "MPMImplicit3D",
            "mpm_scheme": "newmark",
            "scheme_settings": {
                "nonlinear": not a.linear,
                "quasi_static": False,
                "beta": 0.25,
                "gamma": 0.5,
                "max_iteration": 20,
                "displacement_tolerance": 1.0e-10,
                "residual_tolerance": 1.0e-10,
                "relative_residual_tolerance": 1.0e-6,
                "verbosity": a.verbosity,
            },
            "linear_solver": {
                "assembler_type": "EigenImplicit3D",
                "solver_settings": [{
                    "dof": "displacement",
                    "solver_type": solver_type,
                    "sub_solver_type": a.solver,
                    "max_iter": a.lin_maxiter,
                    "tolerance": a.lin_tol,
                    "verbosity": 0,
                }],
            },
            "locate_particles": True,
            "pressure_smoothing": False,
            "velocity_update": "flip",
            "damping": {"type": "None", "damping_factor": 0.0},
            "dt": a.dt,
            "nsteps": a.nsteps,
            "uuid": "column",
            "resume": {"resume": False},
        },
        "post_processing": {
            "path": "results/",
            "output_steps": a.output_steps,
            "vtk": ["displacements"],
        },
    }
    with open(os.path.join(d, "mpm.json"), "w") as f:
        json.dump(cfg, f, indent=2)
    print(f"H={H}: {nnodes} nodes, {ncells} mesh cells "
          f"({nx*ny*nz} with material), {len(pts)} particles, "
          f"{len(cons)} constrained dofs -> {d}")


if __name__ == "__main__":
    main()
