#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""packedBedHeat post-processing: the bed's Nusselt number measured from the
air side, as in a steady packed-bed heat-transfer experiment, against the
closure the run used (results.json, packedBedHeat.png).

usage: postProcess.py CASEDIR [CASEDIR ...]     one per inflow velocity:
                                                results.json, packedBedHeat.png
       postProcess.py --mesh CASEDIR [...]      one Re, several axial cell
                                                sizes: results_mesh.json,
                                                packedBedHeat_mesh.png

Per case (bed.json written by setupCase.py and postProcessing/):
  Q      = rho Cp U_s A (T_out - T_in)       heat picked up by the air [W],
           T_in, T_out the flux-weighted (mixed-cup) temperatures of the
           inlet and outlet patches (surfaceFieldValue), last step;
  dT_lm  = (dT_in - dT_out)/ln(dT_in/dT_out), dT = T_p - T  (log-mean
           grain-to-air temperature difference, plug flow);
  h      = Q/(S dT_lm), S = sum pi d^2 the grain surface (= a_s V_bed);
  Nu     = h d/k;   Re = U_s d/nu (superficial);
  eps    = void fraction of the bed core, from the grains (exact sphere
           slices): between one diameter above the floor and one diameter
           below the bed surface (where the plane solid fraction falls to
           half the core's); mesh-independent;
  correlation: the run's heatTransferModel at (eps, Re_s) (written here
           independently, as tests/cases/test_nusselt.py), Gunn (1978) and
           Wakao & Kaguei (1982) for comparison.
Diagnostic: the closure as vansFoam applies it, averaged over the grains
(each grain's gathered void fraction and Reynolds number), separates the
mapping effects (closure mean vs correlation at the bed's eps and U_s) from
the temperature-field effects (measured vs closure mean).
Checks printed per case: the steady state (T_out over the last flow-through
time), the energy balance Q vs the heat the grains gave (heatBudget.dat)
and the grain temperature drift (the grains are a finite, very large heat
capacity).
"""

import json
import math
import os
import re
import sys

import nscdpost
import numpy as np
from correlations import nusselt_difelice_colburn as nu_difelice_colburn
from correlations import nusselt_gunn as nu_gunn
from correlations import nusselt_ranz_marshall as nu_ranz_marshall
from correlations import nusselt_wakao_kaguei as nu_wakao

here = os.path.dirname(os.path.abspath(__file__))

# closures: Re is the superficial Reynolds number U_s d/nu
MODELS = {"DiFeliceColburn": nu_difelice_colburn, "Gunn": nu_gunn, "RanzMarshall": nu_ranz_marshall}


# ---- case reading --------------------------------------------------------------


def read_internal(path):
    """Internal scalar field; a uniform field is expanded to the cell count."""
    f = nscdpost.read_internal_field(path)
    if f.ndim == 0:
        n = int(
            re.search(
                r"\n(\d+)\s*\n",
                open(
                    os.path.join(os.path.dirname(path), "..", "constant", "polyMesh", "owner")
                ).read(),
            ).group(1)
        )
        return np.full(n, float(f))
    return f


def surface_series(case, name):
    path = os.path.join(case, "postProcessing", name, "0", "surfaceFieldValue.dat")
    rows = [line.split() for line in open(path) if line.strip() and not line.startswith("#")]
    return np.array(rows, dtype=float)


def heat_steps(case):
    """(time, dt, grain mean T, exchanged Q into the grains [J]) per step,
    from postProcessing/heatBudget/<start>/heatBudget.dat (the values of
    the log's "heat:" line; nscdpost.heat_history)."""
    h = nscdpost.heat_history(case)
    return np.column_stack([h["time"], h["dt"], h["grain_T"], h["Q"]])


def solid_fraction_profile(y, yc, d, A):
    """Solid fraction of the horizontal plane at heights y (exact for spheres
    of diameters d centred at heights yc in a column of cross-section A)."""
    r = 0.5 * d
    z = y[:, None] - yc[None, :]
    return np.sum(np.pi * np.clip(r**2 - z**2, 0, None), axis=1) / A


def slab_solid_volume(y1, y2, yc, d):
    """Grain volume between the planes y1 < y2 (exact sphere slices)."""
    r = 0.5 * d
    a = np.clip(y1 - yc, -r, r)
    b = np.clip(y2 - yc, -r, r)
    return float(np.sum(np.pi * (r**2 * (b - a) - (b**3 - a**3) / 3)))


def bed_void_fraction(yc, d, A, y0):
    """Void fraction of the bed core [y0 + d, y_top - d], y_top the height
    where the plane solid fraction falls below half the core's; and y_top."""
    dm = float(np.mean(d))
    y = np.linspace(y0, yc.max() + dm, 4000)
    prof = solid_fraction_profile(y, yc, d, A)
    top = y0 + 4 * dm
    for _ in range(5):
        phi = slab_solid_volume(y0 + dm, top - dm, yc, d) / (A * (top - 2 * dm - y0))
        top = float(y[np.nonzero(prof >= 0.5 * phi)[0][-1]])
    return 1 - phi, top


def unit_ball_points(n=40):
    """Deterministic points filling the unit ball (cell centres of an n^3 grid)."""
    g = (np.arange(n) + 0.5) / n * 2 - 1
    P = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    return P[(P**2).sum(1) <= 1]


def closure_as_applied(case, time_name, b, eps_cells, model, Pr):
    """Mean over the grains of the closure at each grain's own void fraction
    and Reynolds number, as vansFoam evaluates it: eps_p gathered from the
    cell void fractions with the grain/cell overlap weights (overlaps
    sampled here with ~34,000 points per grain: the cell void fractions they
    give agree with the solver's to ~0.01), Re_p = |u_p| d/nu with u_p the
    fluid velocity gathered at the grain (lagrangian field Ufluid).
    Returns (mean Nu, mean Nu weighted by the grain's driving temperature
    difference T_p - T_f,p (T_f,p: the air temperature gathered at the
    grain, lagrangian field Tfluid; this mean times k S/d times the mean
    driving difference is exactly the heat the grains give), mean eps_p,
    mean eps_p Re_p)."""
    d, W, H = b["d"], b["width"], b["height"]
    nx = int(round(W / (2 * d)))
    ny = len(eps_cells) // (nx * nx)
    hx, hy = W / nx, H / ny
    g = nscdpost.read_grains(case, time_name)
    u = nscdpost.read_vector_field(os.path.join(case, time_name, "lagrangian", "grains", "Ufluid"))
    lag = os.path.join(case, time_name, "lagrangian", "grains")
    dT = nscdpost.read_scalar_field(os.path.join(lag, "T")) - nscdpost.read_scalar_field(
        os.path.join(lag, "Tfluid")
    )
    B = unit_ball_points()
    nus, epss, res = [], [], []
    for x, dd, up in zip(g["x"], g["d"], u):
        P = x + 0.5 * dd * B
        i = np.clip((P[:, 0] / hx).astype(int), 0, nx - 1)
        j = np.clip((P[:, 1] / hy).astype(int), 0, ny - 1)
        k = np.clip((P[:, 2] / hx).astype(int), 0, nx - 1)
        cells, counts = np.unique(i + nx * j + nx * ny * k, return_counts=True)
        eps_p = float(np.sum(counts * eps_cells[cells]) / counts.sum())
        re_p = float(np.linalg.norm(up)) * dd / b["nu"]
        nus.append(MODELS[model](eps_p, eps_p * re_p, Pr))
        epss.append(eps_p)
        res.append(eps_p * re_p)
    nus = np.array(nus)
    return (
        float(np.mean(nus)),
        float(np.sum(nus * dT) / np.sum(dT)),
        float(np.mean(epss)),
        float(np.mean(res)),
    )


def latest_time(case):
    return max(
        (float(n), n)
        for n in os.listdir(case)
        if re.fullmatch(r"[0-9.e+-]+", n) and os.path.isfile(os.path.join(case, n, "T"))
    )[1]


def measure(case):
    b = json.load(open(os.path.join(case, "bed.json")))
    d, W, Us = b["d"], b["width"], b["superficial_velocity"]
    rho, cp, k, nu = b["rho"], b["cp"], b["kappa"], b["nu"]
    Pr = cp * rho * nu / k
    Res = Us * d / nu
    A = W * W
    model = b["model"]

    Tin_s = surface_series(case, "inletT")
    Tout_s = surface_series(case, "outletT")
    T_in, T_out = Tin_s[-1, 1], Tout_s[-1, 1]
    hl = heat_steps(case)
    T_p = hl[-1, 2]
    Q = rho * cp * Us * A * (T_out - T_in)
    Q_grains = -hl[-1, 3] / hl[-1, 1]  # heat the grains gave in the last step [W]
    dT_in, dT_out = T_p - T_in, T_p - T_out
    dT_lm = (dT_in - dT_out) / math.log(dT_in / dT_out)
    h = Q / (b["grain_surface"] * dT_lm)
    Nu = h * d / k
    ntu = math.log(dT_in / dT_out)

    # steady state: T_out over the last flow-through time H/U_s
    t_end = Tout_s[-1, 0]
    prev = Tout_s[Tout_s[:, 0] <= t_end - b["height"] / Us]
    drift = abs(T_out - prev[-1, 1]) / dT_out if len(prev) else float("nan")

    # bed void fraction from the grains (exact sphere slices, mesh-independent)
    g = nscdpost.read_grains(case, "0")
    eps_bed, y_top = bed_void_fraction(g["x"][:, 1], g["d"], A, b["bed_bottom"])
    bed_height = b["grain_volume"] / (A * (1 - eps_bed))

    # the solver's void fraction, lateral mean per axial cell layer
    nx = int(round(W / (2 * d)))
    eps_cells = read_internal(os.path.join(case, latest_time(case), "voidFraction"))
    ny = len(eps_cells) // (nx * nx)
    layers = eps_cells.reshape(nx, ny, nx, order="F").mean(axis=(0, 2))

    corr = MODELS[model](eps_bed, Res, Pr)
    nu_applied, nu_applied_dT, eps_applied, re_applied = closure_as_applied(
        case, latest_time(case), b, eps_cells, model, Pr
    )
    res = {
        "case": case,
        "reynolds": Res,
        "superficial_velocity": Us,
        "void_fraction": eps_bed,
        "prandtl": Pr,
        "T_in": T_in,
        "T_out": T_out,
        "T_grains": T_p,
        "Q": Q,
        "Q_grains": Q_grains,
        "dT_lm": dT_lm,
        "ntu": ntu,
        "h": h,
        "nusselt_measured": Nu,
        "nusselt_correlation": corr,
        "nusselt_gunn": nu_gunn(eps_bed, Res, Pr),
        "nusselt_wakao": nu_wakao(Res, Pr),
        "nusselt_closure_grain_mean": nu_applied,
        "nusselt_closure_heat_weighted": nu_applied_dT,
        "grain_void_fraction_mean": eps_applied,
        "grain_reynolds_mean": re_applied,
        "model": model,
        "bed_height": bed_height,
        "steady_drift": drift,
        "grain_T_drift": abs(T_p - b["T_p"]) / dT_in,
        "eps_layers": layers.tolist(),
    }
    print(
        f"{os.path.basename(os.path.normpath(case))}: Re {Res:8.3f} eps {eps_bed:.4f} T_out {T_out:.6f} K NTU {ntu:7.3f} "
        f"Nu {Nu:8.4f} {model} {corr:8.4f} ratio {Nu / corr:.4f} (closure over the grains "
        f"{nu_applied:.4f}: eps_p {eps_applied:.4f}, eps_p Re_p {re_applied:.4g}; weighted by "
        f"T_p - T_f,p {nu_applied_dT:.4f}) | Q {Q:.5g} W, grains {Q_grains:.5g} W "
        f"({(Q - Q_grains) / Q_grains:+.1e}), T_out drift over the last flow-through {drift:.1e} "
        f"of dT_out, grain T drift {res['grain_T_drift']:.1e} of dT_in"
    )
    return res


def plot(cases, png="packedBedHeat.png"):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    Re = np.array([c["reynolds"] for c in cases])
    eps = np.mean([c["void_fraction"] for c in cases])
    Pr = cases[0]["prandtl"]
    model = cases[0]["model"]
    r = np.logspace(np.log10(min(Re.min(), 1.0)), np.log10(max(Re.max(), 500.0)), 200)
    fig, ax = plt.subplots(figsize=(5.5, 4))
    ax.loglog(
        r,
        [MODELS[model](eps, x, Pr) for x in r],
        "k-",
        label=f"{model} (selected), eps = {eps:.3f}",
    )
    if model != "Gunn":
        ax.loglog(r, [nu_gunn(eps, x, Pr) for x in r], "b--", label="Gunn (1978)")
    ax.loglog(r, [nu_wakao(x, Pr) for x in r], "g:", label="Wakao & Kaguei (1982)")
    ax.loglog(
        Re,
        [c["nusselt_measured"] for c in cases],
        "ro",
        ms=7,
        label="vansFoam, measured (mixed-cup Q, log-mean dT)",
    )
    ax.loglog(
        Re,
        [c["nusselt_closure_grain_mean"] for c in cases],
        "k+",
        ms=9,
        label=f"{model} at each grain's eps, Re (mean)",
    )
    ax.set_xlabel("Re = U_s d / nu (superficial)")
    ax.set_ylabel("Nu = h d / k")
    ax.set_title(f"air through a fixed bed of hot spheres, Pr = {Pr:.3f}", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


def mesh_study(argv):
    cases = sorted(
        (measure(c) for c in argv),
        key=lambda c: -json.load(open(os.path.join(c["case"], "bed.json")))["dy_over_d"],
    )
    dy = [json.load(open(os.path.join(c["case"], "bed.json")))["dy_over_d"] for c in cases]
    out = {
        "reynolds": cases[0]["reynolds"],
        "void_fraction": cases[0]["void_fraction"],
        "prandtl": cases[0]["prandtl"],
        "model": cases[0]["model"],
        "dy_over_d": dy,
        "nusselt_measured": [c["nusselt_measured"] for c in cases],
        "nusselt_closure_grain_mean": [c["nusselt_closure_grain_mean"] for c in cases],
        "nusselt_closure_heat_weighted": [c["nusselt_closure_heat_weighted"] for c in cases],
        "grain_void_fraction_mean": [c["grain_void_fraction_mean"] for c in cases],
        "nusselt_correlation": cases[0]["nusselt_correlation"],
        "ntu": [c["ntu"] for c in cases],
    }
    nscdpost.write_json("results_mesh.json", out)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(5, 3.6))
    ax.semilogx(dy, out["nusselt_measured"], "ro-", label="measured (mixed-cup Q, log-mean dT)")
    ax.semilogx(
        dy,
        out["nusselt_closure_grain_mean"],
        "k+--",
        ms=9,
        label="closure at each grain's eps, Re (mean)",
    )
    ax.axhline(out["nusselt_correlation"], color="k", label=f"{out['model']} at the bed's eps, U_s")
    from matplotlib.ticker import NullFormatter

    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xticks(dy)
    ax.set_xticklabels([f"{v:g}" for v in dy])
    ax.set_xlabel("axial cell size / d  (lateral cells 2 d)")
    ax.set_ylabel("Nu")
    ax.set_title(f"Re = {out['reynolds']:g}", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig("packedBedHeat_mesh.png", dpi=120)


def main(argv):
    if argv and argv[0] == "--mesh":
        mesh_study(argv[1:])
        return
    cases = sorted((measure(c) for c in argv), key=lambda c: c["reynolds"])
    out = {
        "void_fraction": float(np.mean([c["void_fraction"] for c in cases])),
        "prandtl": cases[0]["prandtl"],
        "model": cases[0]["model"],
        "reynolds": [c["reynolds"] for c in cases],
        "nusselt_measured": [c["nusselt_measured"] for c in cases],
        "nusselt_correlation": [c["nusselt_correlation"] for c in cases],
        "nusselt_gunn": [c["nusselt_gunn"] for c in cases],
        "nusselt_wakao": [c["nusselt_wakao"] for c in cases],
        "nusselt_closure_grain_mean": [c["nusselt_closure_grain_mean"] for c in cases],
        "nusselt_closure_heat_weighted": [c["nusselt_closure_heat_weighted"] for c in cases],
        "grain_void_fraction_mean": [c["grain_void_fraction_mean"] for c in cases],
        "void_fraction_per_case": [c["void_fraction"] for c in cases],
        "ntu": [c["ntu"] for c in cases],
        "outlet_temperature": [c["T_out"] for c in cases],
        "heat_picked_up": [c["Q"] for c in cases],
        "superficial_velocity": [c["superficial_velocity"] for c in cases],
        "inlet_temperature": cases[0]["T_in"],
        "grain_temperature": cases[0]["T_grains"],
        "bed_height": cases[0]["bed_height"],
    }
    nscdpost.write_json("results.json", out)
    plot(cases)


if __name__ == "__main__":
    main(sys.argv[1:])
