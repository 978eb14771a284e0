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
with gamma the Dallavalle + Di Felice drag law (thesis eq. 3.32 with the
eq. 4.10 exponent, Di Felice 1994), solved by fixed point.  The semi-implicit
drag of eq. 3.46-3.50 is exactly gamma (u - v) at rest (the contact impulse
of the previous step enters v**), so the bed must stay on the floor below
U_mf and lift above it.  Tolerance: the issue's 10 % is tightened to 5 %:
the bed stays put at 0.95 U_mf and lifts at 1.05 U_mf.
"""
import math
import os
import re
import shutil

import numpy as np

import nscdpost
from foamcase import add_fluid, make_box_case, run, write

G = 9.81
D, S, LAYERS = 1.0e-3, 1.1e-3, 8
RHOP, RHO, NU = 2500.0, 1000.0, 1e-6
FACTORS = (0.95, 1.05)


def gamma_difelice(eps, Re, d, mu):
    """Dallavalle (1948) + Di Felice (1994), per unit grain volume, Re built
    with the interstitial slip (as src/vansCoupling/dragModels)."""
    epsRe = eps * Re
    l = 1.5 - math.log10(max(epsRe, 1e-12))
    return eps ** -(2.8 - math.exp(-0.5 * l * l)) * (0.77 * math.sqrt(epsRe) + 5.88) ** 2 * mu / d**2


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
    grains = [((i + 0.5) * S, (j + 0.5) * D, (k + 0.5) * S, dg)
              for j in range(LAYERS) for i in range(nx) for k in range(nx)]
    make_box_case(case, (0, 0, 0), (lx, ly, lx), (nx, ny, nx), (0, -G, 0),
                  {"glass": {"density": RHOP, "friction": 0.0}}, grains=grains,
                  end_time=0.2, dt=1e-3, write_interval=0.2, two_d=False,
                  extra_props="wallPatches (inlet walls);\n",
                  contact_tolerance=1e-6, max_iterations=2000)
    bm = os.path.join(case, "system", "blockMeshDict")
    txt = re.sub(r"boundary \(.*\);", "boundary (\n"
                 "inlet { type patch; faces ((1 5 4 0)); }\n"
                 "outlet { type patch; faces ((3 7 6 2)); }\n"
                 "walls { type wall; faces ((0 4 7 3) (2 6 5 1) (0 3 2 1) (4 5 6 7)); }\n);",
                 open(bm).read(), flags=re.S)
    with open(bm, "w") as f:
        f.write(txt)
    add_fluid(case, RHO, NU, max_dt=1e-3)
    fs = os.path.join(case, "system", "fvSolution")
    txt = open(fs).read().replace("pRefCell 0; pRefValue 0;", "")
    with open(fs, "w") as f:
        f.write(txt)
    # uniform upward inflow U (superficial: the boundary void fraction is 1),
    # slip side walls (no wall shear: the flow stays uniform), open top
    write(os.path.join(case, "0", "U"), "volVectorField", "U",
          "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
          "boundaryField { inlet { type fixedValue; value uniform (0 %.12g 0); }\n"
          " outlet { type zeroGradient; } walls { type slip; } }\n" % U)
    write(os.path.join(case, "0", "p"), "volScalarField", "p",
          "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
          "boundaryField { inlet { type fixedFluxPressure; value uniform 0; }\n"
          " outlet { type fixedValue; value uniform 0; }\n"
          " walls { type fixedFluxPressure; value uniform 0; } }\n")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    return dg


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
    print(f"eps {eps:.4f}, U_mf {Umf:.6g} m/s (Re_mf {Umf / eps * D / NU:.3g}); "
          f"rise (mean, max) [m]: {rise}")
    # below U_mf the bed rests on the floor: it only closes the 1e-6 d gaps
    # and the contact solver's overlap slop (settings.overlapSlop, 1e-4 d)
    assert abs(rise[0.95][0]) < 1e-3 * D and rise[0.95][1] < 1e-3 * D, rise
    # above U_mf the bed expands: every layer has lifted off
    assert rise[1.05][0] > 0.05 * D, rise
