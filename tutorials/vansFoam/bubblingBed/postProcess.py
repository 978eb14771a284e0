#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Post-process the bubbling-bed cases (thesis section 4.2, Figures 4.6-4.8).

usage: postProcess.py CASE [CASE ...]     (cases made by setupCase.py)

Writes results.json:
  inflow_velocity            [m/s], one entry per case
  time                       per case: physical time [s] = S * simulated time
                             (S: the heat time-scale factor, setupCase.py)
  mean_particle_temperature  per case: mean grain temperature [K] (vansFoam
                             heatBudget.dat, sampled every 0.05 s x S)
  excess_temperature         per case: (T - T_in)/(T0 - T_in)
  cooling_time               per case: physical time at which the excess
                             temperature falls to 1/e [s] (None if not reached)
  well_mixed_air_time        per case: M c / (rho_a c_a v W p) [s], the time
                             constant if all the air left at the bed
                             temperature and the walls were adiabatic
  heat_budget                per case: heat lost by grains + fluid over the run
                             and where it went (outflow, side walls, front/
                             rear walls), from the solver's 'heat budget' lines
  time_averaged_maps         per case: averaging window [s] and the PNG names
and bubblingBed.png (temperature curves, thesis Figure 4.8) and, for each
case, maps_<case>.png (time-averaged solid fraction and particle velocity,
thesis Figures 4.6-4.7, averaged from avg_start by OpenFOAM's fieldAverage).

Reference: Patil et al. (2015), Chem. Eng. J. 277, 388-401, the thesis'
experiment, could not be obtained here (no copy in the project's reference
library, no digitised data set found), so the curves are compared with the
thesis' reported trend (section 4.2.3: the bed cools faster the higher the
inflow velocity; the thesis calibrated lambda on v = 1.54 m/s) and with the
well-mixed air-only time constant.
"""

import json
import math
import os
import sys

import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))

RHO_A, CP_A, C_P = 1.204, 1010.0, 840.0
SAMPLE = 0.05  # simulated seconds between stored samples


def log_series(case):
    """(t_sim, grain mean T, energy) per step and the summed budget terms
    [J], from postProcessing/heatBudget/<start>/heatBudget.dat (the values
    of the log's "heat:" and "heat budget:" lines; nscdpost.heat_history)."""
    h = nscdpost.heat_history(case)
    out = np.column_stack([h["time"], h["grain_T"], h["E"]])
    keys = (
        "fluid_boundary",
        "advected",
        "sources",
        "grain_walls",
        "fixed_grains",
        "continuity_defect",
    )
    budget = {k: float(np.sum(h["budget"][:, i])) for i, k in enumerate(keys)}
    return out, budget


def cell_centres(case, tname):
    return nscdpost.read_internal_field(os.path.join(case, tname, "C"))


def maps(case, info, png):
    tdirs = [
        name
        for _t, name in nscdpost.numeric_dirs(case)
        if os.path.isfile(os.path.join(case, name, "voidFractionMean"))
    ]
    if not tdirs:
        return None
    tname = max(tdirs, key=float)
    C = cell_centres(case, tname)
    eps = nscdpost.read_internal_field(os.path.join(case, tname, "voidFractionMean"))
    phiv = nscdpost.read_internal_field(os.path.join(case, tname, "phiVsMean"))
    phi = 1.0 - eps
    v = np.where(phi[:, None] > 0.02, phiv / np.maximum(phi, 1e-12)[:, None], 0.0)
    xs, ys = np.unique(np.round(C[:, 0], 9)), np.unique(np.round(C[:, 1], 9))
    ix = np.searchsorted(xs, np.round(C[:, 0], 9))
    iy = np.searchsorted(ys, np.round(C[:, 1], 9))
    P = np.zeros((len(ys), len(xs)))
    VX, VY = np.zeros_like(P), np.zeros_like(P)
    P[iy, ix], VX[iy, ix], VY[iy, ix] = phi, v[:, 0], v[:, 1]
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no maps")
        return tname
    top = ys[np.nonzero(P.max(axis=1) > 0.01)[0].max()] if (P > 0.01).any() else ys[-1]
    ny = np.searchsorted(ys, min(ys[-1], top + 0.01)) + 1
    fig, axes = plt.subplots(1, 2, figsize=(8, 6), sharey=True)
    ext = [0, xs[-1] + xs[0], 0, ys[ny - 1] + ys[0]]
    im = axes[0].imshow(
        P[:ny], origin="lower", extent=ext, cmap="viridis", vmin=0, vmax=0.75, aspect="equal"
    )
    fig.colorbar(im, ax=axes[0], label="solid fraction")
    axes[0].set_title("time-averaged solid fraction")
    sp = np.hypot(VX, VY)
    im = axes[1].imshow(sp[:ny], origin="lower", extent=ext, cmap="magma", aspect="equal")
    fig.colorbar(im, ax=axes[1], label="|v| [m/s]")
    s = slice(None, None, 2)
    X, Y = np.meshgrid(xs, ys[:ny])
    axes[1].quiver(X[s, s], Y[s, s], VX[:ny][s, s], VY[:ny][s, s], color="w", scale=2.0)
    axes[1].set_title("time-averaged particle velocity")
    for a in axes:
        a.set_xlabel("x [m]")
    axes[0].set_ylabel("y [m]")
    fig.suptitle(
        f"v = {info['inflow_velocity']} m/s, averaged over t = {info['avg_start']} - {float(tname):g} s"
    )
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    plt.close(fig)
    return tname


def main(cases):
    res = {
        "inflow_velocity": [],
        "time": [],
        "mean_particle_temperature": [],
        "excess_temperature": [],
        "cooling_time": [],
        "well_mixed_air_time": [],
        "heat_budget": [],
        "time_averaged_maps": [],
        "heat_time_scale": [],
        "reference": "thesis section 4.2.3 trend (faster cooling at higher inflow "
        "velocity); Patil et al. 2015 data not available here",
    }
    curves = []
    for case in cases:
        info = json.load(open(os.path.join(case, "case.json")))
        S, T0, Tin, v = info["heat_time_scale"], info["T0"], info["T_in"], info["inflow_velocity"]
        data, budget = log_series(case)
        if len(data) == 0:
            print(f"{case}: no rows in postProcessing/heatBudget")
            continue
        # sample every SAMPLE simulated seconds
        keep, nxt = [], 0.0
        for k, (t, _, _) in enumerate(data):
            if t >= nxt - 1e-12:
                keep.append(k)
                nxt += SAMPLE
        d = data[keep]
        tphys = S * d[:, 0]
        Tm = d[:, 1]
        theta = (Tm - Tin) / (T0 - Tin)
        full_theta = (data[:, 1] - Tin) / (T0 - Tin)
        below = np.nonzero(full_theta <= math.exp(-1))[0]
        tc = float(S * data[below[0], 0]) if len(below) else None
        tau_air = info["bed_mass"] * C_P / (RHO_A * CP_A * v * info["width"] * info["gap"])
        png = f"maps_{os.path.basename(os.path.normpath(case))}.png"
        tname = maps(case, info, os.path.join(here, png))
        res["inflow_velocity"].append(v)
        res["heat_time_scale"].append(S)
        res["time"].append([float(x) for x in tphys])
        res["mean_particle_temperature"].append([float(x) for x in Tm])
        res["excess_temperature"].append([float(x) for x in theta])
        res["cooling_time"].append(tc)
        res["well_mixed_air_time"].append(tau_air)
        res["heat_budget"].append(budget)
        res["time_averaged_maps"].append(
            {
                "start": info["avg_start"],
                "end": float(tname) if tname else None,
                "png": png if tname else None,
            }
        )
        curves.append((v, tphys, Tm, tau_air, T0, Tin))
        print(
            f"{case}: v = {v} m/s, {len(data)} steps, T {Tm[0]:.2f} -> {Tm[-1]:.2f} K at t = {tphys[-1]:.1f} s"
            f" (physical), 1/e cooling time {tc}, well-mixed air-only tau {tau_air:.1f} s"
        )
    # the thesis' trend: higher inflow velocity -> faster cooling
    order = sorted(range(len(res["inflow_velocity"])), key=lambda i: res["inflow_velocity"][i])
    tmin = min((res["time"][i][-1] for i in order), default=0)
    at = [float(np.interp(tmin, res["time"][i], res["excess_temperature"][i])) for i in order]
    res["excess_temperature_at_common_time"] = {"time": tmin, "values": at}
    res["faster_cooling_at_higher_velocity"] = (
        bool(all(a > b for a, b in zip(at, at[1:]))) if len(at) > 1 else None
    )
    nscdpost.write_json(os.path.join(here, "results.json"), res)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not available: no plot")
        return
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for (v, t, Tm, tau, T0, Tin), c in zip(curves, ["C0", "C1", "C2", "C3"]):
        ax.plot(t, Tm, color=c, label=f"nscdFoam, v = {v} m/s")
        tt = np.linspace(0, t[-1], 100)
        ax.plot(
            tt,
            Tin + (T0 - Tin) * np.exp(-tt / tau),
            "--",
            color=c,
            lw=0.8,
            label=f"well-mixed bed, air only (tau = {tau:.0f} s)",
        )
    ax.set_xlabel("physical time [s]")
    ax.set_ylabel("mean particle temperature [K]")
    ax.set_title("Bubbling bed cooling (thesis Fig. 4.8 setup)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(here, "bubblingBed.png"), dpi=120)
    print("wrote results.json, bubblingBed.png")


if __name__ == "__main__":
    main(sys.argv[1:])
