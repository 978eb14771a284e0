#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Set up the liquid-fluidised bed of spheres (vansFoam, 3D).

usage: setupCase.py CASEDIR [--across N] [--grains N] [--u0 U] [--end T] [--ranks NP]

A square column of water, W = N_across lattice spacings wide, with glass
spheres (d uniform in [0.95, 1.045] mm, rho_p = 2500 kg/m^3) put on the
loose jittered lattice of grainDeposit (spacing s = 1.1 d_max, solid
fraction ~0.34) from the floor up, and water entering through the floor at
the superficial velocity U_0.  The cells are h = 3 s wide (h/d ~ 3.5; each cell layer holds three lattice layers) and
the column is twice the initial bed high.  Defaults: the tutorial's
100,000 spheres, 42 spacings across (14 x 38 x 14 cells), U_0 = 0.06 m/s,
0.5 s, 4 ranks.
"""

import argparse
import math
import os

import nscdpost

here = os.path.dirname(os.path.abspath(__file__))

D_MIN, LAMBDA = 0.95e-3, 1.1
D_MAX = LAMBDA * D_MIN
SPACING = 1.1 * D_MAX  # grainDeposit's lattice spacing
SPACINGS_PER_CELL = 3  # h = 3 s: each cell layer holds three lattice layers
RHO, RHO_P, NU, G = 1000.0, 2500.0, 1e-6, 9.81


def decomposition(ranks):
    """(nx, nz) of the simple decomposition across the cross-section."""
    return {1: (1, 1), 2: (2, 1), 4: (2, 2), 8: (4, 2)}[ranks]


def setup(case, across=42, grains=100000, u0=0.06, end=0.5, ranks=4, dt=1e-3, write=0.05):
    """Write the case; returns its geometry and parameters (also in case/bed.json)."""
    if across % SPACINGS_PER_CELL:
        raise SystemExit(
            f"setupCase.py: --across {across}: must be a multiple of {SPACINGS_PER_CELL}"
            f" (h = {SPACINGS_PER_CELL} lattice spacings)"
        )
    nx = across // SPACINGS_PER_CELL
    # the lattice holds floor(W/s) nodes across: W a hair above across*s
    width = (across + 1e-6) * SPACING
    layers = math.ceil(grains / across**2)
    h_box = (layers + 1e-6) * SPACING
    h = width / nx
    ny = math.ceil(2 * h_box / h)
    npx, npz = decomposition(ranks)
    subs = {
        "@W@": f"{width:.12g}",
        "@HC@": f"{ny * h:.12g}",
        "@NX@": str(nx),
        "@NY@": str(ny),
        "@HBOX@": f"{h_box:.12g}",
        "@NGRAINS@": str(grains),
        "@DMIN@": f"{D_MIN:g}",
        "@LAMBDA@": f"{LAMBDA:g}",
        "@U0@": f"{u0:.9g}",
        "@ENDTIME@": f"{end:g}",
        "@DT@": f"{dt:g}",
        "@WRITE@": f"{write:g}",
        "@NP@": str(ranks),
        "@NPX@": str(npx),
        "@NPZ@": str(npz),
    }
    nscdpost.instantiate_case(os.path.join(here, "base"), case, subs)
    info = {
        "width": width,
        "column_height": ny * h,
        "cells": [nx, ny, nx],
        "h": h,
        "grains": grains,
        "lattice_layers": layers,
        "lattice_spacing": SPACING,
        "d_min": D_MIN,
        "size_ratio": LAMBDA,
        "u0": u0,
        "rho": RHO,
        "rho_p": RHO_P,
        "nu": NU,
        "g": G,
        "ranks": ranks,
        "end_time": end,
    }
    nscdpost.write_json(os.path.join(case, "bed.json"), info)
    print(
        f"{case}: {grains} spheres, {nx} x {ny} x {nx} cells (h = {h * 1e3:.3f} mm), "
        f"U_0 = {u0} m/s, {end} s, {ranks} rank(s)"
    )
    return info


if __name__ == "__main__":
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("case")
    ap.add_argument("--across", type=int, default=42)
    ap.add_argument("--grains", type=int, default=100000)
    ap.add_argument("--u0", type=float, default=0.06)
    ap.add_argument("--end", type=float, default=0.5)
    ap.add_argument("--ranks", type=int, default=4, choices=(1, 2, 4, 8))
    ap.add_argument("--dt", type=float, default=1e-3)
    ap.add_argument("--write", type=float, default=0.05)
    a = ap.parse_args()
    setup(a.case, a.across, a.grains, a.u0, a.end, a.ranks, a.dt, a.write)
