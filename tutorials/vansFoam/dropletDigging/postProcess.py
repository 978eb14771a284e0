#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Post-process the dropletDigging cases (thesis section 4.3.3,
Figures 4.13-4.19).

usage: postProcess.py [-o OUTDIR] [--snap] CASE1 [CASE2 ...]   (cases made by setupCase.py)
       postProcess.py [-o OUTDIR] --cohesion CASE1 [CASE2 ...]  (one T_bed, several
                          COHESION_FACTOR: cohesion.json, dropletDigging_cohesion.png)

Reads per case `case.json` (setupCase.py), the droplet history
`postProcessing/droplet/<start>/droplet.dat` (src/dropletCoupling: time x y u v m
mdot Q_f Q_p R depth Vdot V_p ...; 2D: m, mdot, Q, Vdot over the mesh depth l)
and vansFoam's run-time files `postProcessing/heatBudget/<start>/heatBudget.dat`
(per step the mean grain temperature, the energy E = rho Cp sum(eps T V) +
sum(m c T) and the budget terms) and `postProcessing/vapour/<start>/vapour.dat`
(psi range); a run continued from its writes (e.g. with a later endTime)
writes a new <start> folder, the parts are joined (nscdpost.read_droplet_history,
nscdpost.heat_history, nscdpost.read_step_data).  Why a run stopped early
comes from `postProcessing/runEnd/<start>/runEnd` (the solver's reason and
error message, nscdpost.read_run_end); none of it from the log.  Writes
OUTDIR/results.json (default: this directory):

- `bed_temperature` [C] (list), `final_depth` [m] (list, depth of the droplet
  centre below its initial position at the end of the run = penetration of
  its lowest point below the bed surface, since it starts resting on it),
  `final_time` [s], `mean_velocity` [m/s] (final_depth/final_time),
  `stopped` (per case None or why it stopped early);
- `cases[<T>]`: `time` [s], `depth` [m], `velocity` [m/s] (downwards
  positive), `mass` [kg], `mdot` [kg/s], `Q_f`, `Q_p`, `Q_film` [W] (L mdot =
  Q_f + Q_p + Q_film),
  `mean_grain_temperature` [K] (time series on `time`), `lifetime` [s]
  (instant lifetime m/mdot, Figure 4.17), `vapour_velocity` [m/s] (U_v =
  Vdot/(2 pi R l), the mean radial vapour velocity at the droplet surface),
  `U_mf` [m/s] (measured in vansFoam by umf.py when the case was set up
  with it, case.json `U_mf_measured`; else Ergun, `ergun_umf`, at the bed's
  mean void fraction; `U_mf_source` says which, `U_mf_ergun` is Ergun's) and
  `fluidisation_number` (time mean of U_v / U_mf), `energy_defect` (relative
  closure of the energy budget, `energy_budget`), `stopped` (None, or why
  the run stopped early, `stop_reason`), `bottom_reached_time` [s] (first
  time the droplet rests on the bottom wall, wall reaction > 0; None if
  never), `psi_max` (largest vapour fraction, vapour.dat `psiMax`),
  `Re_mf` (rho U_mf d/eta) and `ergun_inertial_fraction` (share of
  Ergun's inertial term in the pressure gradient at U_mf), `summary` (depth
  at 0.1/0.3/0.6/1.0/1.5 s, end sinking speed, U_v/U_mf over 0.1-0.3 s, R,
  grains inside, m/mdot at 0.01 s and at the end) and `bed` (per written time,
  `bed_diagnostics`: superficial gas speed in the bed next to the droplet
  over U_mf, ejected grains, cohesive grains next to the droplet) and
  `forces` (`force_balance`: vertical forces over m_0 g, Figure 4.18, the
  eq. 4.17 residual and the shares of the weight carried by gas and grains
  over the last 0.2 s);
- with `--snap`: per case `snap_T<T>_<time>s.png` at the written times
  nearest 0.3 s, half the run and the end (`snapshot`);
- the plots `dropletDigging_finalDepth.png` (Figure 4.13),
  `dropletDigging_depth.png` (4.14, h/D against t/t_ff),
  `dropletDigging_velocity.png` (4.15, u t_ff/R against t/t_ff),
  `dropletDigging_grainTemperature.png` (4.16),
  `dropletDigging_lifetime.png` (4.17), `dropletDigging_forces.png` (4.18:
  gas and grain forces over m_0 g, upward) and `dropletDigging_heat.png`
  (4.19: Q_f and Q_p + Q_film over the first step's L mdot).

The thesis curves are not digitised (the thesis text gives no table): the
final-depth plot marks what section 4.3.3 states in words, the regime
thresholds 350 C and 500 C and the maximum depth near 400 C.

t_ff = sqrt(2 R_0/g) is the free-fall time over the droplet radius (the
thesis' time scale, section 4.3.3); velocities are scaled by R_0/t_ff.
"""

import json
import math
import os
import re
import sys

import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))

# the figures (thesis Figures 4.13-4.19), a sibling module loaded by path so
# that tests loading this file by path (nscdpost.load_module) find it too
figures = nscdpost.load_module("dropletDigging_figures", os.path.join(here, "figures.py"))
G = figures.G

# droplet.dat columns (src/dropletCoupling/README.md)
COL = dict(
    t=0,
    x=1,
    y=2,
    u=3,
    v=4,
    m=5,
    mdot=6,
    Qf=7,
    Qp=8,
    R=9,
    depth=10,
    Vdot=11,
    Vp=12,
    Fp_x=13,
    Fp_y=14,
    Fpen_x=15,
    Fpen_y=16,
    nGrainsIn=17,
    Fw_x=18,
    Fw_y=19,
    S_x=20,
    S_y=21,
    Fc_x=22,
    Fc_y=23,
    Q_film=24,
)


def read_droplet(case):
    """droplet.dat of the case as an (n, >=12) array, the parts of a
    restarted run joined (nscdpost.read_droplet_history); raises
    FileNotFoundError."""
    return nscdpost.read_droplet_history(case)


def read_heat(case):
    """Per time step of the run: dict of arrays `time` [s],
    `grain_T` [K] (mean grain temperature), `E` [J] (fluid + grain energy of
    the "heat:" line), `budget` (n, 5) [J] (fluid boundary, advected,
    sources, grain walls, fixed grains of the "heat budget:" line)
    (nscdpost.heat_history: postProcessing/heatBudget/<start>/heatBudget.dat
    of the run and its continuations joined)."""
    h = nscdpost.heat_history(case)
    return {"time": h["time"], "grain_T": h["grain_T"], "E": h["E"], "budget": h["budget"]}


def energy_budget(case, info=None):
    """Energy budget of droplet + gas + grains + walls over the run.

    Between the end of the first step and the end of the run,
        (E_N - E_1) + L (m_1 - m_N)
          = sum_{k=2..N} [fluid boundary + advected + grain walls + fixed grains
                          + rho Cp T_d Vdot dt]_k
    E = rho Cp sum(eps T V) + sum(m c T) (vansFoam "heat:" line), L (m_1 - m_N)
    the heat the droplet took (eq. 4.16), the bracket the heat through the
    walls and the outlet (gas and grain-wall contact conduction) and the
    enthalpy rho Cp T_d Vdot dt of the vapour released at T_d (the droplet's
    source in the energy equation, src/dropletCoupling/README.md).
    Also checks the droplet's heat against the solver's own source integral:
    sources - rho Cp T_d Vdot dt = -(Q_f + Q_p) dt per step.

    Returns dict: `defect` [J], `relative` (defect / droplet heat),
    `droplet_heat` [J], `source_mismatch` (max relative difference of the
    two integrations of the droplet sink).  Raises ValueError if heatBudget.dat and
    droplet.dat do not have one line per step."""
    if info is None:
        info = json.load(open(os.path.join(case, "case.json")))
    d = read_droplet(case)
    lg = read_heat(case)
    n = len(d)
    if len(lg["E"]) != n or not np.allclose(lg["time"], d[:, 0], rtol=1e-5, atol=1e-12):
        raise ValueError(f"{case}: {n} droplet.dat lines but {len(lg['E'])} heatBudget.dat rows")
    rhoCp = info["rho"] * info["Cp"]
    Td, L = info["T_d"], info["latent_heat"]
    dts = np.diff(np.concatenate(([0.0], d[:, 0])))
    vap = rhoCp * Td * d[:, COL["Vdot"]] * dts
    b = lg["budget"]
    ext = np.sum(b[1:, 0] + b[1:, 1] + b[1:, 3] + b[1:, 4] + b[1:, 5] + vap[1:])
    heat = L * (d[0, COL["m"]] - d[-1, COL["m"]])
    defect = (lg["E"][-1] - lg["E"][0]) + heat - ext
    sink = -(d[:, COL["Qf"]] + d[:, COL["Qp"]]) * dts
    mism = np.max(np.abs((b[:, 2] - vap) - sink) / np.abs(sink))
    return {
        "defect": float(defect),
        "relative": float(abs(defect) / heat),
        "droplet_heat": float(heat),
        "source_mismatch": float(mism),
    }


def ergun_coefficients(d, eps, rho_f, mu):
    """Ergun's law (Ergun 1952) as -dp/dx = a U^2 + b U for the superficial
    speed U [m/s]: a = 1.75 rho_f (1-eps)/(eps^3 d) (inertial), b = 150 mu
    (1-eps)^2/(eps^3 d^2) (viscous).  d [m], mu [Pa s], rho_f [kg/m^3]."""
    phi = 1 - eps
    return 1.75 * rho_f * phi / (eps**3 * d), 150 * mu * phi**2 / (eps**3 * d**2)


def ergun_umf(d, eps, rho_p, rho_f=1.204, mu=2e-5, g=G, weight_fraction=None):
    """Minimum fluidisation velocity [m/s] from Ergun's law (Ergun 1952,
    Chem. Eng. Prog. 48:89): the pressure drop of the bed balances its
    buoyant weight,
        150 mu (1-eps)^2 U/(eps^3 d^2) + 1.75 rho_f (1-eps) U^2/(eps^3 d)
            = phi_w (rho_p - rho_f) g,
    with phi_w = weight_fraction (solid volume per bed volume that carries
    the weight; default 1 - eps).  d [m] grain diameter, eps fluid fraction
    seen by the gas, rho_p [kg/m^3] grain density.  Small Re: Carman-Kozeny
    U = phi_w (rho_p - rho_f) g eps^3 d^2 / (150 mu (1-eps)^2)."""
    phi = 1 - eps
    pw = phi if weight_fraction is None else weight_fraction
    a, b = ergun_coefficients(d, eps, rho_f, mu)
    c = pw * (rho_p - rho_f) * g
    return float((-b + math.sqrt(b * b + 4 * a * c)) / (2 * a))


def bed_void_fraction(case, info):
    """Mean gas fraction eps of the bed at the start (the cells fully below
    the bed top minus one grain diameter, away from the walls by one
    grain), from <first write time>/voidFraction; None if not written."""
    times = [name for t, name in nscdpost.time_dirs(case) if t > 0]
    for t in times:
        p = os.path.join(case, t, "voidFraction")
        if os.path.isfile(p):
            eps = np.asarray(nscdpost.read_scalar_field(p))
            nx, ny = info["cells"]  # uniform mesh (setupCase.py)
            xc = (np.arange(nx) + 0.5) * info["width"] / nx
            yc = (np.arange(ny) + 0.5) * info["height"] / ny
            X, Y = np.meshgrid(xc, yc)
            cc = np.column_stack((X.ravel(), Y.ravel()))
            sel = (
                (cc[:, 1] < info["bed_top"] - 2 * info["grain_diameter"])
                & (cc[:, 1] > 2 * info["grain_diameter"])
                & (cc[:, 0] > info["grain_diameter"])
                & (cc[:, 0] < info["width"] - info["grain_diameter"])
            )
            return float(np.mean(eps[sel]))
    return None


def stop_reason(case):
    """None if the run and its continuations reached their endTime (or were
    stopped by a signal), else why one stopped: the first line of its FOAM
    FATAL ERROR message (e.g. the droplet centre left the mesh), from the
    solver's postProcessing/runEnd/<start>/runEnd (nscdpost.read_run_end;
    a run that never ended: killed, or still running)."""
    for r in nscdpost.read_run_end(case):
        if r["reason"] == "fatalError":
            return r["message"][0] if r["message"] else "FOAM FATAL ERROR"
        if r["reason"] == "running":
            return f"did not end (killed, or still running) after t = {r['time']:g} s"
    return None


def psi_max(case):
    """Largest vapour fraction psi over the run, restarts joined, from
    postProcessing/vapour/<start>/vapour.dat (the values of vansFoam's
    "vapour:" log line, psiEqn.H); None without it."""
    try:
        v = nscdpost.read_step_data(case, "vapour")["psiMax"]
    except FileNotFoundError:
        return None
    return float(v.max()) if len(v) else None


def cohesion_threshold(case):
    """psi^0 of couplingProperties `cohesion { vapourThreshold }` (eq. 4.18);
    None without cohesion."""
    txt = open(os.path.join(case, "constant", "couplingProperties")).read()
    m = re.search(r"vapourThreshold\s+([0-9.eE+-]+)", txt)
    return float(m.group(1)) if m else None


def bed_diagnostics(case, info, d, umf):
    """Bed-side digging diagnostics at every written time t > 0:

    - `ring_speed` [m/s]: mean superficial gas speed eps |u| over the cells
      with R + dx < r < R + 3 dx from the droplet centre, below its equator
      (y < y_d) and below the initial bed top minus dx (in the bed), dx the
      cell size; `ring_radial` [m/s]: mean outward radial superficial flux
      eps u.r_hat over the same cells; `ring_speed_over_Umf`,
      `ring_radial_over_Umf`: both over U_mf (`U_mf` above);
    - `ejected`: grains outside the droplet (r > R) whose centre is more than
      5 d above the initial bed surface where it lies (d the mean grain
      diameter; chimney / ejection), `above_top_1d`: the same count above
      the surface + d (crater rim), `highest_above_surface` [m]: the
      largest height of a grain centre outside the droplet above that
      surface (`initial_surface`, `above_surface`: the surface of the
      grains at t = 0, not the bed top of case.json, the 98th percentile
      of the grain tops, which on a bed of ~180 grains across lies some
      rows below its surface);
    - `cohesive_near`: fraction of the grains with R < r < R + 2 d whose cell
      has psi < psi^0 (cohesive, eq. 4.18; psi of the cell holding the grain
      centre, as vansCloud evaluates it; per grain, not per contact:
      contacts are not written), `near_grains` their number.
    Uniform mesh (setupCase.py).  d: droplet.dat array.  Returns a dict of
    lists on `time`."""
    nx, ny = info["cells"]
    W, H = info["width"], info["height"]
    dx = W / nx
    xc = (np.arange(nx) + 0.5) * dx
    yc = (np.arange(ny) + 0.5) * H / ny
    X, Y = (a.ravel() for a in np.meshgrid(xc, yc))
    top, dg = info["bed_top"], info["grain_diameter"]
    psi0 = cohesion_threshold(case)
    surface = initial_surface(initial_grains(case), W)
    out = {
        k: []
        for k in (
            "time",
            "ring_speed",
            "ring_radial",
            "ring_speed_over_Umf",
            "ring_radial_over_Umf",
            "ejected",
            "above_top_1d",
            "highest_above_surface",
            "cohesive_near",
            "near_grains",
        )
    }
    for t, tn in nscdpost.time_dirs(case):
        if t <= 0 or not os.path.isfile(os.path.join(case, tn, "voidFraction")):
            continue
        k = int(np.argmin(np.abs(d[:, 0] - t)))
        xd, yd, R = d[k, COL["x"]], d[k, COL["y"]], d[k, COL["R"]]
        U = np.asarray(nscdpost.read_internal_field(os.path.join(case, tn, "U")))[:, :2]
        eps = np.asarray(nscdpost.read_internal_field(os.path.join(case, tn, "voidFraction")))
        psi = np.asarray(nscdpost.read_internal_field(os.path.join(case, tn, "psi")))
        r = np.hypot(X - xd, Y - yd)
        ring = (r > R + dx) & (r < R + 3 * dx) & (Y < yd) & (Y < top - dx)
        if ring.any():
            us = eps[ring] * np.linalg.norm(U[ring], axis=1)
            nr = np.column_stack((X[ring] - xd, Y[ring] - yd)) / r[ring][:, None]
            ur = eps[ring] * np.sum(U[ring] * nr, axis=1)
            sp, rad = float(np.mean(us)), float(np.mean(ur))
        else:
            sp = rad = float("nan")
        g = nscdpost.read_grains(case, tn)
        gx, gy = g["x"][:, 0], g["x"][:, 1]
        rg = np.hypot(gx - xd, gy - yd)
        near = (rg > R) & (rg < R + 2 * dg)
        if psi0 is not None and near.any():
            ci = np.clip((gx / dx).astype(int), 0, nx - 1) + nx * np.clip(
                (gy / (H / ny)).astype(int), 0, ny - 1
            )
            coh = float(np.mean(psi[ci[near]] < psi0))
        else:
            coh = None
        out["time"].append(float(t))
        out["ring_speed"].append(sp)
        out["ring_radial"].append(rad)
        out["ring_speed_over_Umf"].append(sp / umf)
        out["ring_radial_over_Umf"].append(rad / umf)
        h = above_surface(surface, gx, gy)[rg > R]
        out["ejected"].append(int(np.sum(h > 5 * dg)))
        out["above_top_1d"].append(int(np.sum(h > dg)))
        out["highest_above_surface"].append(float(h.max()) if h.size else float("nan"))
        out["cohesive_near"].append(coh)
        out["near_grains"].append(int(np.sum(near)))
    return out


def initial_grains(case):
    """Centres `x` (n, 3) [m] and diameters `d` [m] of the grains at t = 0
    (0/grainState.h5, the state the case starts from; its 0/lagrangian
    may hold no fields)."""
    path = os.path.join(case, "0", "grainState.h5")
    return {"x": nscdpost.read_h5(path, "positions"), "d": 2 * nscdpost.read_h5(path, "radii")}


def initial_surface(g, width):
    """The bed surface of grains g (`x`, `d`: initial_grains) across a cell of
    width [m]: (edges, height), the highest grain top y + d/2 [m] in each
    of the columns of width ~2 d_max between the side walls (a column
    without a grain interpolated from its neighbours), for
    `above_surface`."""
    x, y, d = g["x"][:, 0], g["x"][:, 1], g["d"]
    n = max(1, int(width / (2 * d.max())))
    edges = np.linspace(0, width, n + 1)
    col = surface_column(edges, x)
    height = np.full(n, -np.inf)
    np.maximum.at(height, col, y + 0.5 * d)
    empty = ~np.isfinite(height)
    if empty.all():
        raise ValueError("initial_surface: no grains")
    height[empty] = np.interp(np.flatnonzero(empty), np.flatnonzero(~empty), height[~empty])
    return edges, height


def above_surface(surface, x, y):
    """Height [m] of the points (x, y) above the surface of
    `initial_surface` in their column (negative below it)."""
    edges, height = surface
    return y - height[surface_column(edges, x)]


def surface_column(edges, x):
    """Column of `initial_surface` (bounded by edges [m]) holding each
    abscissa x [m]; those beyond the side walls in the end columns."""
    return np.clip(np.searchsorted(edges, x, side="right") - 1, 0, len(edges) - 2)


def summary(d, uv, umf, times=(0.1, 0.3, 0.6, 1.0, 1.5)):
    """Table figures of a run (README.md tables): `depth_at` [m] at `times`
    reached, `sinking_speed_end` [m/s] (linear fit of the depth over the last
    0.2 s, or the last 30 % of a shorter run), `Uv_over_Umf_01_03` (mean U_v
    over 0.1-0.3 s over U_mf; None if not reached or no U_mf), `R_end` [m],
    `grains_inside_end`, `lifetime_start` (m/mdot at 0.01 s) and
    `lifetime_end` [s], `mass_ratio_end` (m/m_0).  d: droplet.dat array,
    uv [m/s]: U_v on d's steps, umf [m/s] or None."""
    t, depth = d[:, 0], d[:, COL["depth"]]
    R, m, mdot = d[:, COL["R"]], d[:, COL["m"]], d[:, COL["mdot"]]
    out = {
        "depth_at": {f"{x:g}": float(np.interp(x, t, depth)) for x in times if x <= t[-1] + 1e-9}
    }
    win = t >= t[-1] - min(0.2, 0.3 * t[-1])
    out["sinking_speed_end"] = (
        float(np.polyfit(t[win], depth[win], 1)[0]) if win.sum() > 2 else None
    )
    w = (t >= 0.1) & (t <= 0.3)
    out["Uv_over_Umf_01_03"] = float(np.mean(uv[w]) / umf) if (w.any() and umf) else None
    out["R_end"] = float(R[-1])
    out["grains_inside_end"] = int(d[-1, 17]) if d.shape[1] > 17 else None
    out["lifetime_start"] = float(np.interp(0.01, t, m / mdot))
    out["lifetime_end"] = float(m[-1] / mdot[-1])
    out["mass_ratio_end"] = float(m[-1] / m[0])
    return out


def force_balance(d, window=0.2):
    """Vertical forces on the droplet (thesis Figure 4.18), upward positive,
    over the initial weight m_0 g, per droplet.dat line: `weight` (-m g),
    `fluid` (S_y: the gas on the droplet's surface, pressure and
    penalisation, with the wall reaction while the droplet rests on a wall;
    src/dropletCoupling/README.md), `grains` (F_p + F_c: the grains inside
    the droplet and, with the capillary barrier, those pressed on its
    surface), `net` (their sum).  Eq. 4.17 holds on these written forces:
    `momentum_residual` = rms(m du_y/dt - net)/(m_0 g) over the steps.
    `support`: the shares of the weight carried by the gas and by the grains,
    mean(S_y)/mean(m g) and mean(F_p + F_c)/mean(m g) over the last
    `window` s (all of a shorter run).  d: droplet.dat array (25 columns;
    older files without F_c: 0)."""
    t, m, v = d[:, 0], d[:, COL["m"]], d[:, COL["v"]]
    w0 = m[0] * G
    grains = d[:, COL["Fp_y"]] + (d[:, COL["Fc_y"]] if d.shape[1] > COL["Fc_y"] else 0)
    fluid = d[:, COL["S_y"]]
    net = -m * G + fluid + grains
    acc = np.diff(v) / np.diff(t)
    resid = float(np.sqrt(np.mean((m[1:] * acc - net[1:]) ** 2)) / w0) if len(t) > 1 else None
    late = t >= t[-1] - window
    mg = np.mean(m[late] * G)
    return {
        "weight": (-m * G / w0).tolist(),
        "fluid": (fluid / w0).tolist(),
        "grains": (grains / w0).tolist(),
        "net": (net / w0).tolist(),
        "momentum_residual": resid,
        "support": {
            "fluid": float(np.mean(fluid[late]) / mg),
            "grains": float(np.mean(grains[late]) / mg),
        },
    }


def snapshot(case, time_name, out):
    """PNG out of the grains of the case at one written time with the
    droplet at the nearest step of droplet.dat (figures.plot_snapshot)."""
    info = json.load(open(os.path.join(case, "case.json")))
    d = read_droplet(case)
    t = float(time_name)
    k = int(np.argmin(np.abs(d[:, 0] - t)))
    droplet = (d[k, COL["x"]], d[k, COL["y"]], d[k, COL["R"]])
    figures.plot_snapshot(nscdpost.read_grains(case, time_name), droplet, t, info, out)


def case_results(case):
    """Results of one case (the `cases[<T>]` entry of results.json, module
    docstring): the droplet history of droplet.dat, the mean grain
    temperature of the log on its steps, the bed's void fraction and U_mf
    with the Ergun figures and `bed_diagnostics` (when voidFraction is
    written), `psi_max`, `summary`, `forces`, `stopped`,
    `bottom_reached_time` and `energy_defect` (printed instead when the
    budget is not available).  Returns (info, results): info the case.json
    of setupCase.py.  Raises OSError or ValueError without droplet
    history."""
    info = json.load(open(os.path.join(case, "case.json")))
    d = read_droplet(case)
    lg = read_heat(case)
    depth = d[:, COL["depth"]]
    mdot = d[:, COL["mdot"]]
    m = d[:, COL["m"]]
    R = d[:, COL["R"]]
    with np.errstate(divide="ignore"):
        life = np.where(mdot > 0, m / np.where(mdot > 0, mdot, 1), np.inf)
    uv = d[:, COL["Vdot"]] / (2 * np.pi * R * info["depth_l"])
    res = {
        "time": d[:, 0].tolist(),
        "depth": depth.tolist(),
        "velocity": (-d[:, COL["v"]]).tolist(),
        "mass": m.tolist(),
        "mdot": mdot.tolist(),
        "Q_f": d[:, COL["Qf"]].tolist(),
        "Q_p": d[:, COL["Qp"]].tolist(),
        "Q_film": (
            d[:, COL["Q_film"]] if d.shape[1] > COL["Q_film"] else np.zeros(len(d))
        ).tolist(),
        "lifetime": life.tolist(),
        "vapour_velocity": uv.tolist(),
    }
    gT = (
        np.interp(d[:, 0], lg["time"], lg["grain_T"])
        if len(lg["time"])
        else np.full(len(d), np.nan)
    )
    res["mean_grain_temperature"] = gT.tolist()
    eps = bed_void_fraction(case, info)
    mu = info.get("mu", 2e-5)  # gas viscosity of the case (similarity scaling)
    if eps is not None:
        ergun = ergun_umf(
            info["grain_diameter"],
            eps,
            info["grain_density"],
            rho_f=info["rho"],
            mu=mu,
            weight_fraction=info.get("bed_weight_fraction"),
        )
        umf = info.get("U_mf_measured") or ergun
        res["bed_void_fraction"] = eps
        res["U_mf"] = umf
        res["U_mf_source"] = "measured (umf.py)" if info.get("U_mf_measured") else "Ergun"
        res["U_mf_ergun"] = ergun
        res["fluidisation_number"] = float(np.mean(uv[1:]) / umf) if len(uv) > 1 else None
        res["Re_mf"] = info["rho"] * umf * info["grain_diameter"] / mu
        a, b = ergun_coefficients(info["grain_diameter"], eps, info["rho"], mu)
        res["ergun_inertial_fraction"] = a * umf / (a * umf + b)
        res["bed"] = bed_diagnostics(case, info, d, umf)
    res["psi_max"] = psi_max(case)
    res["summary"] = summary(d, uv, res.get("U_mf"))
    res["forces"] = force_balance(d)
    res["stopped"] = stop_reason(case)
    # droplet on the bottom wall (wall contact of src/dropletCoupling,
    # droplet.dat Fw_y > 0): first time, None if never
    on_wall = np.nonzero(d[:, 19] > 0)[0] if d.shape[1] > 19 else []
    res["bottom_reached_time"] = float(d[on_wall[0], 0]) if len(on_wall) else None
    try:
        res["energy_defect"] = energy_budget(case, info)["relative"]
    except (ValueError, FileNotFoundError) as e:
        print("energy budget not available:", e)
    return info, res


def case_snapshots(case, T, outdir):
    """`--snap`: `snapshot` PNGs snap_T<T>_<time>s.png in outdir at the
    written times t > 0 of the case nearest 0.3 s, half the run and its end."""
    tn = [(t, n) for t, n in nscdpost.time_dirs(case) if t > 0]
    if tn:
        pick = {min(tn, key=lambda a: abs(a[0] - x))[1] for x in (0.3, 0.5 * tn[-1][0], tn[-1][0])}
        for n in sorted(pick, key=float):
            snapshot(case, n, os.path.join(outdir, f"snap_T{T:g}_{n}s.png"))


def case_line(T, r):
    """The log line of one case: final depth, first-step mdot, mean U_v,
    U_mf, energy defect and, for a run that stopped early, why.  T [C]: bed
    temperature, r: its `case_results`."""
    return (
        f"T_bed {T:g} C: final depth {r['depth'][-1] * 1e3:.3f} mm, mdot(first step) "
        f"{r['mdot'][0]:.3e} kg/s, U_v mean {np.mean(r['vapour_velocity'][1:]):.3g} m/s, "
        f"U_mf {r.get('U_mf', float('nan')):.3g} m/s, energy defect "
        f"{r.get('energy_defect', float('nan')):.2e}"
        + (f", STOPPED at t = {r['time'][-1]:.3g} s: {r['stopped']}" if r["stopped"] else "")
    )


def read_cases(cases, outdir, snap):
    """`case_results` of each case in the order given (a relative path is
    taken from the working directory; a case without droplet history is
    skipped with a message), one log line per case (`case_line`) and, with
    snap, its snapshots (`case_snapshots`).  Returns (res, data): res the
    results.json dict before sorting (`bed_temperature`, `final_depth`,
    `cases`, `final_time`, `stopped`; `grain_diameter` and `grains` of the
    first case), data the list of (T, info, results) per case."""
    res = {"bed_temperature": [], "final_depth": [], "cases": {}}
    data = []
    for c in cases:
        c = c if os.path.isabs(c) else os.path.join(os.getcwd(), c)
        try:
            info, r = case_results(c)
        except (OSError, ValueError) as e:
            print(f"{c}: skipped, no droplet history ({e})")
            continue
        T = info["bed_temperature_C"]
        res["bed_temperature"].append(T)
        res["final_depth"].append(r["depth"][-1])
        res.setdefault("final_time", []).append(r["time"][-1])
        res.setdefault("stopped", []).append(r["stopped"])
        res["cases"][f"{T:g}"] = r
        data.append((T, info, r))
        if snap:
            case_snapshots(c, T, outdir)
        print(case_line(T, r))
    if data:
        res["grain_diameter"] = data[0][1]["grain_diameter"]
        res["grains"] = data[0][1]["grains"]
    return res, data


def sort_by_bed_temperature(res, data):
    """Sorts the per-case lists of res (`bed_temperature`, `final_depth`,
    `final_time`, `stopped`) by bed temperature, adds `mean_velocity` [m/s]
    (final depth / final time) and returns data in the same order."""
    order = np.argsort(res["bed_temperature"])
    res["bed_temperature"] = [res["bed_temperature"][i] for i in order]
    for key in ("final_depth", "final_time", "stopped"):
        res[key] = [res[key][i] for i in order]
    # mean digging velocity over the run [m/s] (final depth / final time)
    res["mean_velocity"] = [h / t for h, t in zip(res["final_depth"], res["final_time"])]
    return [data[i] for i in order]


def write_results(res, outdir):
    """outdir/results.json (indent 1) and the final log line (bed
    temperature, final depth per case)."""
    with open(os.path.join(outdir, "results.json"), "w") as f:
        json.dump(res, f, indent=1)
    print(
        "bed temperature [C], final depth [m]:",
        list(zip(res["bed_temperature"], res["final_depth"])),
    )


def main(cases, outdir=here, snap=False):
    """Post-processes the cases into outdir (module docstring): reads each
    case (`read_cases`), sorts them by bed temperature, draws Figures
    4.13-4.19 and writes results.json.  Returns the results.json dict."""
    res, data = read_cases(cases, outdir, snap)
    data = sort_by_bed_temperature(res, data)
    figures.plot_final_depth(res, data, outdir)
    figures.plot_time_series(data, outdir)
    figures.plot_forces(data, outdir)
    figures.plot_heat(data, outdir)
    write_results(res, outdir)
    return res


def cohesion_bond(info):
    """Granular Bond number of a case's cohesion: F_c^0 over the weight per
    unit depth of a disc of the reference grain (the similarity scaling's
    d_ref, else the bed's mean diameter) of density rho_s (Table 4.2's bed:
    10.0 at F_c^0 = 7.5e-4 N/m)."""
    d = info.get("similarity_reference_diameter") or info["grain_diameter"]
    scale = info["grain_diameter"] / d if info.get("similarity_reference_diameter") else 1.0
    return info["cohesion_force"] / scale / (info["grain_density"] * G * math.pi * d * d / 4)


def cohesion_sweep(cases, outdir=here):
    """`--cohesion`: cases at one bed temperature and different cohesion
    (Allrun COHESION_FACTOR): outdir/cohesion.json (per case `bond`,
    `cohesion_factor`, `time`, `depth`, `summary`) and
    dropletDigging_cohesion.png.  Returns the dict."""
    out, data = {"cases": []}, []
    for c in cases:
        info, r = case_results(c)
        bond = cohesion_bond(info)
        data.append((bond, info, r))
        out["cases"].append(
            {
                "case": os.path.relpath(c, outdir),
                "bond": bond,
                "cohesion_factor": info.get("cohesion_factor"),
                "bed_temperature_C": info["bed_temperature_C"],
                "time": r["time"][::10],
                "depth": r["depth"][::10],
                "summary": r["summary"],
                "support": r["forces"].get("support"),
            }
        )
        print(
            f"{c}: Bo {bond:.3g}, final depth {r['depth'][-1] * 1e3:.3f} mm at {r['time'][-1]:.3g} s"
        )
    figures.plot_cohesion_sweep(data, outdir)
    with open(os.path.join(outdir, "cohesion.json"), "w") as f:
        json.dump(out, f, indent=1)
    return out


if __name__ == "__main__":
    args = sys.argv[1:]
    out = here
    if args[:1] == ["-o"]:
        out, args = args[1], args[2:]
    if args[:1] == ["--cohesion"]:
        cohesion_sweep(args[1:], out)
        sys.exit(0)
    snap = "--snap" in args
    main([a for a in args if a != "--snap"], out, snap)
