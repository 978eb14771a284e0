# SPDX-License-Identifier: GPL-3.0-or-later
"""Immersed vaporising droplet (thesis section 4.3.1, eq. 4.15-4.17): src/dropletCoupling, fvOption vapourDropletSource in vansFoam.

(a) Droplet held fixed in a hot stagnant gas, no grains, blowing off: steady
    conduction from a cylinder of diameter D at T_d centred in a square box of
    side w with walls at T_w.  Reference: Incropera & DeWitt, Fundamentals of
    Heat and Mass Transfer, Table 4.1 (conduction shape factors), case "circular
    cylinder of length L centered in a square solid of equal length", per unit
    depth  Q = k (T_w - T_d) S,  S = 2 pi / ln(1.08 w/D)  (w > D).
    The droplet mass rate must be mdot = Q/L (eq. 4.16, Q_p = 0) within 5 %
    (issue 8).  w/D = 4.  Measured mesh convergence (cells per diameter D/dx,
    2D, implicit Euler to steady state; error of Q against the shape factor):
    see MESH_CONVERGENCE below (-1 % at 8, -0.14 % at 16 cells per D); the
    test runs D/dx = 16 (5 % as the issue asks, plus 1 % to catch a drift of
    the method).
    The radius is held constant by a large (fictitious) liquid density, so
    that the geometry of the reference does not change during the run.
(b) Budgets, blowing on, walls at T_w, outlet (p = 0) on top, 20 steps:
    - energy (conservation law): rho Cp sum(eps T V) changes by the wall and
      outlet heat + the vapour enthalpy source rho Cp T_d Vdot - Q_f per step,
      and the droplet takes L (m_0 - m_N) = sum Q_f dt; the balance
      Delta E_fluid + L (m_0 - m_N) = wall + outlet heat + vapour enthalpy
      closes to 1e-6 relative to the heat taken by the droplet;
    - Q_f logged by the droplet = minus the fvOptions source heat of the
      solver's own heat budget (heatBudget.H) without the vapour enthalpy,
      to 1e-8 relative (two independent integrations of the same sink);
    - vapour mass: rho_v sum Vdot dt (released, one step lagged) = mass lost,
      round-off; the mixture continuity div(eps U) = q holds cell by cell
      (vansFoam's continuity error, q subtracted, < 1e-6 of Vdot; pressure
      solver tolerance 1e-12 absolute) and the outflow through the outlet
      (phi at the end) = Vdot of the last step to 1e-6 relative.
"""

import math
import os
import re

import nscdpost
import numpy as np
import pytest
from dropletcase import (
    CP,
    DEPTH,
    KAPPA,
    LATENT,
    RHO,
    RHO_V,
    T_D,
    T_W,
    D,
    W,
    blowing_droplet_case,
    droplet_case,
    read_droplet,
    water_droplet_case,
)
from foamcase import run

# Measured (w/D = 4, steady state): D/dx -> mdot/(Q_ref/L) - 1, for the
# default penalisationFactor 100 (src/dropletCoupling/README.md has 10 and 1e4).
# The +0.15 % left at 48-64 cells is of the order of the accuracy of the
# 1.08 fit of the shape factor.
MESH_CONVERGENCE = {
    4: -0.054,
    6: -0.023,
    8: -0.0099,
    12: -0.0012,
    16: -0.0014,
    24: -0.0004,
    32: 0.0023,
    48: 0.0015,
    64: 0.0015,
}


def patch_sum(path, patch):
    """Sum of the values of a surfaceScalarField (e.g. phi [m^3/s]) over a
    patch, from an ascii field file."""
    txt = open(path).read()
    block = re.search(patch + r"\s*\{(.*?)\}", txt[txt.index("boundaryField") :], re.S).group(1)
    m = re.search(r"value\s+uniform\s+(\S+);", block)
    if m:
        raise AssertionError(f"uniform {m.group(1)} on {patch}: expected a flux profile")
    m = re.search(r"value\s+nonuniform\s+List<scalar>\s*(\d+)\s*\((.*?)\)", block, re.S)
    vals = np.array(m.group(2).split(), dtype=float)
    assert len(vals) == int(m.group(1))
    return float(vals.sum())


def shape_factor_Q(k, dT, w, d):
    """Incropera & DeWitt Table 4.1: Q per unit depth of a cylinder in a square."""
    return k * dT * 2 * math.pi / math.log(1.08 * w / d)


def conduction_error(tmp_path, env, n_per_d):
    case = str(tmp_path / f"cond{n_per_d}")
    # thermal time w^2/alpha = 2 s; 10 implicit steps of 1 s reach steady state
    droplet_case(case, env, n_per_d, end_time=10.0, dt=1.0, blowing=False, rho_l=1e8)
    run("vansFoam", case, env)
    d = read_droplet(case)
    mdot = d[-1, 6] / DEPTH
    ref = shape_factor_Q(KAPPA, T_W - T_D, W, D) / LATENT
    # steady: the last two steps agree
    assert abs(d[-1, 6] - d[-2, 6]) < 1e-6 * abs(d[-1, 6])
    return mdot / ref - 1


@pytest.mark.fast
def test_fixed_droplet_conduction(tmp_path, env):
    err = conduction_error(tmp_path, env, 16)
    print(f"D/dx = 16: mdot/(Q_ref/L) - 1 = {err:.4f}")
    assert abs(err) < 0.05  # issue 8
    assert abs(err) < 0.01  # the measured accuracy at 16 cells per D (-0.14 %)


@pytest.mark.fast
@pytest.mark.skipif(not os.environ.get("NSCD_SLOW"), reason="mesh convergence study: NSCD_SLOW=1")
def test_fixed_droplet_mesh_convergence(tmp_path, env):
    errs = {n: conduction_error(tmp_path, env, n) for n in (8, 16, 32)}
    print("mesh convergence D/dx: error", errs)
    assert abs(errs[32]) < abs(errs[8])


def budget_lines(case):
    """Per step: (fluid boundary, advected, sources) [J] of vansFoam's heat
    budget, energy E [J] (heatBudget.dat), global continuity error of the
    step's last pressure corrector (continuityErrors.dat)."""
    h = nscdpost.heat_history(case)
    cont = nscdpost.read_step_data(case, "continuityErrors")["global"]
    return h["budget"][:, :3], h["E"], cont


@pytest.mark.fast
@pytest.mark.parametrize("release", ["uniform", "heatFlux"])
def test_energy_and_vapour_budget(tmp_path, env, release):
    """Budgets (b) of the module docstring, for both vapourRelease modes
    (where the vapour leaves the surface must not change any budget)."""
    case = str(tmp_path / "budget")
    dt, n_steps = 0.01, 20
    blowing_droplet_case(case, env, 8, dt, n_steps, extra=f"vapourRelease {release};\n")
    run("vansFoam", case, env)
    d = read_droplet(case)
    bud, E, cont = budget_lines(case)
    n = len(d)  # >= n_steps: the Courant limit may shorten dt
    assert n >= n_steps and len(bud) == n and len(E) == n
    t = d[:, 0]
    dts = np.diff(np.concatenate(([0.0], t)))
    m0 = 1000.0 * math.pi * (D / 2) ** 2 * DEPTH
    m, Qf, Vdot = d[:, 5], d[:, 7] + d[:, 8], d[:, 11]  # Q = Q_f + Q_p (Q_p = 0: no grains)
    assert np.all(d[:, 8] == 0)
    rhoCp = RHO * CP
    E0 = rhoCp * T_W * W * W * DEPTH

    # Q_f (droplet) against the solver's own source integral minus the vapour enthalpy
    src_droplet = bud[:, 2] - rhoCp * T_D * Vdot * dts
    assert np.allclose(-src_droplet, Qf * dts, rtol=1e-8, atol=0)

    # mass: L (m0 - m) = sum Q_f dt (eq. 4.16)
    lost = m0 - m[-1]
    heat = np.sum(Qf * dts)
    assert lost > 0
    assert abs(LATENT * lost - heat) < 1e-10 * heat

    # energy: fluid energy change + heat taken by the droplet (L x mass lost)
    # = heat in through walls and outlet + enthalpy of the released vapour
    ext = np.sum(bud[:, 0] + bud[:, 1] + rhoCp * T_D * Vdot * dts)
    defect = (E[-1] - E0) + LATENT * (m0 - m[-1]) - ext
    print(f"heat to droplet {heat:.6e} J, energy defect {defect:.3e} J")
    assert abs(defect) < 1e-6 * heat

    # vapour released (one step lagged) = mass lost
    released = RHO_V * np.sum(Vdot * dts)
    assert Vdot[0] == 0
    assert abs(released - (m0 - m[-2])) < 1e-10 * released

    # mixture continuity with the source: div(eps U) + div(phi v*) = q cell by
    # cell, so vansFoam's continuity error (which subtracts q) stays at the
    # pressure solver tolerance, and the outflow through the outlet at the
    # end equals the volume source of the last step
    Vtot = W * W * DEPTH
    err = np.abs(cont) * Vtot / dts  # last corrector [m^3/s]
    assert np.all(err < 1e-6 * Vdot[1:].min())
    outflow = patch_sum(os.path.join(case, f"{dt * n_steps:g}", "phi"), "outlet")
    print(f"outflow {outflow:.9e} m^3/s, Vdot {Vdot[-1]:.9e} m^3/s")
    assert abs(outflow - Vdot[-1]) < 1e-6 * Vdot[-1]


@pytest.mark.fast
def test_bounded_vapour_fraction_with_blowing_droplet(tmp_path, env):
    """vapour { bounded yes; } (advective form of eq. 4.19, psiEqn.H) must
    keep the vapour fraction in [0, 1] next to a blowing droplet, whose
    vapour volume source q [1/s] (ring cells just outside the droplet) is
    part of the mixture continuity: d(eps)/dt + div(phi) = q there.  The
    advective form subtracts psi times the continuity DEFECT only,
    psi (d(eps)/dt + div(phi) - q), so that the injected vapour enters as
    q (1 - psi) (reference: the continuous equations; psi = 1 is the
    injected vapour, thesis 4.3.2 table).  Subtracting psi (d(eps)/dt +
    div(phi)) instead left eps dpsi/dt = q in the source cells: psi grew
    by q dt/eps per step (measured max psi 1.055 in this case; 2.4-3.7 in
    the dropletDigging tutorial runs).  Asserted at every step (log):
    min psi >= -1e-9, max psi <= 1 + 1e-6, and psi reaches > 0.5 (the
    vapour is there)."""
    case = str(tmp_path / "bounded")
    dt, n_steps = 0.01, 20
    blowing_droplet_case(case, env, 8, dt, n_steps)
    tp = os.path.join(case, "constant", "transportProperties")
    txt = open(tp).read()
    assert "vapour { D 2.5e-5;" in txt
    open(tp, "w").write(txt.replace("vapour { D 2.5e-5;", "vapour { bounded yes; D 2.5e-5;"))
    run("vansFoam", case, env)
    v = nscdpost.read_step_data(case, "vapour")
    rng = np.column_stack([v["psiMin"], v["psiMax"]])
    assert len(rng) >= n_steps
    print(
        f"bounded psi: min {rng[:, 0].min():.3e}, max {rng[:, 1].max():.6f} over {len(rng)} steps"
    )
    assert rng[:, 0].min() >= -1e-9
    assert rng[:, 1].max() <= 1 + 1e-6
    assert rng[:, 1].max() > 0.5


def sector_shares(values, xy, centre, edges):
    """Shares of sum(values) in the angular sectors [edges[k], edges[k+1])
    [rad] of the directions xy - centre (values >= 0 per cell, already x V)."""
    ang = np.arctan2(xy[:, 1] - centre[1], xy[:, 0] - centre[0])
    ang = np.where(ang < edges[0], ang + 2 * np.pi, ang)
    k = np.digitize(ang, edges) - 1
    tot = values.sum()
    return np.array([values[k == i].sum() / tot for i in range(len(edges) - 1)])


@pytest.mark.fast
@pytest.mark.parametrize("release", ["uniform", "heatFlux"])
def test_vapour_released_where_heat_enters(tmp_path, env, release):
    """vapourRelease heatFlux (vapourDroplet.H, "Blowing"): the vapour of
    each angular sector of the surface is the heat the droplet took there
    over L rho_v (local mass balance of the phase change, eq. 4.16 per
    surface element), to the width of the projection cone.  Held droplet,
    blowing, 16 cells per D, its centre 0.7 D above the bottom wall
    (walls at T_w, open top): the hot wall below makes the heat enter
    mostly through the lower half.  Asserted at the last step (fields
    dropletVolumeSource q [1/s] and dropletHeatSink [W/m^3] written every
    step; q of step n is released from the sink of step n-1):
    - sum q V = Vdot of droplet.dat (vapour volume, 1e-9 relative);
    - heatFlux: the vapour share of each of 4 quadrants (lower, right,
      upper, left) equals the heat share of step n-1 within 0.03 (the cone
      of half-angle 2 h/R = 14 deg smears across the quadrant borders);
    - uniform (the thesis' blowing): the lower-quadrant vapour share is
      the ring's, 0.25 within 0.02, while the heat share is > 0.4: the
      configuration discriminates the two modes."""
    n_per_d, dt, n_steps = 16, 0.005, 12
    case = str(tmp_path / release)
    w = 4 * D
    centre = (w / 2, 0.7 * D)
    blowing_droplet_case(
        case,
        env,
        n_per_d,
        dt,
        n_steps,
        rho_l=1e6,
        centre=centre,
        write_interval=dt,
        extra=f"vapourRelease {release};\n",
    )
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace("adjustTimeStep yes;", "adjustTimeStep no;")
    open(cd, "w").write(txt)
    run("vansFoam", case, env)
    d = read_droplet(case)
    assert len(d) == n_steps
    times = [name for t, name in nscdpost.numeric_dirs(case) if t > 0]
    last, prev = times[-1], times[-2]
    n = 4 * n_per_d
    h = w / n
    xs = (np.arange(n) + 0.5) * h
    xy = np.stack([np.tile(xs, n), np.repeat(xs, n)], axis=1)  # blockMesh order
    vol = h * h * DEPTH
    q = nscdpost.read_internal_field(os.path.join(case, last, "dropletVolumeSource"))
    sink = nscdpost.read_internal_field(os.path.join(case, prev, "dropletHeatSink"))
    assert q.shape == (n * n,) and sink.shape == (n * n,)
    Vdot = d[-1, 11]
    assert Vdot > 0
    assert abs(q.sum() * vol - Vdot) < 1e-9 * Vdot
    assert q.min() >= 0
    edges = np.array([-0.75, -0.25, 0.25, 0.75, 1.25]) * np.pi  # lower, right, upper, left
    s_vap = sector_shares(q * vol, xy, centre, edges)
    s_heat = sector_shares(np.maximum(sink, 0) * vol, xy, centre, edges)
    print(f"{release}: vapour shares {np.round(s_vap, 4)}, heat shares {np.round(s_heat, 4)}")
    assert s_heat[0] > 0.4
    if release == "heatFlux":
        assert np.all(np.abs(s_vap - s_heat) < 0.03)
    else:
        assert abs(s_vap[0] - 0.25) < 0.02


@pytest.mark.fast
def test_grain_heat_to_droplet(tmp_path, env):
    """Q_p (eq. 4.16): two hot fixed grains (r = 0.3 R, T_p0 = T_d + 200 K)
    wholly inside the droplet, gas and walls at T_d.  The grains give their
    heat to the penalised fluid at T_d (vansCloud, thesis eq. 4.13) and the
    droplet takes it: conservation law, the grains' heat loss
    2 m_g c (T_p0 - T_p(t)) = sum Q_p dt = L x (mass lost) to 1e-6 relative
    (Q_f, the gas part, ~0: < 1 % of Q_p), and the grains cool."""
    R0 = D / 2
    c = 2 * D
    r = 0.3 * R0
    grains = [(c + 0.3 * R0, c, DEPTH / 2, 2 * r), (c - 0.3 * R0, c, DEPTH / 2, 2 * r)]
    case = str(tmp_path / "hotgrains")
    T0 = T_D + 200
    dt, n_steps = 0.01, 10
    water_droplet_case(
        case, env, dt, n_steps, rho_l=1000.0, grains=grains, fixed_grains=True, T_grains=T0
    )
    run("vansFoam", case, env)
    d = read_droplet(case)
    Tg = nscdpost.heat_history(case)["grain_T"]
    assert len(d) == n_steps and len(Tg) == n_steps
    Qf, Qp = d[:, 7], d[:, 8]
    mg = 2500 * math.pi * r * r * DEPTH  # 2D disc x mesh depth
    grain_loss = 2 * mg * 800 * (T0 - Tg[-1])
    heat_p = np.sum(Qp * dt)
    m0 = 1000.0 * math.pi * R0**2 * DEPTH
    print(
        f"grain heat loss {grain_loss:.6e} J, sum Q_p dt {heat_p:.6e} J, sum Q_f dt "
        f"{np.sum(Qf * dt):.3e} J, T_p {Tg[-1]:.3f} K"
    )
    assert Tg[-1] < T0 - 1
    assert abs(heat_p - grain_loss) < 1e-6 * grain_loss
    assert abs(np.sum(Qf * dt)) < 0.01 * heat_p
    assert abs(LATENT * (m0 - d[-1, 5]) - np.sum((Qf + Qp) * dt)) < 1e-10 * heat_p


def film_reference(r, F, dT, mu_v=1.227e-5, k=KAPPA, rho_v=RHO_V, L=LATENT):
    """Leidenfrost film under a 2D grain of radius r [m] pressed on the
    droplet by F [N/m] at superheat dT [K]: lubrication of the vapour
    squeezed out of the gap e(x) = delta + x^2/(2 r) (Poiseuille, mass
    flux k dT/(L e) per unit area; vapourDroplet.H), evaluated here
    independently: I by quadrature, delta = [24 I mu_v k dT (2r)^1.5 /
    (rho_v L F)]^0.4, heat per unit depth pi k dT sqrt(2 r/delta).
    Returns (delta [m], G = heat/dT [W/(m K)])."""
    s = np.linspace(0.0, 400.0, 800001)
    f = s * np.arctan(s) / (1 + s * s) ** 3
    I = float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(s)))
    assert abs(I - 0.147262) < 1e-5  # the constant of vapourDroplet.C
    delta = (24 * I * mu_v * k * dT * (2 * r) ** 1.5 / (rho_v * L * F)) ** 0.4
    return delta, math.pi * k * math.sqrt(2 * r / delta)


@pytest.mark.fast
def test_leidenfrost_film_heat(tmp_path, env):
    """filmConduction yes (vapourDroplet.H, "Leidenfrost film conduction"):
    a hot grain (r = 0.1 mm, T_d + 300 K, glass 2500 kg/m^3, c = 800
    J/(kg K)) resting by its weight on top of a held droplet (capillary
    barrier 0.05891 N/m), gas and walls at T_d, blowing off, 20 steps of
    1 ms.  Asserted:
    - the film heat of each step (droplet.dat Q_film, applied with the
      grain temperature and contact force of the step before) equals the
      lubrication film's G* dT l, G* = G C/(C + dt G), G from
      `film_reference` with F = the grain's apparent weight m g (1 -
      rho_f/rho_s) and dT from the logged grain temperature, within 1e-3
      (the gas drag on the resting grain is not in F; Q ~ F^0.2);
    - conservation: the grains + gas energy E of the log changes by the
      logged budget minus the film heat, (E_N - E_1) - sum_{2..N}(budget
      - Q_film dt) = 0 to 1e-8 of the film heat, and L x (mass lost) =
      sum (Q_f + Q_p + Q_film) dt (eq. 4.16) to 1e-10;
    - the first step has no film heat (nothing was pressed yet), and the
      grain cools;
    - restart from the write time 10 ms (the pending film heat is in
      <time>/uniform/droplet) reproduces the uninterrupted droplet.dat to
      1e-9 relative."""
    import shutil

    R0 = D / 2
    c = 2 * D
    r = 1e-4
    rho_s, cp_s = 2500.0, 800.0
    case = str(tmp_path / "film")
    T0 = T_D + 300
    dt, n_steps = 1e-3, 20
    water_droplet_case(
        case,
        env,
        dt,
        n_steps,
        rho_l=1000.0,
        grains=[(c, c + R0 + r, DEPTH / 2, 2 * r)],
        T_grains=T0,
        gravity=9.81,
        write_interval=10 * dt,
        extra="surfaceTension 0.05891;\nfilmConduction yes;\n",
    )
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace("adjustTimeStep yes;", "adjustTimeStep no;")
    open(cd, "w").write(txt)
    run("vansFoam", case, env)
    d = read_droplet(case)
    h = nscdpost.heat_history(case)
    Tg = h["grain_T"]
    assert len(d) == n_steps and len(Tg) == n_steps and d.shape[1] == 28
    Qfilm = d[:, 24]
    assert Qfilm[0] == 0
    assert np.all(Qfilm[1:] > 0)
    m_g = rho_s * math.pi * r * r  # kg/m (2D)
    F = m_g * 9.81 * (1 - RHO / rho_s)
    C = m_g * cp_s
    ratios = []
    for k in range(2, n_steps):
        dT = Tg[k - 1] - T_D
        delta, G = film_reference(r, F, dT)
        Gs = G * C / (C + dt * G)
        ratios.append(Qfilm[k] / (Gs * dT * DEPTH))
    ratios = np.array(ratios)
    delta0, G0 = film_reference(r, F, T0 - T_D)
    print(
        f"film: delta {delta0 * 1e6:.3f} um, Q_film {Qfilm[2]:.4e} W, ratio to the "
        f"lubrication film {ratios.min():.6f}..{ratios.max():.6f}, grain T {Tg[-1]:.2f} K"
    )
    assert np.all(np.abs(ratios - 1) < 1e-3)
    assert Tg[-1] < T0 - 1

    # conservation: the film heat leaves the grain once and enters the droplet once
    E, bud = h["E"], h["budget"]
    film_heat = np.sum(Qfilm[1:] * dt)
    defect = (E[-1] - E[0]) - np.sum(bud[1:].sum(axis=1) - Qfilm[1:] * dt)
    print(f"film heat {film_heat:.6e} J, energy defect {defect:.3e} J")
    assert abs(defect) < 1e-8 * film_heat
    m0 = 1000.0 * math.pi * R0**2 * DEPTH
    heat = np.sum((d[:, 7] + d[:, 8] + Qfilm) * dt)
    assert abs(LATENT * (m0 - d[-1, 5]) - heat) < 1e-10 * heat

    half = str(tmp_path / "half")
    shutil.copytree(case, half)
    shutil.rmtree(os.path.join(half, f"{n_steps * dt:g}"))
    shutil.rmtree(os.path.join(half, "postProcessing"))
    assert "filmHeat" in open(os.path.join(half, f"{10 * dt:g}", "uniform", "droplet")).read()
    run("vansFoam", half, env)
    rest = np.loadtxt(
        os.path.join(half, "postProcessing", "droplet", f"{10 * dt:g}", "droplet.dat"), ndmin=2
    )
    assert len(rest) == n_steps - 10
    assert np.allclose(rest, d[10:], rtol=1e-9, atol=1e-15)


@pytest.mark.slow
def test_tutorial_skeleton_runs(tmp_path, env):
    """tutorials/vansFoam/dropletDigging (skeleton, Table 4.2) with its own
    setupCase.py on its reduced bed (1 mm grains, 10 steps): the droplet
    vaporises from the start, and its instant lifetime m/mdot is of the order
    of ten seconds as in the thesis at the start of the fall (Figure 4.17:
    ~10 s; accepted 2-60 s, an order-of-magnitude check of eq. 4.16 with
    Table 4.2 properties at T_bed = 400 C)."""
    from foamcase import tutorial_modules

    (setup,) = tutorial_modules("vansFoam", "dropletDigging", names=("setupCase",))
    root = str(tmp_path)
    setup.deposit(1e-3, root=root)
    dep = os.path.join(root, "deposit")
    run("blockMesh", dep, env)
    run("grainDeposit", dep, env)
    case = os.path.join(root, "T400")
    setup.setup(case, 400.0, 10 * setup.DT, root=root)
    run("blockMesh", case, env)
    run("vansFoam", case, env)
    d = read_droplet(case)
    assert len(d) >= 10
    m, mdot = d[-1, 5], d[-1, 6]
    assert mdot > 0 and m < d[0, 5]
    lifetime = m / mdot
    print(f"instant lifetime m/mdot = {lifetime:.3g} s, Q_f {d[-1, 7]:.3g} W, Q_p {d[-1, 8]:.3g} W")
    assert 2 < lifetime < 60
