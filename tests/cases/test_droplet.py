"""Immersed vaporising droplet (issue 8, first increment; thesis section 4.3.1,
eq. 4.15-4.17): src/dropletCoupling, fvOption vapourDropletSource in vansFoam.

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

import numpy as np
import pytest

import correlations
import nscdpost

from foamcase import add_fluid, make_box_case, run, write, add_scalar_transport

# Measured (w/D = 4, steady state): D/dx -> mdot/(Q_ref/L) - 1, for the
# default penalisationFactor 100 (src/dropletCoupling/README.md has 10 and 1e4).
# The +0.15 % left at 48-64 cells is of the order of the accuracy of the
# 1.08 fit of the shape factor.
MESH_CONVERGENCE = {4: -0.054, 6: -0.023, 8: -0.0099, 12: -0.0012, 16: -0.0014,
                    24: -0.0004, 32: 0.0023, 48: 0.0015, 64: 0.0015}

D = 2.5e-3
W = 4 * D
DEPTH = 1e-4
RHO, NU, CP, KAPPA = 1.0, 2e-5, 1000.0, 0.05
T_W, T_D = 773.15, 373.15
LATENT = 2.26e6
RHO_V = 0.6


def droplet_case(case, env, n_per_d, end_time, dt, blowing, rho_l, outlet=False,
                 extra="", w_over_d=4, gravity=0.0, nu=NU, T_w=None, grains=(), T_grains=None,
                 fixed_grains=True, write_interval=None, coupling="", rho_f=RHO, moving=False,
                 centre=None):
    """2D square box w x w (w = w_over_d D, n_per_d * w_over_d cells a side),
    walls at T_w (default T_W), droplet of diameter D at the centre; with
    outlet the top side is an open patch (p = 0, zeroGradient U, inletOutlet
    T and psi)."""
    w = w_over_d * D
    n = w_over_d * n_per_d
    T_w = T_W if T_w is None else T_w
    make_box_case(case, (0, 0, 0), (w, w, DEPTH), (n, n, 1), (0, -gravity, 0),
                  {"glass": {"density": 2500, "friction": 0.4}}, grains=list(grains),
                  end_time=end_time, dt=dt,
                  write_interval=end_time if write_interval is None else write_interval)
    if grains and fixed_grains:
        open(os.path.join(case, "system", "grainDepositDict"), "a").write("fixed yes;\n")
    if grains:
        gp = os.path.join(case, "constant", "grainProperties")
        txt = open(gp).read().replace("glass { density 2500; friction 0.4; }",
                                      "glass { density 2500; friction 0.4; conductivity 1;"
                                      " heatCapacity 800; }")
        open(gp, "w").write(txt + f"initialTemperature {T_w if T_grains is None else T_grains};\n")
    add_fluid(case, rho_f, nu, max_co=0.5, max_dt=dt)
    tp = os.path.join(case, "constant", "transportProperties")
    open(tp, "a").write(f"Cp {CP};\nkappa {KAPPA};\nvapour {{ D 2.5e-5; rho {RHO_V}; }}\n")
    cp = os.path.join(case, "constant", "couplingProperties")
    open(cp, "a").write("heatTransferModel DiFeliceColburn;\n"
                        "DiFeliceColburnCoeffs { delta 500; alpha 0.4; }\n" + coupling)
    emp = "frontAndBack { type empty; }"
    if outlet:
        bm = os.path.join(case, "system", "blockMeshDict")
        txt = open(bm).read()
        txt = txt.replace("walls { type wall; faces ((1 5 4 0) (0 4 7 3) (2 6 5 1) (3 7 6 2)); }",
                          "walls { type wall; faces ((1 5 4 0) (0 4 7 3) (2 6 5 1)); }\n"
                          "outlet { type patch; faces ((3 7 6 2)); }")
        open(bm, "w").write(txt)
        write(os.path.join(case, "0", "U"), "volVectorField", "U",
              "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
              f"boundaryField {{ walls {{ type noSlip; }} outlet {{ type pressureInletOutletVelocity;"
              f" value uniform (0 0 0); }} {emp} }}\n")
        write(os.path.join(case, "0", "p"), "volScalarField", "p",
              "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
              f"boundaryField {{ walls {{ type fixedFluxPressure; value uniform 0; }}"
              f" outlet {{ type fixedValue; value uniform 0; }} {emp} }}\n")
        fs = os.path.join(case, "system", "fvSolution")
        txt = open(fs).read().replace("pRefCell 0; pRefValue 0;", "")
        open(fs, "w").write(txt)
        out_T = f"outlet {{ type inletOutlet; inletValue uniform {T_w}; value uniform {T_w}; }}"
        out_psi = "outlet { type inletOutlet; inletValue uniform 0; value uniform 0; }"
    else:
        out_T = out_psi = ""
    write(os.path.join(case, "0", "T"), "volScalarField", "T",
          f"dimensions [0 0 0 1 0 0 0];\ninternalField uniform {T_w};\n"
          f"boundaryField {{ walls {{ type fixedValue; value uniform {T_w}; }} {out_T} {emp} }}\n")
    write(os.path.join(case, "0", "psi"), "volScalarField", "psi",
          "dimensions [0 0 0 0 0 0 0];\ninternalField uniform 0;\n"
          f"boundaryField {{ walls {{ type zeroGradient; }} {out_psi} {emp} }}\n")
    add_scalar_transport(case, "T", "Gauss upwind")
    add_scalar_transport(case, "psi", "Gauss upwind")
    fs = os.path.join(case, "system", "fvSolution")
    txt = open(fs).read().replace("tolerance 1e-9; relTol 0.01;", "tolerance 1e-12; relTol 0;")
    open(fs, "w").write(txt)
    cd = os.path.join(case, "system", "controlDict")
    open(cd, "a").write('libs ("libdropletCoupling.so");\n')
    write(os.path.join(case, "system", "fvOptions"), "dictionary", "fvOptions",
          "droplet { type vapourDropletSource; }\n")
    cx, cy = (w / 2, w / 2) if centre is None else centre
    write(os.path.join(case, "constant", "dropletProperties"), "dictionary", "dropletProperties",
          f"centre ({cx} {cy} {DEPTH / 2});\ndiameter {D};\nliquidDensity {rho_l};\n"
          f"latentHeat {LATENT};\nvapourisationTemperature {T_D};\nvapourDensity {RHO_V};\n"
          f"blowing {'yes' if blowing else 'no'};\nmoving {'yes' if moving else 'no'};\n" + extra)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)


read_droplet = nscdpost.read_droplet


def patch_sum(path, patch):
    """Sum of the values of a surfaceScalarField (e.g. phi [m^3/s]) over a
    patch, from an ascii field file."""
    txt = open(path).read()
    block = re.search(patch + r"\s*\{(.*?)\}", txt[txt.index("boundaryField"):], re.S).group(1)
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


def test_fixed_droplet_conduction(tmp_path, env):
    err = conduction_error(tmp_path, env, 16)
    print(f"D/dx = 16: mdot/(Q_ref/L) - 1 = {err:.4f}")
    assert abs(err) < 0.05      # issue 8
    assert abs(err) < 0.01      # the measured accuracy at 16 cells per D (-0.14 %)


@pytest.mark.skipif(not os.environ.get("NSCD_SLOW"), reason="mesh convergence study: NSCD_SLOW=1")
def test_fixed_droplet_mesh_convergence(tmp_path, env):
    errs = {n: conduction_error(tmp_path, env, n) for n in (8, 16, 32)}
    print("mesh convergence D/dx: error", errs)
    assert abs(errs[32]) < abs(errs[8])


def budget_lines(log):
    """Per step: (fluid boundary, advected, sources) [J] of vansFoam's heat
    budget, energy E [J] of the "heat:" line, global continuity error."""
    h = nscdpost.heat_log(log)
    cont = []
    for line in log.splitlines():
        m = re.match(r"^mixture continuity errors : sum local = \S+, global = (\S+)", line)
        if m:
            cont.append(float(m.group(1)))
    return h["budget"][:, :3], h["E"], np.array(cont)


@pytest.mark.parametrize("release", ["uniform", "heatFlux"])
def test_energy_and_vapour_budget(tmp_path, env, release):
    """Budgets (b) of the module docstring, for both vapourRelease modes
    (where the vapour leaves the surface must not change any budget)."""
    case = str(tmp_path / "budget")
    dt, n_steps = 0.01, 20
    droplet_case(case, env, 8, end_time=dt * n_steps, dt=dt, blowing=True, rho_l=1000.0,
                 outlet=True, extra=f"vapourRelease {release};\n")
    log = run("vansFoam", case, env).stdout
    d = read_droplet(case)
    bud, E, cont = budget_lines(log)
    n = len(d)                      # >= n_steps: the Courant limit may shorten dt
    assert n >= n_steps and len(bud) == n and len(E) == n
    t = d[:, 0]
    dts = np.diff(np.concatenate(([0.0], t)))
    m0 = 1000.0 * math.pi * (D / 2) ** 2 * DEPTH
    m, Qf, Vdot = d[:, 5], d[:, 7] + d[:, 8], d[:, 11]     # Q = Q_f + Q_p (Q_p = 0: no grains)
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
    err = np.abs(cont.reshape(n, -1)[:, -1]) * Vtot / dts   # last corrector [m^3/s]
    assert np.all(err < 1e-6 * Vdot[1:].min())
    outflow = patch_sum(os.path.join(case, f"{dt * n_steps:g}", "phi"), "outlet")
    print(f"outflow {outflow:.9e} m^3/s, Vdot {Vdot[-1]:.9e} m^3/s")
    assert abs(outflow - Vdot[-1]) < 1e-6 * Vdot[-1]


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
    droplet_case(case, env, 8, end_time=dt * n_steps, dt=dt, blowing=True, rho_l=1000.0,
                 outlet=True)
    tp = os.path.join(case, "constant", "transportProperties")
    txt = open(tp).read()
    assert "vapour { D 2.5e-5;" in txt
    open(tp, "w").write(txt.replace("vapour { D 2.5e-5;", "vapour { bounded yes; D 2.5e-5;"))
    log = run("vansFoam", case, env).stdout
    rng = np.array([[float(a), float(b)] for a, b in
                    re.findall(r"psi min/max = (\S+) (\S+)", log)])
    assert len(rng) >= n_steps
    print(f"bounded psi: min {rng[:, 0].min():.3e}, max {rng[:, 1].max():.6f} over {len(rng)} steps")
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
    droplet_case(case, env, n_per_d, end_time=dt * n_steps, dt=dt, blowing=True,
                 rho_l=1e6, outlet=True, centre=centre, write_interval=dt,
                 extra=f"vapourRelease {release};\n")
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
    xy = np.stack([np.tile(xs, n), np.repeat(xs, n)], axis=1)     # blockMesh order
    vol = h * h * DEPTH
    q = nscdpost.read_internal_field(os.path.join(case, last, "dropletVolumeSource"))
    sink = nscdpost.read_internal_field(os.path.join(case, prev, "dropletHeatSink"))
    assert q.shape == (n * n,) and sink.shape == (n * n,)
    Vdot = d[-1, 11]
    assert Vdot > 0
    assert abs(q.sum() * vol - Vdot) < 1e-9 * Vdot
    assert q.min() >= 0
    edges = np.array([-0.75, -0.25, 0.25, 0.75, 1.25]) * np.pi     # lower, right, upper, left
    s_vap = sector_shares(q * vol, xy, centre, edges)
    s_heat = sector_shares(np.maximum(sink, 0) * vol, xy, centre, edges)
    print(f"{release}: vapour shares {np.round(s_vap, 4)}, heat shares {np.round(s_heat, 4)}")
    assert s_heat[0] > 0.4
    if release == "heatFlux":
        assert np.all(np.abs(s_vap - s_heat) < 0.03)
    else:
        assert abs(s_vap[0] - 0.25) < 0.02


@pytest.mark.parametrize("release", ["uniform", "heatFlux"])
def test_restart_continues_exactly(tmp_path, env, release):
    """A run stopped at a write time and restarted (state from
    <time>/uniform/droplet: centre, velocity, mass, pending vapour; with
    vapourRelease heatFlux also the last heat sink) ends as the
    uninterrupted run, to 1e-9 relative on every droplet.dat column
    (reference: the uninterrupted run; fields are written with 17 digits).
    The droplet moves (moving yes, initial velocity) and blows, so the
    position, velocity, mass and lagged vapour all have to be restored."""
    import shutil
    dt = 0.01
    case = str(tmp_path / "full")
    droplet_case(case, env, 6, end_time=10 * dt, dt=dt, blowing=True, rho_l=1000.0,
                 outlet=True, extra=f"velocity (0.004 -0.01 0);\nvapourRelease {release};\n",
                 moving=True)
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace(f"writeInterval {10 * dt};", f"writeInterval {5 * dt};")
    txt = txt.replace("adjustTimeStep yes;", "adjustTimeStep no;")   # same dt after restart
    open(cd, "w").write(txt)
    run("vansFoam", case, env)
    full = read_droplet(case)
    assert len(full) == 10
    assert abs(full[-1, 2] - W / 2) > 1e-4          # it did move (m)
    half = str(tmp_path / "half")
    shutil.copytree(case, half)
    shutil.rmtree(os.path.join(half, "0.1"))
    shutil.rmtree(os.path.join(half, "postProcessing"))
    assert os.path.isfile(os.path.join(half, "0.05", "uniform", "droplet"))
    run("vansFoam", half, env)
    rest = np.loadtxt(os.path.join(half, "postProcessing", "droplet", "0.05", "droplet.dat"),
                      ndmin=2)
    assert len(rest) == 5
    assert np.allclose(rest, full[5:], rtol=1e-9, atol=1e-15)


def held_suspension_case(case, env, r_frac, n, write_every, nu_gas, dg=5e-5):
    """A HELD droplet (D, water, gravity on, no heat) of diameter D at
    (2D, 2D) whose inner disc r < r_frac R is filled with a square lattice of
    free grains of diameter dg (spacing 1.02 dg, phi_2D = 0.755, no
    contacts), gas viscosity nu_gas; n steps of dt = 5e-4 s, written every
    write_every steps.  Returns (grains, dt)."""
    R0, c, a = D / 2, 2 * D, 1.02 * dg
    k = int(r_frac * R0 / a)
    grains = [(c + i * a, c + j * a, DEPTH / 2, dg)
              for j in range(-k, k + 1) for i in range(-k, k + 1)
              if math.hypot(i * a, j * a) < r_frac * R0]
    dt = 5e-4
    droplet_case(case, env, 8, end_time=dt * n, dt=dt, blowing=False, rho_l=RHO_W, T_w=T_D,
                 grains=grains, fixed_grains=False, write_interval=dt * write_every,
                 gravity=9.81, nu=nu_gas, extra=f"liquidViscosity {MU_W};\n")
    return grains, dt


def test_restart_with_grains_continues_exactly(tmp_path, env):
    """The grains' contact predictor of the droplet (vapourDroplet.H, "Gas
    drag of the grains inside") has a history (v^{n-1}, v^{n-2}, F^{n-1},
    dG^{n-1}, dt^{n-1}); it is written to <time>/uniform/droplet
    (grainHistory, the grains within 2 R + r_i of the centre).  A dense
    suspension of free 50 um grains in a held droplet (the case of
    test_dense_suspension_settles_steadily, inner quarter of the radius, gas
    nu = 2e-5), stopped at step 20 of 40 and restarted, ends as the
    uninterrupted run: every droplet.dat column and every grain velocity
    within 1e-9 relative (reference: the uninterrupted run; 17 digits
    written).  Without grainHistory the restart is NOT exact (asserted:
    grain velocities off by > 1e-6 relative; measured 1.3e-4, and 0 with
    it: bit-identical; the first step after the restart then runs without
    the predictor), so the test fails if the history is lost.  A history
    that does not fit the case's grains (a label out of range) is a
    FatalIOError naming grainHistory and the fix."""
    import shutil
    n = 40
    case = str(tmp_path / "full")
    grains, dt = held_suspension_case(case, env, 0.25, n, n // 2, 2e-5)
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace("adjustTimeStep yes;", "adjustTimeStep no;")
    open(cd, "w").write(txt)
    run("vansFoam", case, env)
    full = read_droplet(case)
    assert len(full) == n and np.all(full[:, 17] == len(grains))
    times = nscdpost.time_dirs(case)
    (t1, mid), (t2, last) = times[-2], times[-1]
    assert abs(t1 - dt * n / 2) < 1e-12 and abs(t2 - dt * n) < 1e-12
    u_full = nscdpost.read_grains(case, last)["U"]
    hist = open(os.path.join(case, mid, "uniform", "droplet")).read()
    assert "grainHistory" in hist

    def restart(name, edit_history=None, check=True):
        half = str(tmp_path / name)
        shutil.copytree(case, half)
        shutil.rmtree(os.path.join(half, last))
        shutil.rmtree(os.path.join(half, "postProcessing"))
        if edit_history:
            f = os.path.join(half, mid, "uniform", "droplet")
            txt = edit_history(open(f).read())
            open(f, "w").write(txt)
        p = run("vansFoam", half, env, check=check)
        if not check:
            return p
        rest = np.loadtxt(os.path.join(half, "postProcessing", "droplet", mid, "droplet.dat"),
                          ndmin=2)
        return rest, nscdpost.read_grains(half, last)["U"]

    rest, u_rest = restart("half")
    scale = np.abs(u_full[:, :2]).max()
    err = np.abs(u_rest[:, :2] - u_full[:, :2]).max() / scale
    print(f"{len(grains)} grains, restart with history: max grain velocity error {err:.2e} "
          f"(relative to {scale:.3e} m/s)")
    assert len(rest) == n // 2
    assert np.allclose(rest, full[n // 2:], rtol=1e-9, atol=1e-15)
    assert err < 1e-9
    _, u_lost = restart("lost", lambda txt: txt[:txt.index("grainHistory")] + "\n")
    err_lost = np.abs(u_lost[:, :2] - u_full[:, :2]).max() / scale
    print(f"restart without grainHistory: max grain velocity error {err_lost:.2e}")
    assert err_lost > 1e-6
    # a history that does not fit the grains of the case: a clear error
    p = restart("bad", lambda txt: re.sub(r"\bgrains\b[^;]*;", "grains (99999);", txt, count=1),
                check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "grainHistory" in out and "Fix" in out and "FOAM FATAL IO ERROR" in out, out[-2000:]


@pytest.mark.parametrize("edit, words", [
    (lambda s: s.replace("latentHeat", "latentHeet"), ["latentHeet", "dropletProperties"]),
    (lambda s: re.sub(r"latentHeat \S+;\n", "", s), ["latentHeat", "Missing keyword"]),
    (lambda s: s.replace("diameter", "radius 1e-3;\ndiameter"), ["radius", "diameter"]),
    (lambda s: s.replace("liquidDensity 1000.0", "liquidDensity -1"), ["liquidDensity", "positive"]),
    (lambda s: s + "liquidViscosity -2e-4;\n", ["liquidViscosity", "positive"]),
    (lambda s: s + "vapourRelease bottom;\n", ["vapourRelease", "heatFlux"]),
])
def test_keyword_errors(tmp_path, env, edit, words):
    """constant/dropletProperties is keyword-checked: unknown, missing,
    contradictory or non-positive entries are FatalIOErrors naming the file
    and the keyword."""
    case = str(tmp_path / "err")
    droplet_case(case, env, 2, end_time=0.01, dt=0.01, blowing=False, rho_l=1000.0)
    dp = os.path.join(case, "constant", "dropletProperties")
    txt = edit(open(dp).read())
    open(dp, "w").write(txt)
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "FOAM FATAL IO ERROR" in out
    for w in words:
        assert w in out, out[-1500:]


def test_falling_droplet_added_mass(tmp_path, env):
    """Motion (eq. 4.17, moving yes): a droplet 10 times denser than the gas,
    released from rest in a box w = 8 D, nearly inviscid gas (nu = 1e-7,
    viscous layer sqrt(nu t)/R < 2 % over the run), no vaporisation (walls at
    T_d).  Early-time acceleration of a circular cylinder in an ideal fluid:
        a = (rho_l - rho_f)/(rho_l + C_a rho_f) g,  C_a = 1
    (added mass of a circular cylinder, e.g. Batchelor, An Introduction to
    Fluid Dynamics, 1967, section 6.4; Newman, Marine Hydrodynamics, Table 4.2)
    = 0.818 g.  Measured 0.79 g at 16 cells per D (the walls at 4 D raise C_a
    by a few %, the diffuse surface slightly too); tolerance 5 %.  Without the
    added mass (penalisation force missing) a = 0.9 g, without buoyancy 1.0 g:
    both > 5 % away."""
    case = str(tmp_path / "fall")
    rho_l, dt, n_steps = 10 * RHO, 5e-4, 10
    droplet_case(case, env, 16, end_time=n_steps * dt, dt=dt, blowing=False, rho_l=rho_l,
                 w_over_d=8, gravity=9.81, nu=1e-7, T_w=T_D, moving=True)
    run("vansFoam", case, env)
    d = read_droplet(case)
    assert len(d) == n_steps
    t, v = d[:, 0], d[:, 4]
    a = -np.diff(v) / np.diff(t) / 9.81           # per-step accelerations / g
    a_mean = float(np.mean(a[1:]))                # first step: explicit lag (a = g')
    ref = (rho_l - RHO) / (rho_l + 1.0 * RHO)
    print(f"a/g = {a_mean:.4f} (reference {ref:.4f}), per step {np.round(a, 4)}")
    assert abs(a_mean / ref - 1) < 0.05
    assert np.all(np.abs(d[:, 1] - 4 * D) < 1e-9)     # falls straight down


@pytest.mark.parametrize("release", ["uniform", "heatFlux"])
def test_parallel_matches_serial(tmp_path, env, release):
    """Two ranks (the droplet straddles the processor boundary x = w/2): the
    droplet.dat columns equal the serial run's to 1e-8 relative (reference:
    the serial run; the overlaps are exact on every rank and Q_f, F, the
    ring weights are global sums; with vapourRelease heatFlux the heat sink
    is gathered onto all ranks and the droplet sits low, 0.8 D above the
    hot bottom wall, so that the release is not symmetric)."""
    import shutil
    dt, n_steps = 0.01, 5
    case = str(tmp_path / "serial")
    centre = None if release == "uniform" else (2 * D, 0.8 * D)
    droplet_case(case, env, 6, end_time=dt * n_steps, dt=dt, blowing=True, rho_l=1000.0,
                 outlet=True, centre=centre, extra=f"vapourRelease {release};\n")
    par = str(tmp_path / "par")
    shutil.copytree(case, par)
    run("vansFoam", case, env)
    from foamcase import run_parallel
    run_parallel("vansFoam", par, env, n=2)
    a, b = read_droplet(case), read_droplet(par)
    assert a.shape == b.shape
    assert np.allclose(a[:, :13], b[:, :13], rtol=1e-8, atol=1e-18)
    # forces F_p, F_pen (second increment): the penalisation force is a sum
    # of the end-of-step U, equal to the U solver tolerance (1e-6 relative)
    F = np.abs(a[:, 13:17]).max()
    assert np.allclose(a[:, 13:17], b[:, 13:17], rtol=1e-6, atol=1e-6 * F)
    assert np.array_equal(a[:, 17], b[:, 17])


def lens_area(R, r, d):
    """Area of the intersection of two discs (radii R, r, centre distance d)."""
    if d >= R + r:
        return 0.0
    if d <= abs(R - r):
        return math.pi * min(R, r) ** 2
    a1 = math.acos((d * d + r * r - R * R) / (2 * d * r))
    a2 = math.acos((d * d + R * R - r * r) / (2 * d * R))
    return r * r * a1 + R * R * a2 - 0.5 * math.sqrt((-d + r + R) * (d + r - R) * (d - r + R) * (d + r + R))


def test_absorbed_grains_volume(tmp_path, env):
    """Eq. 4.15, V = V_f + V_p: two fixed grains, one wholly inside the
    droplet (r = 0.3 R at 0.3 R from the centre), one straddling its surface
    (r = 0.25 R at R from the centre).  The droplet radius must satisfy the
    fixed point pi R^2 = pi R_f^2 + pi r1^2 + lens(R, r2, R) (2D, per depth)
    with R_f the liquid radius and lens the disc-disc intersection area
    (elementary geometry, computed here independently), to 1e-9 relative after
    the lagged iteration (one pass per step) has converged; no grains: V_p = 0
    (the other tests)."""
    R0 = D / 2
    c = 2 * D
    grains = [(c + 0.3 * R0, c, DEPTH / 2, 0.6 * R0), (c, c + R0, DEPTH / 2, 0.5 * R0)]
    case = str(tmp_path / "grains")
    droplet_case(case, env, 8, end_time=0.2, dt=0.01, blowing=False, rho_l=1e8, T_w=T_D,
                 grains=grains)
    run("vansFoam", case, env)
    d = read_droplet(case)
    Rf = math.sqrt(d[-1, 5] / (1e8 * math.pi * DEPTH))
    R = d[-1, 9]
    A = math.pi * Rf ** 2 + math.pi * (0.3 * R0) ** 2 + lens_area(R, 0.25 * R0, R0)
    print(f"R/R_f = {R / Rf:.9f}, fixed point R = {math.sqrt(A / math.pi):.12e}, V_p = {d[-1, 12]:.6e}")
    assert abs(R - math.sqrt(A / math.pi)) < 1e-9 * R
    assert abs(d[-1, 12] - (A - math.pi * Rf ** 2) * DEPTH) < 1e-6 * d[-1, 12]
    assert R > 1.04 * Rf


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
    droplet_case(case, env, 8, end_time=dt * n_steps, dt=dt, blowing=False, rho_l=1000.0, T_w=T_D,
                 grains=grains, T_grains=T0)
    log = run("vansFoam", case, env).stdout
    d = read_droplet(case)
    Tg = [float(v) for v in re.findall(r"^heat: grain mean T = (\S+),", log, re.M)]
    assert len(d) == n_steps and len(Tg) == n_steps
    Qf, Qp = d[:, 7], d[:, 8]
    mg = 2500 * math.pi * r * r * DEPTH                # 2D disc x mesh depth
    grain_loss = 2 * mg * 800 * (T0 - Tg[-1])
    heat_p = np.sum(Qp * dt)
    m0 = 1000.0 * math.pi * R0 ** 2 * DEPTH
    print(f"grain heat loss {grain_loss:.6e} J, sum Q_p dt {heat_p:.6e} J, sum Q_f dt "
          f"{np.sum(Qf * dt):.3e} J, T_p {Tg[-1]:.3f} K")
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
    assert abs(I - 0.147262) < 1e-5            # the constant of vapourDroplet.C
    delta = (24 * I * mu_v * k * dT * (2 * r) ** 1.5 / (rho_v * L * F)) ** 0.4
    return delta, math.pi * k * math.sqrt(2 * r / delta)


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
    droplet_case(case, env, 8, end_time=dt * n_steps, dt=dt, blowing=False, rho_l=1000.0,
                 T_w=T_D, grains=[(c, c + R0 + r, DEPTH / 2, 2 * r)], T_grains=T0,
                 fixed_grains=False, gravity=9.81, write_interval=10 * dt,
                 extra="surfaceTension 0.05891;\nfilmConduction yes;\n")
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace("adjustTimeStep yes;", "adjustTimeStep no;")
    open(cd, "w").write(txt)
    log = run("vansFoam", case, env).stdout
    d = read_droplet(case)
    h = nscdpost.heat_log(log)
    Tg = np.array([float(v) for v in re.findall(r"^heat: grain mean T = (\S+),", log, re.M)])
    assert len(d) == n_steps and len(Tg) == n_steps and d.shape[1] == 25
    Qfilm = d[:, 24]
    assert Qfilm[0] == 0
    assert np.all(Qfilm[1:] > 0)
    m_g = rho_s * math.pi * r * r                     # kg/m (2D)
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
    print(f"film: delta {delta0 * 1e6:.3f} um, Q_film {Qfilm[2]:.4e} W, ratio to the "
          f"lubrication film {ratios.min():.6f}..{ratios.max():.6f}, grain T {Tg[-1]:.2f} K")
    assert np.all(np.abs(ratios - 1) < 1e-3)
    assert Tg[-1] < T0 - 1

    # conservation: the film heat leaves the grain once and enters the droplet once
    E, bud = h["E"], h["budget"]
    film_heat = np.sum(Qfilm[1:] * dt)
    defect = (E[-1] - E[0]) - np.sum(bud[1:, :5].sum(axis=1) - Qfilm[1:] * dt)
    print(f"film heat {film_heat:.6e} J, energy defect {defect:.3e} J")
    assert abs(defect) < 1e-8 * film_heat
    m0 = 1000.0 * math.pi * R0 ** 2 * DEPTH
    heat = np.sum((d[:, 7] + d[:, 8] + Qfilm) * dt)
    assert abs(LATENT * (m0 - d[-1, 5]) - heat) < 1e-10 * heat

    half = str(tmp_path / "half")
    shutil.copytree(case, half)
    shutil.rmtree(os.path.join(half, f"{n_steps * dt:g}"))
    shutil.rmtree(os.path.join(half, "postProcessing"))
    assert "filmHeat" in open(os.path.join(half, f"{10 * dt:g}", "uniform", "droplet")).read()
    run("vansFoam", half, env)
    rest = np.loadtxt(os.path.join(half, "postProcessing", "droplet", f"{10 * dt:g}",
                                   "droplet.dat"), ndmin=2)
    assert len(rest) == n_steps - 10
    assert np.allclose(rest, d[10:], rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize("extra, words", [
    ("filmConduction yes;\n", ["filmConduction", "surfaceTension"]),
    ("surfaceTension 0.05891;\nfilmConduction yes;\nvapourViscosity -1;\n",
     ["vapourViscosity", "positive"]),
])
def test_film_keyword_errors(tmp_path, env, extra, words):
    """filmConduction without the capillary barrier (no load for the film)
    and a non-positive vapourViscosity are FatalIOErrors naming the file,
    the keyword and the fix."""
    case = str(tmp_path / "err")
    droplet_case(case, env, 2, end_time=0.01, dt=0.01, blowing=False, rho_l=1000.0, extra=extra)
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "FOAM FATAL IO ERROR" in out and "dropletProperties" in out
    for w in words:
        assert w in out, out[-1500:]


def test_tutorial_skeleton_runs(tmp_path, env):
    """tutorials/vansFoam/dropletDigging (skeleton, Table 4.2) with its own
    setupCase.py on its reduced bed (1 mm grains, 10 steps): the droplet
    vaporises from the start, and its instant lifetime m/mdot is of the order
    of ten seconds as in the thesis at the start of the fall (Figure 4.17:
    ~10 s; accepted 2-60 s, an order-of-magnitude check of eq. 4.16 with
    Table 4.2 properties at T_bed = 400 C)."""
    from foamcase import tutorial_modules
    setup, = tutorial_modules("vansFoam", "dropletDigging", names=("setupCase",))
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


# ---------------------------------------------------------------------------
# Second increment: grain-droplet force F_p (eq. 4.17), porous grains (4.3.2)
# ---------------------------------------------------------------------------

RHO_W, MU_W = 958.0, 2.82e-4   # water at 100 C: Incropera & DeWitt Table A.6
                               # (1/v_f = 958 kg/m^3), IAPWS 2008 (281.8e-6 Pa s)


def difelice_gamma(eps, Re, d, mu, two_d=True):
    """DallavalleDiFelice drag [kg/(m^3 s)] of src/vansCoupling/dragModels
    (Di Felice 1994, correlations.gamma_dallavalle_difelice), per unit disc
    area with the default 2D convention perUnitDepth (8/(3 pi) x the sphere's
    per unit volume) when two_d, per unit sphere volume otherwise."""
    g = correlations.gamma_dallavalle_difelice(eps, Re, d, mu)
    return g * correlations.DISC_PER_UNIT_DEPTH if two_d else g


def rk4(rate, y, t_end, n):
    """y(t_end) of dy/dt = rate(y) from y(0) = y, classical Runge-Kutta with n steps."""
    h = t_end / n
    for _ in range(n):
        k1 = rate(y)
        k2 = rate(y + 0.5 * h * k1)
        k3 = rate(y + 0.5 * h * k2)
        k4 = rate(y + h * k3)
        y += h * (k1 + 2 * k2 + 2 * k3 + k4) / 6
    return y


def grain_relaxation_reference(t_end, u_d, rho_p, d, eps, n=20000):
    """Slip u_d - v(t) of a grain released at rest in liquid moving at u_d:
    rho_p dv/dt = gamma(eps, Re(u_d - v)) (u_d - v), RK4 with n steps."""
    def rate(w):
        return -difelice_gamma(eps, RHO_W * abs(w) * d / MU_W, d, MU_W) * w / rho_p
    return rk4(rate, u_d, t_end, n)


def porous_bed_pressure_gradient(tmp_path, env, n, ny=12, nx=3):
    """Fixed bed filling a 3D box (one sphere of d = 0.999 h per cell, simple
    cubic lattice, uniform upflow U_s from the bottom inlet), grainPorosity n:
    returns the pressure gradient [Pa/m] between interior rows (the lattice is
    uniform, so U = U_s/eps and grad p are uniform there), eps of the
    voidFraction field and the reference: the momentum balance of model A
    with the same DallavalleDiFelice law, eps dp/dy = (1 - eps) gamma u,
    u = U_s/eps, evaluated here at eps = 1 - (1 - n) pi d^3/(6 h^3)."""
    from foamcase import fixed_lattice_bed, read_internal
    d, h, Us, rho, mu = 0.999e-3, 1e-3, 2e-3, 1000.0, 1e-3
    case = str(tmp_path / f"bed{n}")
    extra = f"grainPorosity {n};\n" if n > 0 or "explicit0" in case else ""
    p = fixed_lattice_bed(case, env, h, d, nx, ny, range(ny), Us, rho, mu / rho,
                          extra_coupling=extra)
    t, name = nscdpost.time_dirs(case)[-1]
    eps_field = read_internal(os.path.join(case, name, "voidFraction"))
    # even number of cell intervals: the solver's pressure has a weak odd-even
    # (2-cell) oscillation along the flow in a uniform bed, which cancels
    j1, j2 = 2, ny - 4
    grad = rho * (p[:, j1, :].mean() - p[:, j2, :].mean()) / ((j2 - j1) * h)
    eps = 1 - (1 - n) * math.pi / 6 * d**3 / h**3
    u = Us / eps
    law = (1 - eps) * difelice_gamma(eps, rho * u * d / mu, d, mu, two_d=False) * u / eps
    return grad, eps_field, eps, law, p


def test_porous_grains_pressure_gradient(tmp_path, env):
    """Porous grains (thesis 4.3.2, couplingProperties grainPorosity n): the
    fluid sees (1 - n) of each grain's volume, eps = 1 - (1 - n) phi_geom.
    Fixed bed, uniform upflow: the pressure gradient is the momentum balance
    of model A with the drag law at the reduced solid fraction,
    eps dp/dy = (1 - eps) gamma(eps, Re) u (thesis eq. 3.23, 3.32), gamma
    written out here (difelice_gamma), within 1 % (issue 8); n = 0.5 halves
    the solid fraction (0.522 -> 0.261) and divides the gradient by ~13, so a
    missing porosity would be off by a factor of 13.  grainPorosity 0 gives
    bitwise the run without the keyword (the old code path)."""
    for n in (0.0, 0.5):
        grad, eps_field, eps, law, p = porous_bed_pressure_gradient(tmp_path, env, n)
        print(f"n = {n}: eps = {eps:.6f}, grad p = {grad:.6g} Pa/m, law {law:.6g}, "
              f"rel {grad / law - 1:+.4f}")
        assert np.allclose(eps_field, eps, rtol=1e-12)
        assert abs(grad / law - 1) < 0.01
        if n == 0.0:
            p0 = p
    # explicit grainPorosity 0: identical to the default
    import shutil
    grad, eps_field, eps, law, p = porous_bed_pressure_gradient(tmp_path / "explicit0", env, 0.0)
    assert np.array_equal(p, p0)


@pytest.mark.parametrize("porosity", [0.0, 0.5])
def test_grain_relaxes_in_held_droplet(tmp_path, env, porosity):
    """A free grain (d = 100 um, rho_p = 2500) released at rest at the centre
    of a held droplet of water (rho_l = 958, mu_l = 2.82e-4), gravity on, gas
    nearly inviscid (nu = 1e-9: its drag is 4e-6 of the liquid's), no heat:
    the grain settles in the liquid, rho_p dv/dt = (rho_p - k rho_l - rho_f) g -
    gamma(eps_l, Re) v/eps_l, with gamma the DallavalleDiFelice law of
    vansCloud (thesis eq. 3.32) evaluated with the liquid's rho, mu at
    eps_l = 1 - (1 - n) V_p/V (eq. 4.15) and Re = rho_l |v| d/mu_l;
    reference: that ODE integrated here (RK4), time constant tau ~ 1.7 ms,
    terminal velocity 1.0 cm/s (Re ~ 3.4).  The liquid pressure on the grain
    is (a/V) S with S = -m g - F_p the holder's force (README, "Liquid
    pressure on the grains"): a/V S = -k rho_l a g + (a/(V - a)) c (u - v),
    k = (V - V_p)/(V - a) (= 1 for n = 0), a = (1 - n) V_p, i.e. the
    hydrostatic buoyancy plus the grain's weight spread over the droplet,
    which raises the drag by 1/eps_l (hindered settling of a suspension):
    the reference changes by -0.13 % (n = 0) / -0.03 % (n = 0.5) at
    t = 12 ms (terminal) against the former rho_l g buoyancy.
    Within 2 % at every write time over 7 tau at the Table 4.2 time step
    dt = 5e-4 s (dt/tau ~ 0.3; measured max 1.1 %, 0.3 % at dt = 2e-4: the
    exponential integration over the step is exact for a Re-independent law).
    Without the liquid drag the grain free-falls (v = g t = 0.12 m/s).
    Porous grain (grainPorosity 0.5, density (1 - n) 2500 as the README
    prescribes): mass, weight, drag and buoyancy all scale with (1 - n), so
    the same curve (eps_l = 1 - (1 - n) V_p/V)."""
    R0, c, dg, G = D / 2, 2 * D, 1e-4, 9.81
    dt, n = 5e-4, 24
    case = str(tmp_path / "relax")
    droplet_case(case, env, 8, end_time=dt * n, dt=dt, blowing=False, rho_l=RHO_W, T_w=T_D,
                 grains=[(c, c, DEPTH / 2, dg)], fixed_grains=False, write_interval=dt * n / 6,
                 nu=1e-9, gravity=G, extra=f"liquidViscosity {MU_W};\n",
                 coupling=f"grainPorosity {porosity};\n")
    if porosity > 0:
        gp = os.path.join(case, "constant", "grainProperties")
        txt = open(gp).read().replace("density 2500;", f"density {(1 - porosity) * 2500};")
        open(gp, "w").write(txt)
        run("grainDeposit", case, env)      # the grain state holds the masses
    run("vansFoam", case, env)
    # liquid fraction of the droplet, 1 - (1 - n) V_p/V (eq. 4.15)
    vp = (dg / 2) ** 2 / (R0**2 + (dg / 2) ** 2)        # V_p/V
    eps = 1 - (1 - porosity) * vp
    k = (1 - vp) / eps

    def reference(t, N=2000):
        def rate(v):
            gam = difelice_gamma(eps, RHO_W * abs(v) * dg / MU_W, dg, MU_W)
            return ((2500 - k * RHO_W - RHO) * G - gam * v / eps) / 2500
        return rk4(rate, 0.0, t, N)
    times = nscdpost.time_dirs(case)[1:]
    assert len(times) == 6
    for t, name in times:
        v = nscdpost.read_grains(case, name)["U"][0]
        ref = reference(t)
        print(f"t = {t:.4f} s: v = {-v[1]:.6e} m/s, reference {ref:.6e}, rel {-v[1] / ref - 1:+.4f}")
        assert abs(-v[1] / ref - 1) < 0.02
        assert abs(v[0]) < 1e-9 * abs(v[1])


def test_grain_droplet_momentum_exchange(tmp_path, env):
    """Newton's third law of F_p (eq. 4.17): a moving droplet (released with
    u_d = (5, -2) cm/s, gravity on, no heat) with four free grains (three
    inside, one straddling the surface, no contacts).  Every step:
    - F_p on the droplet (droplet.dat) = -(sum of the forces vansFoam handed to
      the grains' NSCD step) to 1e-12 relative;
    - droplet momentum (eq. 4.17, moving): (m - rho_f V)(u^{n+1} - u^n)/dt =
      F_pen + F_p + (m - rho_f V) g to 1e-9;
    - grain momentum: sum m_i (v_i^{n+1} - v_i^n) = dt (sum F_fluid,i + sum m_i g
      - F_p/depth) to 1e-8 relative to the droplet impulse (written states,
      17 digits), i.e. droplet + grains + gas exchange closes."""
    R0, c, G = D / 2, 2 * D, 9.81
    dgs = [1e-4, 1.5e-4, 2e-4, 2e-4]
    grains = [(c + 0.3 * R0, c, DEPTH / 2, dgs[0]), (c - 0.4 * R0, c + 0.2 * R0, DEPTH / 2, dgs[1]),
              (c, c - 0.5 * R0, DEPTH / 2, dgs[2]), (c + R0, c, DEPTH / 2, dgs[3])]
    dt, n = 5e-4, 6
    case = str(tmp_path / "momentum")
    droplet_case(case, env, 8, end_time=dt * n, dt=dt, blowing=False, rho_l=RHO_W, T_w=T_D,
                 grains=grains, fixed_grains=False, write_interval=dt, gravity=G,
                 extra="velocity (0.05 -0.02 0);\n", moving=True)
    log = run("vansFoam", case, env).stdout
    d = read_droplet(case)
    sums = [tuple(float(x) for x in m) for m in
            re.findall(r"^droplet-grain force: sum over grains = \((\S+) (\S+) (\S+)\) N", log, re.M)]
    assert len(d) == n and len(sums) == n
    Fp = d[:, 13:15]
    assert np.all(d[:, 17] == 4) and np.all(np.abs(Fp[:, 1]) > 0)
    for k in range(n):
        assert np.allclose(Fp[k], -np.array(sums[k][:2]), rtol=1e-12, atol=1e-12 * np.abs(Fp[k]).max())
    # droplet
    m = d[:, 5]
    mEff = m - RHO * m / RHO_W
    u = np.vstack([[0.05, -0.02], d[:, 3:5]])
    lhs = mEff[:, None] * np.diff(u, axis=0) / dt
    rhs = d[:, 15:17] + Fp + mEff[:, None] * np.array([0, -G])
    assert np.allclose(lhs, rhs, rtol=0, atol=1e-9 * np.abs(rhs).max())
    # grains (per unit depth in nscd)
    mass = np.array([2500 * math.pi * (dg / 2) ** 2 for dg in dgs])
    states = [nscdpost.read_grains(case, name) for t, name in nscdpost.time_dirs(case)]
    assert len(states) == n + 1
    for k in range(n):
        dP = (mass[:, None] * (states[k + 1]["U"] - states[k]["U"])[:, :2]).sum(axis=0)
        ext = dt * (states[k + 1]["Ffluid"][:, :2].sum(axis=0) + mass.sum() * np.array([0, -G]))
        jump = -dt * Fp[k] / DEPTH
        print(f"step {k}: grain momentum change - external {dP - ext}, droplet impulse {jump}")
        assert np.allclose(dP - ext, jump, rtol=0, atol=1e-8 * np.abs(jump).max())


@pytest.mark.parametrize("value", ["1", "-0.1"])
def test_grain_porosity_keyword_error(tmp_path, env, value):
    """couplingProperties grainPorosity must be in [0, 1): FatalIOError naming
    the keyword and the file."""
    case = str(tmp_path / "err")
    droplet_case(case, env, 2, end_time=0.01, dt=0.01, blowing=False, rho_l=1000.0,
                 coupling=f"grainPorosity {value};\n")
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0 and "FOAM FATAL IO ERROR" in out
    assert "grainPorosity" in out and "couplingProperties" in out


def darcy_seepage_speed(phi, d, rho_f=RHO, n=0.0):
    """Seepage speed [m/s] of the droplet model through a fixed bed of solid
    fraction phi (the grains' (1 - n) share seen by the liquid) that fills
    the droplet, derived from the model's equations at steady state
    (src/dropletCoupling/README.md, "Liquid pressure on the grains"):
    liquid, eq. 4.17 with the surface force S = F_f = -V grad p,
      0 = m g + S + F_p,  F_p = -sum_i F_i,
    fixed grain i: F_i = c_i u + (a_i/V) S (drag + its share of the liquid
    pressure), a_i = f_i V_i, sum a_i = phi V, sum c_i = C = phi V gamma;
    free droplet in a gas at rest, no gas drag (F_pen = 0): S = -rho_f V_f g
    (buoyancy of the gas on the liquid; Uhlmann's surface force), so
      C u = m g - (1 - phi) rho_f V_f g,   m = rho_l V_f,  V_f = (1 - phi) V:
      u = g (1 - phi) (rho_l - (1 - phi) rho_f) / (phi gamma(1 - phi, Re)),
    Re = rho_l u d/mu_l, gamma the DallavalleDiFelice law (difelice_gamma),
    solved by fixed point: the 1D Darcy law of a liquid whose pressure
    gradient is the gas's, eps_l (rho_l - rho_f) g = (1 - eps_l) gamma u
    (model A, as in test_porous_grains_pressure_gradient), up to the gas's
    buoyancy on the grain volume (phi rho_f/rho_l = 5e-4).  In the Stokes
    limit gamma ~ 1/d^2, so u ~ d^2.  The former hydrostatic buoyancy
    (grains pushed by rho_l g, the droplet by the reaction) gave
    u = g (rho_l - rho_f (1 - phi))/(phi gamma): 1/(1 - phi) = 2.0 times
    this at phi = 0.503."""
    u = 1e-3
    for _ in range(100):
        u = 9.81 * (1 - phi) * (RHO_W - (1 - phi) * rho_f) / (
            phi * difelice_gamma(1 - phi, RHO_W * u * d / MU_W, d, MU_W))
    return u


def seepage_run(tmp_path, env, dg):
    """Droplet (D = 2.5 mm, water, moving yes, gravity, no heat) released at
    rest inside a FIXED square lattice of grains of diameter dg, spacing
    1.25 dg (phi = pi/(4 1.25^2) = 0.503), which covers the droplet with a
    margin of 4 spacings even after it has swollen to R = R_0/sqrt(1 - phi)
    (eq. 4.15); gas nearly inviscid (nu = 1e-9) so that the gas resistance
    F_pen is negligible.  Returns droplet.dat."""
    R0, c, G = D / 2, 2 * D, 9.81
    a = 1.25 * dg
    half = R0 / math.sqrt(1 - math.pi / (4 * 1.25**2)) + 4 * a
    k = int(half / a)
    grains = [(c + i * a, c + j * a, DEPTH / 2, dg)
              for j in range(-k, k + 1) for i in range(-k, k + 1)]
    dt, n = 5e-4, 16
    case = str(tmp_path / f"seep{dg:g}")
    droplet_case(case, env, 8, end_time=dt * n, dt=dt, blowing=False, rho_l=RHO_W, T_w=T_D,
                 grains=grains, fixed_grains=True, gravity=G, nu=1e-9,
                 extra=f"liquidViscosity {MU_W};\n", moving=True)
    run("vansFoam", case, env)
    return read_droplet(case)


def test_droplet_seeps_through_fixed_bed(tmp_path, env):
    """A droplet has no capillary or contact force with the grains in the
    thesis (eq. 4.17: F_p is the force of the particles on the liquid, here
    their drag in the liquid + their share of the liquid's pressure), so on
    a bed that is not fluidised it is not held but seeps through the packing
    at the liquid's Darcy speed of the same drag law, which scales as d^2.
    The liquid's pressure gradient is the one its surface imposes (grad p =
    -S/V, the gas's), so the drag carries the liquid's own weight only:
    at the solid fraction phi = 0.4 of Table 4.2's porous bed (thesis 4.3.2)
    0.98 mm/s for d = 55 um, 3.2 mm/s at 0.1 mm, 1.2 cm/s at 0.2 mm, 4.2 cm/s
    at 0.5 mm (darcy_seepage_speed; 1.6 mm/s, 5.3 mm/s, 1.9 cm/s, 5.8 cm/s
    with the former hydrostatic buoyancy, ~1/(1 - phi) faster).
    Measured: d = 50 um 0.3235 mm/s, against (a) -1.1e-5, (b) -0.47 %;
    d = 100 um 1.2763 mm/s, (a) -1.1e-6, (b) -0.38 %; ratio 3.945 (law
    3.942); gas resistance F_pen/F_p < 1.2e-5.
    Reference: darcy_seepage_speed (steady state of the model's droplet
    equations fully inside a uniform fixed bed, derived in its docstring;
    DallavalleDiFelice, thesis eq. 3.32, written out in difelice_gamma),
    evaluated (a) with the droplet's own liquid fraction eps_l = 1 - V_p/V
    from droplet.dat (exact lens overlaps) - tolerance 2 % - and (b) with
    the lattice's phi = 0.503 - tolerance 5 % (the lens sum over a finite
    lattice differs from phi V by the boundary layer of grains), for d = 50
    and 100 um.  Scaling: u(100 um)/u(50 um) = 4 (d^2, Darcy) within 20 %
    (brief) and equal to the law's own ratio (the inertial correction is weak
    at Re_d = 0.05-0.5) within 3 %.  The gas resistance is < 1 % of F_p
    (nu_gas = 1e-9).  The former hydrostatic model is 2.0 times faster: the
    2 % tolerance excludes it."""
    G = 9.81
    phi_lat = math.pi / (4 * 1.25**2)
    speeds = {}
    for dg in (5e-5, 1e-4):
        d = seepage_run(tmp_path, env, dg)
        last = d[-4:]
        m, R, Vp = last[:, 5], last[:, 9], last[:, 12]
        V = math.pi * R**2 * DEPTH
        phi = Vp / V
        u = -last[:, 4]
        u_own = np.array([darcy_seepage_speed(p, dg) for p in phi])
        u_lat = darcy_seepage_speed(phi_lat, dg)
        Fpen, Fp = last[:, 16], last[:, 14]
        print(f"d = {dg:g}: u = {u[-1]:.5e} m/s, Darcy (own phi {phi[-1]:.4f}) {u_own[-1]:.5e} "
              f"({u[-1] / u_own[-1] - 1:+.2e}), lattice phi {phi_lat:.4f}: {u_lat:.5e} "
              f"({u[-1] / u_lat - 1:+.2e}), F_pen/F_p {np.max(np.abs(Fpen / Fp)):.1e}, "
              f"grains in {int(last[-1, 17])}")
        assert np.all(np.abs(Fpen) < 0.01 * np.abs(Fp))
        assert np.all(np.abs(u / u_own - 1) < 0.02)
        assert abs(u[-1] / u_lat - 1) < 0.05
        assert np.all(np.abs(last[:, 3]) < 1e-6 * u)      # straight down
        speeds[dg] = (u[-1], u_lat)
    ratio = speeds[1e-4][0] / speeds[5e-5][0]
    ratio_law = speeds[1e-4][1] / speeds[5e-5][1]
    print(f"u(100 um)/u(50 um) = {ratio:.4f} (d^2: 4, law {ratio_law:.4f})")
    assert abs(ratio / 4 - 1) < 0.2
    assert abs(ratio / ratio_law - 1) < 0.03


@pytest.mark.parametrize("with_grain", [False, True])
def test_droplet_lands_on_wall(tmp_path, env, with_grain):
    """Robustness (issue 8 brief: a droplet reaching a wall must not stop the
    run): unilateral, frictionless, perfectly inelastic contact of the
    droplet surface with the walls (vapourDroplet::wallContact).  A water
    droplet (D = 2.5 mm) released at rest with its surface 0.3 mm above the
    bottom wall falls through the gas (no heat: walls at T_d, blowing off),
    lands after ~sqrt(2 x 0.3 mm/g) = 8 ms and stays.  Checks:
    - no crash, one droplet.dat line per step;
    - final gap y_d - R to the wall < 1e-9 m and >= -1e-12 m (the contact puts
      the surface exactly on the wall), final velocity 0 (< 1e-9 m/s);
    - the droplet never goes below the wall (gap >= -1e-12 m at every step);
    - eq. 4.17 with the wall reaction closes every step,
      (m - rho_f V)(u^{n+1} - u^n)/dt = F_pen + F_p + F_w + (m - rho_f V) g,
      to 1e-9 (momentum conservation), F_w >= 0 (pushes only) and F_w = 0
      before the landing;
    - at rest (last 10 steps) the reaction carries the droplet's weight:
      F_w,y = m g within 1 % (brief; the gas's buoyancy rho_f/rho_l = 0.1 %
      and the decaying gas force are inside that).
    with_grain: a free grain (d = 0.4 mm, rho_s = 2500) inside the droplet,
    touching its lowest point from inside; droplet and grain fall together
    (weightless inside) and land together (the grain on the wall through its
    NSCD contact, 32 um after the droplet, which is swollen by V_p).  At rest
    the liquid pressure inside is hydrostatic again (S = -V grad p from the
    liquid balance with the wall reaction, src/dropletCoupling/README.md), so
    the grain feels the buoyancy rho_l V_i g and the droplet its reaction:
    F_w,y = (m + rho_l V_i) g within 1 % (the grain's share), the grain's
    wall contact carries (rho_s - rho_l) V_i g; without the share F_w,y = m g
    is 2.6 % lower (asserted > 1.5 %: the test discriminates)."""
    R0, G, gap0 = D / 2, 9.81, 3e-4
    dt, n = 5e-4, 50
    case = str(tmp_path / "land")
    dg = 4e-4
    grains = [(W / 2, gap0 + dg / 2, DEPTH / 2, dg)] if with_grain else ()
    droplet_case(case, env, 8, end_time=dt * n, dt=dt, blowing=False, rho_l=RHO_W, T_w=T_D,
                 gravity=G, extra=f"liquidViscosity {MU_W};\n", grains=grains,
                 fixed_grains=False, moving=True, centre=(W / 2, R0 + gap0))
    run("vansFoam", case, env)
    d = read_droplet(case)
    assert len(d) == n and d.shape[1] >= 20
    y, v, m, R = d[:, 2], d[:, 4], d[:, 5], d[:, 9]
    gap = y - R
    Fw = d[:, 18:20]
    mEff = m - RHO * m / RHO_W
    u = np.vstack([[0.0, 0.0], d[:, 3:5]])
    lhs = mEff[:, None] * np.diff(u, axis=0) / dt
    rhs = d[:, 15:17] + d[:, 13:15] + Fw + mEff[:, None] * np.array([0, -G])
    landed = np.nonzero(Fw[:, 1] > 0)[0]
    print(f"landing step {landed[0]} (t = {d[landed[0], 0]:.4f} s), final gap {gap[-1]:.3e} m, "
          f"v {v[-1]:.3e} m/s, F_w/(m g) = {Fw[-1, 1] / (m[-1] * G):.6f}")
    assert np.all(gap >= -1e-12)
    assert 0 <= gap[-1] < 1e-9
    assert abs(v[-1]) < 1e-9
    assert np.allclose(lhs, rhs, rtol=0, atol=1e-9 * np.abs(mEff * G).max())
    assert np.all(Fw[:, 1] >= 0) and np.all(Fw[:, 0] == 0)
    assert landed[0] > 5 and np.all(Fw[:landed[0], 1] == 0)    # falls freely first
    share = RHO_W * math.pi * (dg / 2) ** 2 * DEPTH if with_grain else 0.0
    late = Fw[-10:, 1] / ((m[-10:] + share) * G)
    print(f"at rest F_w/((m + rho_l V_i) g) = {late[-1]:.6f}, grains inside {d[-1, 17]:g}")
    assert np.all(np.abs(late - 1) < 0.01)
    if with_grain:
        assert np.all(d[:, 17] == 1)
        assert np.all(np.abs(Fw[-10:, 1] / (m[-10:] * G) - 1) > 0.015)


def test_supported_grain_gets_full_drag(tmp_path, env):
    """The contact network carries the droplet's push: a free grain (d = 50
    um) resting on a fixed grain (d = 0.4 mm, mostly outside) inside a held
    droplet whose liquid moves down at u_d = 1 cm/s, gravity on.  The grain
    cannot move, so the liquid must give it the full drag of its law plus
    its full share of the liquid pressure,
      F_i = c_i (u_d - v_i) + (a_i/V) S,  c_i = a_i gamma(eps_l, Re_i),
    a_i = f_i V_i, and the droplet the opposite F_p = -sum F_i; S is the
    holder's force that keeps the droplet still, S = -m g - F_p (liquid
    balance, eq. 4.17 with du_d/dt = 0), hence
      S = (-m g + sum c_i (u_d - v_i))/(1 - sum a_i/V)
    (model in src/dropletCoupling/README.md; gamma the DallavalleDiFelice
    law, thesis eq. 3.32, evaluated here).  At dt = 1 ms the grain's x = c
    dt/m ~ 2: a coupling that sees only the grain's inertia (no contact
    predictor) gives phi (c_i (u_d - v_i) + (a_i/V) S) - (1 - phi) m_i g,
    phi = (1 - e^-x)/x, here F_p off by more than 20 % (checked); with the
    predictor of the other forces (eq. 3.46 p^n) the fixed point is the full
    force: F_p within 1 % after 30 steps.  The fixed grain's share is exact
    by construction."""
    R0, c, G, u = D / 2, 2 * D, 9.81, 0.01
    df, dg = 4e-4, 5e-5
    y_free = c - R0 + 1e-4
    y_fix = y_free - (dg + df) / 2 * 1.0001
    dt, n = 1e-3, 30
    case = str(tmp_path / "support")
    droplet_case(case, env, 8, end_time=dt * n, dt=dt, blowing=False, rho_l=RHO_W, T_w=T_D,
                 grains=[(c, y_free, DEPTH / 2, dg)], fixed_grains=False, gravity=G, nu=1e-9,
                 extra=f"velocity (0 {-u} 0);\nliquidViscosity {MU_W};\n")
    open(os.path.join(case, "system", "grainDepositDict"), "a").write(
        f"fixedRow {{ from ({c} {y_fix} {DEPTH / 2}); to ({c} {y_fix} {DEPTH / 2}); diameter {df}; }}\n")
    run("grainDeposit", case, env)
    run("vansFoam", case, env)
    d = read_droplet(case)
    t, name = nscdpost.time_dirs(case)[-1]
    gr = nscdpost.read_grains(case, name)
    R, Vp, m_d = d[-1, 9], d[-1, 12], d[-1, 5]
    Vd = math.pi * R**2 * DEPTH
    eps = 1 - Vp / Vd
    gvec = np.array([0.0, -G])
    drag, a_sum, parts = np.zeros(2), 0.0, []
    for x, di, v in zip(gr["x"], gr["d"], gr["U"]):
        r = di / 2
        f = lens_area(R, r, math.hypot(x[0] - c, x[1] - c)) / (math.pi * r * r)
        V = math.pi * r * r
        rel = np.array([0.0, -u]) - v[:2]
        gam = difelice_gamma(eps, RHO_W * np.linalg.norm(rel) * di / MU_W, di, MU_W)
        drag += f * V * gam * rel
        a_sum += f * V
        parts.append((f * V, f * V * gam, rel))
    # holder's force S [N over the depth] and the full force on each grain
    S = (-m_d * gvec + DEPTH * drag) / (1 - DEPTH * a_sum / Vd)
    F = np.zeros(2)
    F_nopred = np.zeros(2)
    share = []
    for i, (a_i, c_i, rel) in enumerate(parts):
        Fi = c_i * rel + a_i * S / Vd
        F += Fi
        share.append(Fi[1])
        if gr["fixed"][i]:
            F_nopred += Fi
        else:
            # what a coupling without the contact predictor would give
            m = 2500 * math.pi * (gr["d"][i] / 2) ** 2
            x_i = c_i * dt / m
            phi = (1 - math.exp(-x_i)) / x_i
            F_nopred += phi * Fi - (1 - phi) * m * gvec
    F_ref = -F * DEPTH
    F_nopred = -F_nopred * DEPTH
    print(f"x = {x_i:.2f}, without the predictor F_p would be {F_nopred}")
    assert abs(F_nopred[1] / F_ref[1] - 1) > 0.2          # the test discriminates
    print(f"F_p = {d[-1, 13:15]}, reference {F_ref}, rel {d[-1, 14] / F_ref[1] - 1:+.2e}, "
          f"grain shares {share}, v_free = {gr['U'][0]}")
    assert gr["fixed"][1] and not gr["fixed"][0]
    assert np.linalg.norm(gr["U"][0]) < 1e-3 * u                 # held by the contact
    assert abs(d[-1, 14] / F_ref[1] - 1) < 0.01


def test_free_droplet_is_weightless_inside(tmp_path, env):
    """Liquid pressure on the grains inside a FREE droplet (src/dropletCoupling/
    README.md, "Liquid pressure on the grains"; mixture momentum balance of the
    droplet, thesis eq. 4.17 with F_f + F_w = S = -V grad p): a water droplet
    (D = 2.5 mm) with three free grains inside (d = 100-200 um, rho_s = 2500,
    no contacts), released at rest in a gas of density rho_f = 1e-3 kg/m^3
    (rho_f/rho_l = 1e-6), gravity on, no heat.  The liquid's pressure
    gradient is fixed by its surface, grad p = -S/V ~ rho_f g, so a freely
    falling droplet is weightless inside: the grains do not move relative to
    the liquid and droplet + grains fall at g.  20 steps of dt = 5e-4 s:
    - droplet velocity = -g t within 1e-4 relative at every step (measured
      5e-6: the gas's added mass and drag, rho_f/rho_l = 1e-6);
    - the surface force S (droplet.dat, last two columns) < 1e-4 m g
      (measured 5e-6);
    - every grain: v_i = -g t within 1e-3 relative and |v_i - u_d| < 5e-5 m/s
      at every write time (measured max 1.5e-5 m/s at 10 ms).  What is left
      is not the droplet's: the gas force of vansCloud on grains inside the
      penalised droplet (Ffluid, written) is 1-4e-4 of their weight at
      rho_f = 1e-4, 1e-3 and 1e-2 alike (the kinematic pressure inside the
      penalised region has gradients ~1e4 m/s^2 there), so the bound is
      4e-4 g t = 4e-5 m/s, and the test checks that the relative velocity
      stays below max|Ffluid_i|/m_i t + 1e-7 m/s, i.e. the droplet adds none.
    The former hydrostatic buoyancy F_b,i = -f_i V_i rho_l g pushed each grain
    up at (rho_l/rho_s) g = 0.38 g relative to the liquid, limited by the
    drag: w(t) = w_t (1 - e^{-t/tau}), w_t = rho_l g/gamma, tau = rho_s/gamma
    (DallavalleDiFelice at eps_l, written out here): 0.92 cm/s for the 100 um
    grain at 10 ms (Stokes-limit drag), 180 times the bound (asserted > 100).
    Measured with the former model (same case): max |v_i - u_d| = 0.73 /
    1.15 / 1.37 / 1.49 cm/s at 2.5 / 5 / 7.5 / 10 ms (300 x the bound), and
    the droplet fell 1.0 % faster than g (the reaction of the buoyancy)."""
    R0, c, G = D / 2, 2 * D, 9.81
    rho_f, rho_s = 1e-3, 2500.0
    dgs = [1e-4, 1.5e-4, 2e-4]
    grains = [(c + 0.4 * R0, c, DEPTH / 2, dgs[0]), (c - 0.4 * R0, c + 0.2 * R0, DEPTH / 2, dgs[1]),
              (c, c - 0.5 * R0, DEPTH / 2, dgs[2])]
    dt, n = 5e-4, 20
    case = str(tmp_path / "weightless")
    droplet_case(case, env, 8, end_time=dt * n, dt=dt, blowing=False, rho_l=RHO_W, T_w=T_D,
                 grains=grains, fixed_grains=False, write_interval=dt * n / 4, gravity=G,
                 rho_f=rho_f, extra=f"liquidViscosity {MU_W};\n", moving=True)
    run("vansFoam", case, env)
    d = read_droplet(case)
    assert len(d) == n and np.all(d[:, 17] == 3)
    t, u = d[:, 0], d[:, 3:5]
    fall = u[:, 1] / (-G * t) - 1
    S = d[:, 20:22]
    mg = d[:, 5] * G
    print(f"droplet: max |v/(-g t) - 1| = {np.abs(fall).max():.2e}, max |u_x| = {np.abs(u[:, 0]).max():.1e}, "
          f"max |S|/(m g) = {np.abs(S).max() / mg.min():.2e}")
    assert np.all(np.abs(fall) < 1e-4)
    assert np.all(np.abs(S) < 1e-4 * mg[:, None])
    bound = 5e-5
    mass = np.array([rho_s * math.pi * (dg / 2) ** 2 for dg in dgs])
    for tw, name in nscdpost.time_dirs(case)[1:]:
        k = int(round(tw / dt)) - 1
        gr = nscdpost.read_grains(case, name)
        rel = np.abs(gr["U"][:, :2] - u[k]).max()
        gas = np.abs(gr["Ffluid"][:, :2]).max(axis=1) / mass
        print(f"t = {tw:g} s: max |v_i - u_d| = {rel:.2e} m/s, gas force / weight {np.round(gas / G, 6)}, "
              f"v_i/(-g t) - 1 = {np.round(gr['U'][:, 1] / (-G * tw) - 1, 6)}")
        assert rel < bound
        assert rel < gas.max() * tw + 1e-7
        assert np.all(np.abs(gr["U"][:, 1] / (-G * tw) - 1) < 1e-3)
    # the former hydrostatic buoyancy: relative velocity of the 100 um grain at 10 ms
    eps = 1 - d[-1, 12] / (math.pi * d[-1, 9] ** 2 * DEPTH)
    gam = difelice_gamma(eps, 0.0, dgs[0], MU_W)
    w_old = RHO_W * G / gam * (1 - math.exp(-t[-1] * gam / rho_s))
    print(f"former hydrostatic model: |v_i - u_d| ~ {w_old:.2e} m/s (Stokes-limit drag)")
    assert w_old > 100 * bound


@pytest.mark.parametrize("nu_gas", [2e-5, 1e-9])
def test_dense_suspension_settles_steadily(tmp_path, env, nu_gas):
    """Issue 8 (Table 4.2: 55 um grains at dt = 5e-4 s): a dense square
    lattice of 481 free 50 um grains (spacing 1.02 d, phi_2D = 0.755, no
    contacts) fills the inner half (r < R/2) of a HELD droplet (moving no,
    water, gravity on).  The suspension must settle at the model's steady
    hindered-settling speed (src/dropletCoupling/README.md, "Liquid pressure
    on the grains": held droplet, S from the liquid balance, S = -(m_d + M) g
    at steady state, so every grain fully inside has c_i v_i = (m_i - rho_mix
    V_i) g):
      v = (rho_s - rho_mix) g / gamma(eps_l, Re),  rho_mix = (m_d + M)/V,
    gamma the DallavalleDiFelice law (Di Felice 1994, 2D perUnitDepth,
    difelice_gamma) at the droplet's own eps_l = 1 - V_p/V (droplet.dat).
    200 steps of dt = 5e-4 s, checked at 4 write times.  Consistency check
    of the droplet's grain coupling (the reference is the model's own law).
    Bounds: the measured values plus noise; they were 2.36 x tighter before
    the drag law was corrected (issue 25): the grains now settle 2.36 x
    faster and the lag of the coupling grows with the speed.
    - nu_gas = 1e-9 (gas resistance negligible): the reference itself, mean
      v_y within -3 %..0 of -v, every grain within -8 %..+5 %, |v_x| < 0.05 v
      (measured mean -2.3..-2.0 %, -6.9..+3.3 %, |v_x| < 0.037 v).
    - nu_gas = 2e-5 (the other cases' gas): the gas inside the penalised
      droplet drags the dense lattice (vansCloud's implicit factor
      b_i = W dt gamma*/m) and can only slow it on average: mean -12 %..0,
      every grain -28 %..+15 %, |v_x| < 0.2 v, no time-step collapse (200
      steps). Measured with the gas drag inside the contact solve (issue
      26): mean -10.0..-7.8 %, grains -21.8..+10.5 %, |v_x| < 0.146 v; with
      the gas drag from the last contact impulse (before) mean -10.7..-10.4 %,
      grains -15.6..+2.3 %, |v_x| < 0.076 v: the droplet's predictor below
      still models vansCloud's gas drag as lagged by a step, and turning that
      part off (b_i = 0) widens the spread further (-28..+15 %).  This is the
      case of the issue: without the gas-drag part of the predictor
      (vapourDroplet.H, "Gas drag of the grains inside") the droplet's and
      vansCloud's predictors over-correct each other (linear growth factor
      -1.4 per step at b = 0.83, x = 1): F_p flips sign every step, the
      grains reach 0.4-1.3 m/s (700 x v) and the time step collapses (269
      steps instead of 200), measured."""
    G, dg, n = 9.81, 5e-5, 200
    case = str(tmp_path / "dense")
    grains, dt = held_suspension_case(case, env, 0.5, n, n // 4, nu_gas, dg)
    run("vansFoam", case, env)
    d = read_droplet(case)
    m_d, R, Vp = d[-1, 5], d[-1, 9], d[-1, 12]
    V = math.pi * R**2 * DEPTH
    eps = 1 - Vp / V
    rho_mix = (m_d + 2500 * Vp) / V
    v = 1e-3
    for _ in range(50):
        v = (2500 - rho_mix) * G / difelice_gamma(eps, RHO_W * v * dg / MU_W, dg, MU_W)
    lo, hi, mlo, mhi, xmax = ((-0.28, 0.15, -0.12, 0.0, 0.2) if nu_gas > 1e-6
                              else (-0.08, 0.05, -0.03, 0.0, 0.05))
    rows = []
    for tw, name in nscdpost.time_dirs(case)[1:]:
        gr = nscdpost.read_grains(case, name)
        rel = -gr["U"][:, 1] / v - 1
        vx = np.abs(gr["U"][:, 0]).max() / v
        print(f"nu_gas {nu_gas:g}, t = {tw:g} s: {len(grains)} grains, v_ref = {v:.4e} m/s "
              f"(eps_l {eps:.4f}, rho_mix {rho_mix:.1f}), v_y/v_ref - 1 mean {rel.mean():+.4f} "
              f"in [{rel.min():+.4f}, {rel.max():+.4f}], max |v_x|/v_ref {vx:.3f}")
        rows.append((rel, vx))
    for rel, vx in rows:
        assert np.all((rel > lo) & (rel < hi))
        assert mlo < rel.mean() < mhi
        assert vx < xmax
    assert len(d) == n and np.all(d[:, 17] == len(grains))
