# SPDX-License-Identifier: GPL-3.0-or-later
"""Minimum fluidisation of a uniform bed (issue 4: "the bed lifts within 10 %
of the predicted u_mf").

The bed: a column of 8 frictionless spheres (d = 1 mm, rho_p = 2500)
stacked on a porous floor (the inlet patch is a wall for the grains) in a
column of cells s x d x s (s = 1.1 d), one sphere per cell, so the void
fraction is exactly uniform, eps = 1 - pi d^2/(6 s^2) = 0.567, and the
interstitial velocity u = U/eps with U the superficial inflow.  Water flows
up through it.  One cell across with slip side walls: the flow is exactly
one-dimensional (several free-standing frictionless columns side by side
buckle, an unstable equilibrium that has nothing to do with u_mf).

Closed form (model A, steady state, v = 0): the fluid balance
  0 = -eps dp/dy - eps rho g - phi gamma u
and the grains' balance
  0 = -phi dp/dy + phi gamma u - phi rho_p g
give at incipient fluidisation
  gamma(eps, Re_mf) U_mf / eps^2 = (rho_p - rho) g,
with gamma the Dallavalle + Di Felice drag law (Di Felice 1994, published
form, correlations.py), solved by fixed point.  The semi-implicit
drag of eq. 3.46-3.50 is exactly gamma (u - v) at rest (the contact impulse
of the previous step enters v**), so the bed must stay on the floor below
U_mf and lift above it.  Tolerance: the issue's 10 % is tightened to 5 %:
the bed stays put at 0.95 U_mf and lifts at 1.05 U_mf.
"""

import math
import os

import correlations
import nscdpost
import numpy as np
import pytest
from foamcase import add_fluid, inlet_outlet_box, make_box_case, run, tutorial_modules, write

G = 9.81
D, S, LAYERS = 1.0e-3, 1.1e-3, 8
RHOP, RHO, NU = 2500.0, 1000.0, 1e-6
FACTORS = (0.95, 1.05)


def gamma_difelice(eps, Re, d, mu):
    """The coded DallavalleDiFelice law (Di Felice 1994, per unit sphere
    volume, correlations.py): this test checks the force balance and the
    semi-implicit drag at rest (consistency), test_drag.py the law itself."""
    return correlations.gamma_dallavalle_difelice(eps, Re, d, mu)


def u_mf(eps, d):
    """Superficial minimum fluidisation velocity of a uniform bed [m/s]."""
    U = 1e-3
    for _ in range(500):
        Re = U / eps * d / NU
        U = eps**2 * (RHOP - RHO) * G / gamma_difelice(eps, Re, d, RHO * NU)
    return U


def bed_case(case, env, U):
    nx, ny = 1, 2 * LAYERS
    lx, ly = nx * S, ny * D
    dg = D * (1 - 1e-6)
    grains = [
        ((i + 0.5) * S, (j + 0.5) * D, (k + 0.5) * S, dg)
        for j in range(LAYERS)
        for i in range(nx)
        for k in range(nx)
    ]
    make_box_case(
        case,
        (0, 0, 0),
        (lx, ly, lx),
        (nx, ny, nx),
        (0, -G, 0),
        {"glass": {"density": RHOP, "friction": 0.0}},
        grains=grains,
        end_time=0.2,
        dt=1e-3,
        write_interval=0.2,
        two_d=False,
        extra_props="wallPatches (inlet walls);\n",
        contact_tolerance=1e-6,
        max_iterations=2000,
    )
    add_fluid(case, RHO, NU, max_dt=1e-3)
    inlet_outlet_box(case)
    # uniform upward inflow U (superficial: the boundary void fraction is 1),
    # slip side walls (no wall shear: the flow stays uniform), open top
    write(
        os.path.join(case, "0", "U"),
        "volVectorField",
        "U",
        "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
        "boundaryField { inlet { type fixedValue; value uniform (0 %.12g 0); }\n"
        " outlet { type zeroGradient; } walls { type slip; } }\n" % U,
    )
    write(
        os.path.join(case, "0", "p"),
        "volScalarField",
        "p",
        "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
        "boundaryField { inlet { type fixedFluxPressure; value uniform 0; }\n"
        " outlet { type fixedValue; value uniform 0; }\n"
        " walls { type fixedFluxPressure; value uniform 0; } }\n",
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    return dg


@pytest.mark.fast
def test_minimum_fluidisation(tmp_path, env):
    dg = D * (1 - 1e-6)
    eps = 1 - math.pi * dg**3 / (6 * S * S * D)
    Umf = u_mf(eps, dg)
    rise = {}
    for f in FACTORS:
        case = str(tmp_path / f"U{f}")
        bed_case(case, env, f * Umf)
        g0 = nscdpost.read_grains(case, "0")
        run("vansFoam", case, env)
        t, name = nscdpost.time_dirs(case)[-1]
        g = nscdpost.read_grains(case, name)
        dy = g["x"][:, 1] - g0["x"][:, 1]
        rise[f] = (float(np.mean(dy)), float(np.max(dy)))
    print(
        f"eps {eps:.4f}, U_mf {Umf:.6g} m/s (Re_mf {Umf / eps * D / NU:.3g}); "
        f"rise (mean, max) [m]: {rise}"
    )
    # below U_mf the bed rests on the floor: it only closes the 1e-6 d gaps
    # and the contact solver's overlap slop (settings.overlapSlop, 1e-4 d)
    assert abs(rise[0.95][0]) < 1e-3 * D and rise[0.95][1] < 1e-3 * D, rise
    # above U_mf the bed expands: every layer has lifted off
    assert rise[1.05][0] > 0.05 * D, rise


# ---------------------------------------------------------------------------
# Heave of a settled layer under a rising bottom pressure (thesis section
# 3.3.2, eq. 3.53-3.54): a reduced copy of tutorials/vansFoam/fluidisation
# (400 discs, 20 d wide, ramp 4x faster) on meshes h/d = 1 and 4.
#
# Reference (force balance): the whole bed cannot lift before the pressure
# force across it balances its buoyant weight, i.e. the differential head
# at total heave is at least dh_w = sum V_p (rho_p - rho) / (rho W).  Side-
# wall friction (mu = 0.4) and arching add to it: the full tutorial measures
# 1.22 dh_w at h/d = 0.5, the thesis' 2D runs 0.22 m against 0.19 m in the
# experiment (+16 %).  Asserted: 0.95 dh_w <= heave head <= 1.5 dh_w (0.95:
# probe interpolation on the initial top of the layer), first movement no
# later than total heave, and the heave head of h/d = 1 and 4 within 10 %,
# the heave time within 5 % (the thesis finds "no significant difference"
# from h/d = 0.5 to 8).  Measured when written: heave at 0.2298 / 0.2294 s,
# heave head 7.09 / 7.36 mm = 1.26 / 1.31 dh_w for h/d = 1 / 4.
# ---------------------------------------------------------------------------
@pytest.mark.slow
def test_heave_under_rising_pressure(tmp_path, env):
    """The reduced tutorial at its own maxDeltaT (1e-3 s) on h/d = 1 and 4,
    and on h/d = 1 at 1e-4 s. References: the force balance (the bed cannot
    lift before the head carries its buoyant weight dh_w), mesh independence
    (thesis section 3.3.2), and time-step convergence: issue 26 asks for a
    heave head at 1e-3 s within 5 % of the 1e-4 s run (the drag implicit in
    the contact solve; with the drag from last step's contact impulse 1e-3 s
    lifted the bed at a quarter of dh_w)."""
    setup, post = tutorial_modules("vansFoam", "fluidisation")
    box = {"width": 20 * setup.D_MEAN, "height": 40 * setup.D_MEAN}
    assert setup.MAX_DELTA_T == 1e-3
    root = str(tmp_path)
    setup.deposit(root, n_grains=400, **box)
    dep = os.path.join(root, "deposit")
    run("blockMesh", dep, env)
    run("grainDeposit", dep, env)
    res = {}
    for hd, dt in ((1, 1e-3), (4, 1e-3), (1, 1e-4)):
        case = os.path.join(root, f"hd{hd}_dt{dt:g}")
        setup.setup(case, hd, "0.32", root, max_delta_t=dt, ramp_time=0.25, **box)
        run("blockMesh", case, env)
        run("vansFoam", case, env)
        res[hd, dt] = post.measure(case)
    msg = "; ".join(
        f"h/d {hd}, dt {dt:g}: first movement {r['first_movement_time']} s, heave {r['heave_time']} s, "
        f"heave head {r['heave_head']} m, buoyant weight head {r['buoyant_weight_head']:.5g} m"
        for (hd, dt), r in res.items()
    )
    print(msg)
    for r in res.values():
        assert r["heave_time"] is not None, msg
        assert (
            0.95 * r["buoyant_weight_head"] <= r["heave_head"] <= 1.5 * r["buoyant_weight_head"]
        ), msg
        assert r["first_movement_time"] <= r["heave_time"], msg
    assert res[1, 1e-3]["heave_head"] == pytest.approx(res[4, 1e-3]["heave_head"], rel=0.10), msg
    assert res[1, 1e-3]["heave_time"] == pytest.approx(res[4, 1e-3]["heave_time"], rel=0.05), msg
    assert res[1, 1e-3]["heave_head"] == pytest.approx(res[1, 1e-4]["heave_head"], rel=0.05), msg
    assert res[1, 1e-3]["heave_time"] == pytest.approx(res[1, 1e-4]["heave_time"], rel=0.05), msg
