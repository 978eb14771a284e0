# SPDX-License-Identifier: GPL-3.0-or-later
"""Immersed vaporising droplet: the grains inside the droplet -
absorbed volume (eq. 4.15), grain-droplet force F_p (eq. 4.17), liquid drag
and pressure on the grains, porous grains (thesis 4.3.2).  Case set-up in
dropletcase.py."""

import math
import os

import nscdpost
import numpy as np
import pytest
from dropletcase import (
    DEPTH,
    MU_W,
    RHO,
    RHO_W,
    T_D,
    D,
    difelice_gamma,
    droplet_case,
    held_suspension_case,
    read_droplet,
    water_droplet_case,
)
from foamcase import run

# ---------------------------------------------------------------------------
# Grain-droplet force F_p (eq. 4.17), porous grains (4.3.2)
# ---------------------------------------------------------------------------


def lens_area(R, r, d):
    """Area of the intersection of two discs (radii R, r, centre distance d)."""
    if d >= R + r:
        return 0.0
    if d <= abs(R - r):
        return math.pi * min(R, r) ** 2
    a1 = math.acos((d * d + r * r - R * R) / (2 * d * r))
    a2 = math.acos((d * d + R * R - r * r) / (2 * d * R))
    return (
        r * r * a1
        + R * R * a2
        - 0.5 * math.sqrt((-d + r + R) * (d + r - R) * (d - r + R) * (d + r + R))
    )


@pytest.mark.fast
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
    droplet_case(
        case, env, 8, end_time=0.2, dt=0.01, blowing=False, rho_l=1e8, T_w=T_D, grains=grains
    )
    run("vansFoam", case, env)
    d = read_droplet(case)
    Rf = math.sqrt(d[-1, 5] / (1e8 * math.pi * DEPTH))
    R = d[-1, 9]
    A = math.pi * Rf**2 + math.pi * (0.3 * R0) ** 2 + lens_area(R, 0.25 * R0, R0)
    print(
        f"R/R_f = {R / Rf:.9f}, fixed point R = {math.sqrt(A / math.pi):.12e}, V_p = {d[-1, 12]:.6e}"
    )
    assert abs(R - math.sqrt(A / math.pi)) < 1e-9 * R
    assert abs(d[-1, 12] - (A - math.pi * Rf**2) * DEPTH) < 1e-6 * d[-1, 12]
    assert R > 1.04 * Rf


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
    p = fixed_lattice_bed(
        case, env, h, d, nx, ny, range(ny), Us, rho, mu / rho, extra_coupling=extra
    )
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


@pytest.mark.slow
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
        print(
            f"n = {n}: eps = {eps:.6f}, grad p = {grad:.6g} Pa/m, law {law:.6g}, "
            f"rel {grad / law - 1:+.4f}"
        )
        assert np.allclose(eps_field, eps, rtol=1e-12)
        assert abs(grad / law - 1) < 0.01
        if n == 0.0:
            p0 = p
    # explicit grainPorosity 0: identical to the default
    grad, eps_field, eps, law, p = porous_bed_pressure_gradient(tmp_path / "explicit0", env, 0.0)
    assert np.array_equal(p, p0)


@pytest.mark.fast
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
    water_droplet_case(
        case,
        env,
        dt,
        n,
        grains=[(c, c, DEPTH / 2, dg)],
        write_interval=dt * n / 6,
        nu=1e-9,
        gravity=G,
        extra=f"liquidViscosity {MU_W};\n",
        coupling=f"grainPorosity {porosity};\n",
    )
    if porosity > 0:
        gp = os.path.join(case, "constant", "grainProperties")
        txt = open(gp).read().replace("density 2500;", f"density {(1 - porosity) * 2500};")
        open(gp, "w").write(txt)
        run("grainDeposit", case, env)  # the grain state holds the masses
    run("vansFoam", case, env)
    # liquid fraction of the droplet, 1 - (1 - n) V_p/V (eq. 4.15)
    vp = (dg / 2) ** 2 / (R0**2 + (dg / 2) ** 2)  # V_p/V
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
        print(
            f"t = {t:.4f} s: v = {-v[1]:.6e} m/s, reference {ref:.6e}, rel {-v[1] / ref - 1:+.4f}"
        )
        assert abs(-v[1] / ref - 1) < 0.02
        assert abs(v[0]) < 1e-9 * abs(v[1])


def released_droplet(case, env, dgs, extra=""):
    """Water droplet released at u_d = (5, -2) cm/s at (2D, 2D) (gravity
    9.81, no heat, 6 steps of 5e-4 s, every step written) with free grains
    of diameters dgs at rest (no contacts) at up to four places: three
    inside, the fourth straddling the surface; extra: more dropletProperties.  Returns (case,
    droplet.dat array)."""
    R0, c, dt = D / 2, 2 * D, 5e-4
    at = [(c + 0.3 * R0, c), (c - 0.4 * R0, c + 0.2 * R0), (c, c - 0.5 * R0), (c + R0, c)]
    grains = [(x, y, DEPTH / 2, dg) for (x, y), dg in zip(at, dgs)]
    case = str(case)
    water_droplet_case(
        case,
        env,
        dt,
        6,
        grains=grains,
        write_interval=dt,
        gravity=9.81,
        extra="velocity (0.05 -0.02 0);\n" + extra,
        moving=True,
    )
    run("vansFoam", case, env)
    return case, read_droplet(case)


@pytest.mark.fast
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
    G, dt, n = 9.81, 5e-4, 6
    dgs = [1e-4, 1.5e-4, 2e-4, 2e-4]
    case, d = released_droplet(tmp_path / "momentum", env, dgs)
    # the force on the grains summed (droplet.dat Fg, the log's
    # "droplet-grain force" line) against the droplet's own F_p
    fg = nscdpost.read_step_data(case, "droplet")
    sums = np.column_stack([fg["Fg_x"], fg["Fg_y"]])
    assert len(d) == n and len(sums) == n
    Fp = d[:, 13:15]
    assert np.all(d[:, 17] == 4) and np.all(np.abs(Fp[:, 1]) > 0)
    for k in range(n):
        assert np.allclose(Fp[k], -sums[k], rtol=1e-12, atol=1e-12 * np.abs(Fp[k]).max())
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


@pytest.mark.fast
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
    water_droplet_case(
        case,
        env,
        dt,
        n,
        grains=[(c, y_free, DEPTH / 2, dg)],
        gravity=G,
        nu=1e-9,
        extra=f"velocity (0 {-u} 0);\nliquidViscosity {MU_W};\n",
    )
    open(os.path.join(case, "system", "grainDepositDict"), "a").write(
        f"fixedRow {{ from ({c} {y_fix} {DEPTH / 2}); to ({c} {y_fix} {DEPTH / 2}); diameter {df}; }}\n"
    )
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
    assert abs(F_nopred[1] / F_ref[1] - 1) > 0.2  # the test discriminates
    print(
        f"F_p = {d[-1, 13:15]}, reference {F_ref}, rel {d[-1, 14] / F_ref[1] - 1:+.2e}, "
        f"grain shares {share}, v_free = {gr['U'][0]}"
    )
    assert gr["fixed"][1] and not gr["fixed"][0]
    assert np.linalg.norm(gr["U"][0]) < 1e-3 * u  # held by the contact
    assert abs(d[-1, 14] / F_ref[1] - 1) < 0.01


@pytest.mark.slow
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
    lo, hi, mlo, mhi, xmax = (
        (-0.28, 0.15, -0.12, 0.0, 0.2) if nu_gas > 1e-6 else (-0.08, 0.05, -0.03, 0.0, 0.05)
    )
    rows = []
    for tw, name in nscdpost.time_dirs(case)[1:]:
        gr = nscdpost.read_grains(case, name)
        rel = -gr["U"][:, 1] / v - 1
        vx = np.abs(gr["U"][:, 0]).max() / v
        print(
            f"nu_gas {nu_gas:g}, t = {tw:g} s: {len(grains)} grains, v_ref = {v:.4e} m/s "
            f"(eps_l {eps:.4f}, rho_mix {rho_mix:.1f}), v_y/v_ref - 1 mean {rel.mean():+.4f} "
            f"in [{rel.min():+.4f}, {rel.max():+.4f}], max |v_x|/v_ref {vx:.3f}"
        )
        rows.append((rel, vx))
    for rel, vx in rows:
        assert np.all((rel > lo) & (rel < hi))
        assert mlo < rel.mean() < mhi
        assert vx < xmax
    assert len(d) == n and np.all(d[:, 17] == len(grains))


@pytest.mark.fast
@pytest.mark.parametrize("absorbed", ["carried", "drag"])
def test_carried_grains_move_with_droplet(tmp_path, env, absorbed):
    """absorbedGrains carried (src/dropletCoupling/README.md, "The model"):
    grains fully inside the droplet move with it and count in its mass and
    weight.  A moving droplet (released at u_d = (5, -2) cm/s, gravity on,
    no heat) with three free grains fully inside at rest, no contacts.
    Independent reference: Newton's second law of the combined rigid body
    (liquid + grains), every step,
      (M' + M)(u^{n+1} - u^n)/dt = F_pen + (M' + M) g + depth sum G_i,
    M' = m - rho_f V_f, M = depth sum m_i, G_i the gas force on grain i
    (written states), after the first step, whose impulse also brings the
    grains from rest to u_d: M' (u^1 - u^0) + M u^1 = dt (F_pen + (M' + M) g
    + depth sum G_i); and every grain at the droplet's velocity.
    Bounds: the gas force on the grains is vansCloud's, applied in the NSCD
    step and predicted by the droplet from the last steps (P_i), so the
    grains lag by the unpredicted part: measured 1.4e-4 m/s (2.8e-3 of
    |u|) in the first three steps, 2.3e-5 after; Newton's residual 0.4-3 %
    of M g.  Asserted: lag < 5e-3 |u| (< 1e-3 |u| from step 4), residual
    < 5 % M g.  drag (default): the grains lag the droplet (x = c dt/m ~
    0.03 for these 0.2 mm grains in water): lag 0.033-0.046 m/s, residual
    0.46-9.4 M g, so the same checks fail by far."""
    G, dt, n, dg = 9.81, 5e-4, 6, 2e-4
    case, d = released_droplet(tmp_path / absorbed, env, [dg] * 3, f"absorbedGrains {absorbed};\n")
    assert len(d) == n and np.all(d[:, 17] == 3)
    mEff = d[:, 5] - RHO * d[:, 5] / RHO_W
    M = 3 * 2500 * math.pi * (dg / 2) ** 2 * DEPTH
    u = np.vstack([[0.05, -0.02], d[:, 3:5]])
    states = [nscdpost.read_grains(case, name) for t, name in nscdpost.time_dirs(case)]
    lags = [np.abs(states[k + 1]["U"][:, :2] - u[k + 1]).max() for k in range(n)]
    lag = max(lags)
    newton = []
    for k in range(n):
        lhs = mEff[k] * (u[k + 1] - u[k]) + M * (u[k + 1] - (u[k] if k else 0))
        ext = d[k, 15:17] + (mEff[k] + M) * np.array([0, -G])
        ext = ext + DEPTH * states[k + 1]["Ffluid"][:, :2].sum(axis=0)
        newton.append(np.abs(lhs / dt - ext).max() / (M * G))
    print(f"{absorbed}: grain - droplet velocity {np.array(lags)} m/s")
    print(f"combined-body residual / Mg {np.array(newton)}")
    if absorbed == "carried":
        assert lag < 5e-3 * np.abs(u).max()
        assert max(lags[3:]) < 1e-3 * np.abs(u).max()
        assert max(newton) < 0.05
    else:
        assert lag > 0.1 * np.abs(u).max()
        assert max(newton) > 0.1
