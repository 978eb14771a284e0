# SPDX-License-Identifier: GPL-3.0-or-later
"""Immersed vaporising droplet, liquidConductivity (src/dropletCoupling/
README.md "The model", Heat and mass): the grains inside the droplet
exchange heat with the liquid with the conductance H k_l/kappa instead of
vansCloud's gas exchange H.  A hot grain held inside a held droplet (gas
and walls at T_d, no blowing), with and without the keyword.  Case set-up
in dropletcase.py."""

import math
import os

import nscdpost
import numpy as np
import pytest
from dropletcase import DEPTH, KAPPA, LATENT, T_D, D, read_droplet, water_droplet_case
from foamcase import run

pytestmark = pytest.mark.fast

DT, N_STEPS = 1e-3, 12
R_GRAIN, RHO_S, C_S = 1e-4, 2500.0, 800.0  # glass of dropletcase
FACTOR = 10.0


def grain_in_droplet(case, env, extra):
    """A grain (r = 0.1 mm, T_d + 300 K, free, no gravity) at the centre
    of a held water droplet of 1000 kg/m^3 (8 cells per D: the grain's
    cells lie wholly inside, chi = 1)."""
    c = 2 * D
    water_droplet_case(
        case,
        env,
        DT,
        N_STEPS,
        rho_l=1000.0,
        grains=[(c, c, DEPTH / 2, 2 * R_GRAIN)],
        T_grains=T_D + 300,
        write_interval=N_STEPS * DT,
        extra=extra,
    )
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace("adjustTimeStep yes;", "adjustTimeStep no;")
    open(cd, "w").write(txt)
    run("vansFoam", case, env)
    return read_droplet(case), nscdpost.heat_history(case)["grain_T"]


def test_liquid_conductivity_scales_the_grains_heat(tmp_path, env):
    """Reference: backward Euler of the grain's C dT/dt = -G (T - T_d) in
    liquid at T_d, whose decay per step r = C/(C + dt G) gives 1/r - 1 =
    dt G/C.  Without the keyword G = H (vansCloud's exchange) and droplet.dat
    Q_film = 0; with liquidConductivity = 10 kappa, G = 10 H: (1/r - 1) is
    10 times that of the run without, step by step, within 1 % (the
    penalised liquid is at T_d to ~1e-3 of the superheat).  Conservation:
    the grain's heat loss of each step, C (T^n - T^{n+1}), equals what the
    droplet took from it, Q_p + Q_film (its exchange with the penalised
    cells plus the liquid heat), to 1e-6, and L x (mass lost) = sum (Q_f +
    Q_p + Q_film) dt (eq. 4.16) to 1e-10."""
    d0, T0 = grain_in_droplet(str(tmp_path / "gas"), env, "")
    d1, T1 = grain_in_droplet(
        str(tmp_path / "liquid"), env, f"liquidConductivity {FACTOR * KAPPA};\n"
    )
    assert len(d0) == len(d1) == len(T0) == len(T1) == N_STEPS
    assert np.all(d0[:, 24] == 0)
    assert np.all(d1[:, 24] > 0)
    g0 = (T0[:-1] - T_D) / (T0[1:] - T_D) - 1
    g1 = (T1[:-1] - T_D) / (T1[1:] - T_D) - 1
    ratio = g1 / g0
    print(f"dt G/C without {g0[:3]}, with {g1[:3]}; ratio {ratio.min():.5f}..{ratio.max():.5f}")
    assert np.all(np.abs(ratio / FACTOR - 1) < 1e-2)
    assert T1[-1] < T0[-1] - 50

    C = RHO_S * math.pi * R_GRAIN**2 * DEPTH * C_S
    loss = C * (T1[:-1] - T1[1:]) / DT
    took = d1[1:, 8] + d1[1:, 24]
    print(f"grain loss {loss[:3]} W, droplet Q_p + Q_film {took[:3]} W")
    assert np.allclose(loss, took, rtol=1e-6, atol=0)
    m0 = 1000.0 * math.pi * (D / 2) ** 2 * DEPTH
    heat = np.sum((d1[:, 7] + d1[:, 8] + d1[:, 24]) * DT)
    assert abs(LATENT * (m0 - d1[-1, 5]) - heat) < 1e-10 * heat
