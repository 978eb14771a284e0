#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Peer-code run of the sedimentation case with MigFlow 1.4 (PyPI `migflow`).

Case: tutorials/vansFoam/sedimentation (M. Henry, PhD thesis, UCLouvain,
section 3.2.2) as its setupCase.py: closed 0.4 x 0.6 m box (no-slip fluid
walls, frictional grain walls), water (1000 kg/m^3, 1e-3 Pa s), g 9.81 m/s^2,
discs r = 1.5 mm, 1500 kg/m^3, friction 0.3, the tutorial's packing.py: the
square lattice of spacing 2r (6,650 discs, 133 columns centred in x, 50 rows,
top centres at y = 0.6 - 2e-3 - r) or, with --packing hexagonal, the thesis'
hexagonal packing (7,553 discs, 57 rows), at rest at t = 0; gmsh triangles of 9 mm (h/d = 3).  MigFlow's defaults
otherwise: drag (2D: per unit depth), exact disc/triangle overlap porosity,
fluid-then-grains step.  Contact tolerance 1e-4 d (vansFoam's bench value;
MigFlow's 1e-8 m costs ~10x and gave the same front at t = 0.05 s).
Time step 5e-3 s (vansFoam's maxDeltaT here; MigFlow's fluid step is implicit
and it sub-steps the grains when |v| dt > r/8); third argument to change it.

Linear solver: the wheel only has MigFlow's scipy backend (Pardiso needs the
`mkl` wheel), whose SuperLU factorisation of the system bordered by the
mean-pressure row takes 5.4 s per step.  PinnedPressureSystem solves it with
one pressure dof pinned, then shifts the pressure to the imposed mean (exact:
the closed-box null space is the constant pressure), 0.12-0.18 s; it checks
the bordered residual and falls back to MigFlow's solve above 1e-9.

Measure (as tutorials/vansFoam/sedimentation/postProcess.py): front_height(t)
= 0.5 % quantile of grain centre heights minus r, every 0.05 s; fall_Xs =
front_height(0) - front_height(X); the row spread (packing.row_spread) at the
times of SNAPSHOTS, whose grain positions go to OUTDIR/positions.npz (t0,
t0.5, ...: (n, 2) arrays [m]; row: each grain's starting row).  Reference: MigFlow 1.4 run of this case in
issue 25: leading-edge fall 0.118 m at 1 s, 0.283 m at 2 s.

usage: migflowSedimentation.py OUTDIR [ENDTIME [DT]] [--packing square|hexagonal]
           [--effective-diameter-factor K]   (the fluid sees radius K r)
       ->  OUTDIR/front.json, OUTDIR/positions.npz

Install MigFlow in a virtual environment (`python3 -m venv v; v/bin/pip
install migflow gmsh scipy`): PyPI's gmsh puts its own `gmsh` executable on
PATH ahead of Debian's, and the lituyaBay tutorial's mesh then changes.
"""

import argparse
import contextlib
import json
import os
import sys
import time

import gmsh
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from migflow import fluid, scipylsys, scontact, time_integration  # initialises gmsh

sys.path.insert(
    0,
    os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "../../tutorials/vansFoam/sedimentation"
    ),
)
import packing  # noqa: E402  (the tutorial's lattices and measures)

W, H = 0.4, 0.6  # box [m]
R, RHO_P, FRICTION = 1.5e-3, 1500.0, 0.3
RHO, MU = 1000.0, 1e-3
G = np.array([0.0, -9.81])
MESH_SIZE = 9e-3  # h/d = 3
CONTACT_TOL = 1e-4 * 2 * R  # m, NSCD tolerance of vansFoam's bench
SAMPLE = 0.05  # s between front samples
SNAPSHOTS = (0.0, 0.5, 1.0, 2.0)  # s: grain positions written (OUTDIR/positions.npz)
SIDES = {
    "Bottom": ((0, 0), (W, 0)),
    "Right": ((W, 0), (W, H)),
    "Top": ((W, H), (0, H)),
    "Left": ((0, H), (0, 0)),
}


class PinnedPressureSystem(scipylsys.LinearSystem):
    """[K c; c^T 0][s; l] = b (c: node volumes on pressure dofs) solved with one
    pressure dof pinned, then s_p shifted so that c.s = b_n; returns s (ndof,)."""

    def solve(self, rhs):
        n, A = self.ndof, self.matrix
        if len(self.constraints) != 1:
            return super().solve(rhs)
        p = self.constraints[0]
        keep = np.ones(n)
        keep[p[0]] = 0.0
        D = sp.diags(keep)
        K = (D @ A[:n, :n] @ D + sp.csc_matrix(([1.0], ([p[0]], [p[0]])), shape=(n, n))).tocsc()
        b = rhs[:n] * keep
        s = sla.splu(K, permc_spec="COLAMD").solve(b)
        c = A[n, :n].toarray().ravel()
        s[p] += (rhs[n] - c @ s) / c[p].sum()
        res = np.linalg.norm(A[:, :n] @ s - rhs)
        if res > 1e-9 * max(np.linalg.norm(rhs), 1e-300):
            print(f"pinned solve residual {res:.3g}: MigFlow's own solve", file=sys.stderr)
            return super().solve(rhs)
        return s


def mesh_box():
    """Triangulate the box with gmsh (current model), one physical line per side."""
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("box")
    gmsh.model.occ.addRectangle(0, 0, 0, W, H)
    gmsh.model.occ.synchronize()
    e = 1e-6
    for name, ((x0, y0), (x1, y1)) in SIDES.items():
        lines = gmsh.model.getEntitiesInBoundingBox(
            min(x0, x1) - e, min(y0, y1) - e, -e, max(x0, x1) + e, max(y0, y1) + e, e, 1
        )
        gmsh.model.addPhysicalGroup(1, [t for _, t in lines], name=name)
    gmsh.model.addPhysicalGroup(2, [1], name="domain")
    gmsh.option.setNumber("Mesh.MeshSizeMin", MESH_SIZE)
    gmsh.option.setNumber("Mesh.MeshSizeMax", MESH_SIZE)
    gmsh.model.mesh.generate(2)


def front_height(p):
    """Leading edge of the falling front [m] (packing.front_height)."""
    return packing.front_height(p.position()[:, 1])


def arguments():
    a = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    a.add_argument("outdir")
    a.add_argument("end", nargs="?", type=float, default=2.0)
    a.add_argument("dt", nargs="?", type=float, default=5e-3)
    a.add_argument("--packing", choices=list(packing.ROWS), default="square")
    a.add_argument("--effective-diameter-factor", type=float, default=1.0, metavar="K")
    return a.parse_args()


def main():
    args = arguments()
    outdir, end, dt = args.outdir, args.end, args.dt
    os.makedirs(outdir, exist_ok=True)
    xy, row = packing.lattice(args.packing)

    p = scontact.ParticleProblem(2)
    for x in xy:
        p.add_particle(x, R, RHO_P * np.pi * R**2)
    for name, (a, b) in SIDES.items():
        p.add_boundary_segment(np.array(a, float), np.array(b, float), name)
    p.set_friction_coefficient(FRICTION)  # grain-grain and grain-wall

    mesh_box()
    f = fluid.FluidProblem(2, G, [MU], [RHO], solver="scipy")  # default drag, stabilisation
    f.linear_system_package = PinnedPressureSystem
    f.load_msh(None)
    if args.effective_diameter_factor != 1.0:
        # the fluid sees discs of radius K r (vansFoam's effectiveDiameterFactor,
        # thesis section 3.2.3): MigFlow's fluid takes the radius from the
        # volume it is given (fluid.set_particles), the grains keep theirs
        k2, set_particles = args.effective_diameter_factor**2, f.set_particles
        f.set_particles = lambda delassus, volume, *a: set_particles(delassus, k2 * volume, *a)
    f.set_wall_boundary(list(SIDES), velocity=[0.0, 0.0])  # no-slip walls
    f.set_mean_pressure(0.0)  # closed box: fix the pressure level
    weight = p.volume() * RHO_P * G  # buoyancy comes from the fluid pressure

    every = int(round(SAMPLE / dt))
    nsteps = int(round(end / dt))
    times, front = [0.0], [front_height(p)]
    snaps = {"row": row, "t0": p.position().copy()}
    tic, cpu = time.time(), time.process_time()
    with open(os.devnull, "w") as null:
        for step in range(1, nsteps + 1):
            with contextlib.redirect_stdout(null):  # MigFlow prints per-step timings
                time_integration.iterate(
                    f, p, dt, contact_tol=CONTACT_TOL, external_particles_forces=weight
                )
            t = round(step * dt, 10)
            if any(abs(t - s) < 0.5 * dt for s in SNAPSHOTS):
                snaps[f"t{t:g}"] = p.position().copy()
            if step % every == 0:
                times.append(round(step * dt, 10))
                front.append(front_height(p))
                print(
                    f"t {times[-1]:.2f} s  front {front[-1]:.4f} m  wall {time.time() - tic:.1f} s",
                    file=sys.stderr,
                    flush=True,
                )
    wall, cpu = time.time() - tic, time.process_time() - cpu

    np.savez_compressed(os.path.join(outdir, "positions.npz"), **snaps)
    spread = {k: packing.row_spread(row, v[:, 1]) for k, v in snaps.items() if k.startswith("t")}
    fall = lambda t: front[0] - front[times.index(t)] if t in times else None  # noqa: E731
    out = {
        "case": "tutorials/vansFoam/sedimentation (thesis section 3.2.2)",
        "packing": args.packing,
        "effective_diameter_factor": args.effective_diameter_factor,
        "time": times,
        "front_height": front,
        "fall_1s": fall(1.0),
        "fall_2s": fall(2.0),
        "row_spread": {k: {"lowest_row": a, "median_lowest_10": b} for k, (a, b) in spread.items()},
        "wall_seconds": wall,
        "cpu_seconds": cpu,
        "dt": dt,
        "mesh_size": MESH_SIZE,
        "grains": int(p.n_particles()),
        "triangles": int(f.n_elements()),
        "migflow_version": "1.4.0",
        "reference": "MigFlow 1.4 run in issue 25: fall 0.118 m at 1 s, 0.283 m at 2 s",
    }
    with open(os.path.join(outdir, "front.json"), "w") as fh:
        json.dump(out, fh, indent=1)
    print(f"fall_1s {out['fall_1s']}  fall_2s {out['fall_2s']}  wall {wall:.1f} s")


if __name__ == "__main__":
    main()
