#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The fluid force between the two discs of a drafting-kissing-tumbling run
(tutorials/vansFoam/draftingKissingTumbling) along their line of centres,
set beside the two-dimensional squeeze film of lubrication theory.

At each write time: the gap delta = |x1 - x2| - D, the normal relative
velocity U_n = (U1 - U2).n (n from the lower disc to the upper one; > 0
separating) and the pair's fluid force F_n = (F1 - F2).n / 2 from the
grains' Ffluid (per unit depth; the buoyancy and the common drag cancel in
the difference; > 0 pushes the discs apart), both over the disc's net weight
W = (rho_p - rho_f) g pi a^2.  The reference is Reynolds' lubrication
equation for two equal cylinders of radius a, gap h(x) = delta + x^2/a, the
film squeezed at U_n (per unit depth, delta << a):

    F_lub = -3 sqrt(2) pi mu U_n (a* / delta)^(3/2),   a* = a/2,

which resists approach (U_n < 0: F_lub > 0) and separation alike (derived
from dp/dx = -12 mu Q / h^3 with the squeeze flux Q = -U_n x; O. Reynolds
1886; e.g. Batchelor, An Introduction to Fluid Dynamics, 4.8).  An
independent closed form: it is not what the coupling computes, and where
the film is thinner than a cell no mesh here resolves it.

usage: dktFilmForce.py CASEDIR [JSON]
       prints the rows with delta < D/2; JSON (optional) gets them with the
       case's first contact (gap < D/100) and the largest separating force.
"""

import json
import os
import sys

import nscdpost
import numpy as np

# the tutorial's post-processing: its set-up (discs, fluid) and its contact time
_dkt = nscdpost.load_module(
    "draftingKissingTumbling_postProcess",
    os.path.join(
        os.path.dirname(os.path.abspath(__file__)),
        "..",
        "..",
        "..",
        "tutorials",
        "vansFoam",
        "draftingKissingTumbling",
        "postProcess.py",
    ),
)
_setup = _dkt.setupCase
D, RHO_F, RHO_P = _setup.D, _setup.RHO_F, _setup.RHO_P  # [m], [kg/m^3] (the tutorial's)
MU, G = _setup.RHO_F * _setup.NU, 9.81  # [Pa s], [m/s^2]


def squeeze_film_force(delta, un, a=D / 2, mu=MU):
    """Reynolds' 2D squeeze-film force [N/m] between two equal cylinders of
    radius a [m] at gap delta [m] > 0, normal relative velocity un [m/s]
    (> 0 separating), fluid viscosity mu [Pa s]; > 0 pushes them apart."""
    return -3.0 * np.sqrt(2.0) * np.pi * mu * un * (0.5 * a / delta) ** 1.5


def film_history(case):
    """Rows (t [s], delta/D, U_n [m/s], F_n/W, F_lub/W) at the write times
    that hold the grains' Ffluid, and the discs' centres there [2, nt, 3] m."""
    a = D / 2
    W = (RHO_P - RHO_F) * G * np.pi * a * a
    rows, centres = [], []
    for time, name in nscdpost.time_dirs(case):
        g = nscdpost.read_grains(case, name)
        if "Ffluid" not in g or len(g["d"]) != 2:
            continue
        x, U, F = g["x"], g["U"], g["Ffluid"]
        d = x[0] - x[1]
        n = d / np.linalg.norm(d)
        delta = float(np.linalg.norm(d)) - D
        un = float(np.dot(U[0] - U[1], n))
        fn = 0.5 * float(np.dot(F[0] - F[1], n))
        flub = squeeze_film_force(max(delta, 1e-3 * D), un) if delta > 0 else float("nan")
        rows.append((time, delta / D, un, fn / W, flub / W))
        centres.append(x)
    return rows, np.transpose(np.array(centres), (1, 0, 2)) if centres else None


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    rows, x = film_history(sys.argv[1])
    if not rows:
        sys.exit(f"dktFilmForce.py: no write time of {sys.argv[1]} holds the two discs' Ffluid")
    print(" t [s]   gap/D    U_n [mm/s]   F_n/W (coupling)   F_lub/W (squeeze film)")
    for t, g, un, fn, fl in rows:
        if g < 0.5:
            print(f"{t:6.3f}  {g:7.4f}  {1e3 * un:9.3f}  {fn:14.3f}  {fl:14.3f}")
    if len(sys.argv) > 2:
        contact = _dkt.contact_time(np.array([r[0] for r in rows]), x, D)
        near = [r for r in rows if r[1] < 0.5]
        top = max(near, key=lambda r: r[3]) if near else None
        out = {
            "case": sys.argv[1],
            "first_contact_time_s": contact,
            "largest_separating_fluid_force_over_weight": top[3] if top else None,
            "largest_separating_fluid_force_time_s": top[0] if top else None,
            "rows_gap_below_half_D": [
                {
                    "t": r[0],
                    "gap_over_D": r[1],
                    "normal_velocity_m_s": r[2],
                    "fluid_force_over_weight": r[3],
                    "squeeze_film_force_over_weight": r[4],
                }
                for r in near
            ],
        }
        with open(sys.argv[2], "w") as fo:
            json.dump(out, fo, indent=1)
            fo.write("\n")


if __name__ == "__main__":
    main()
