#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Post-processing of the liquid-fluidised bed (fluidisedBed3D).

usage: postProcess.py [CASE]      (default: this directory)

Reads bed.json (setupCase.py), the patch-averaged pressures of the
function objects pBottom and pTop (every step) and the grains at every
write (reconstructPar, or a serial run), and writes CASE/results.json and
CASE/fluidisedBed3D.png.

References, independent of the code:
- momentum balance of the column: once the bed is suspended, the pressure
  drop across it carries its buoyant weight, dp = sum (rho_p - rho) V_p g / A
  (Kunii & Levenspiel, Fluidization Engineering, 2nd ed. 1991, ch. 3);
- the exchange of momentum: dp A = sum over the grains of (F_fluid - rho V_p g)
  at every write (the fluid's drag reaction, Newton's third law), whatever
  the drag closure;
- bed expansion: Richardson & Zaki (1954), U_0 = u_i eps^n, with n from
  Rowe (1987), u_t from the drag curve of Turton & Levenspiel (1986) (not
  the Dallavalle law of the code) and u_i = u_t 10^(-d/W) (Richardson &
  Zaki's wall factor).
"""

import json
import math
import os
import sys

import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))


def patch_average(case, name):
    """(t, p) of the surfaceFieldValue function object `name` [s, m^2/s^2]."""
    runs = nscdpost.numeric_dirs(os.path.join(case, "postProcessing", name))
    if not runs:
        raise SystemExit(f"{case}: no postProcessing/{name}: run vansFoam first")
    rows = []
    for _, start in runs:  # restarts write one directory each
        rows.append(
            np.loadtxt(
                os.path.join(case, "postProcessing", name, start, "surfaceFieldValue.dat"), ndmin=2
            )
        )
    a = np.concatenate(rows)
    _, keep = np.unique(a[:, 0], return_index=True)
    return a[keep, 0], a[keep, 1]


def turton_levenspiel_cd(re):
    """Drag coefficient of a sphere, Turton & Levenspiel (1986), Powder
    Technol. 47, 83-86."""
    return 24 / re * (1 + 0.173 * re**0.657) + 0.413 / (1 + 16300 * re**-1.09)


def terminal_velocity(d, rho, rho_p, nu, g):
    """Settling speed of a lone sphere [m/s] with turton_levenspiel_cd."""
    lo, hi = 1e-6, 10.0
    for _ in range(200):
        u = 0.5 * (lo + hi)
        re = u * d / nu
        drag = turton_levenspiel_cd(re) * 0.5 * rho * u * u * math.pi * d * d / 4
        if drag > (rho_p - rho) * g * math.pi * d**3 / 6:
            hi = u
        else:
            lo = u
    return 0.5 * (lo + hi)


def richardson_zaki(b, d):
    """Void fraction of the expanded bed at U_0 (Richardson & Zaki 1954,
    n of Rowe 1987, wall factor 10^(-d/W)), with u_t and n."""
    ut = terminal_velocity(d, b["rho"], b["rho_p"], b["nu"], b["g"])
    ret = ut * d / b["nu"]
    n = (4.7 + 0.41 * ret**0.75) / (1 + 0.175 * ret**0.75)
    ui = ut * 10 ** (-d / b["width"])
    return {
        "terminal_velocity": ut,
        "terminal_reynolds": ret,
        "exponent_n": n,
        "void_fraction": (b["u0"] / ui) ** (1 / n),
    }


def bed_surface(y, d):
    """Height of the bed's surface [m]: the 99.5th percentile of the grain
    tops (a few grains thrown above the bed do not count)."""
    return float(np.percentile(y + 0.5 * d, 99.5))


def analyse(case):
    b = json.load(open(os.path.join(case, "bed.json")))
    area = b["width"] ** 2
    tb, pb = patch_average(case, "pBottom")
    tt, pt = patch_average(case, "pTop")
    n = min(len(tb), len(tt))
    t, pb, pt = tb[:n], pb[:n], pt[:n]
    # dynamic pressure drop [Pa]: kinematic p includes the water's weight
    dp = b["rho"] * (pb - pt - b["g"] * b["column_height"])

    times = nscdpost.time_dirs(case)
    if not times:
        raise SystemExit(f"{case}: no grains written (reconstructPar after a parallel run)")
    g0 = nscdpost.read_grains(case, times[0][1])
    vp = math.pi / 6 * g0["d"] ** 3
    weight = float(vp.sum() * (b["rho_p"] - b["rho"]) * b["g"] / area)  # [Pa]
    d_mean = float(g0["d"].mean())
    rz = richardson_zaki(b, d_mean)

    writes = []
    for tw, name in times:
        g = nscdpost.read_grains(case, name)
        if len(g["d"]) != len(g0["d"]):
            raise SystemExit(f"{case}/{name}: {len(g['d'])} grains, {len(g0['d'])} at the start")
        y = g["x"][:, 1]
        surface = bed_surface(y, g["d"])
        row = {
            "time": tw,
            "grains": int(len(g["d"])),
            "bed_surface": surface,
            "bed_void_fraction": 1 - float((math.pi / 6 * g["d"] ** 3).sum()) / (area * surface),
            "resting_on_floor": int((y < 0.5 * g["d"] * 1.02).sum()),
        }
        if "Ffluid" in g and tw > 0:
            k = int(np.argmin(abs(t - tw)))
            fy = g["Ffluid"][:, 1] - b["rho"] * math.pi / 6 * g["d"] ** 3 * b["g"]
            row["fluid_force_minus_buoyancy_over_weight"] = float(fy.sum() / area / weight)
            row["pressure_drop_over_weight"] = float(dp[k] / weight)
        writes.append(row)

    end = float(t[-1])
    late = t >= 0.5 * end
    res = {
        "bed_weight_per_area": weight,
        "d_mean": d_mean,
        "u0": b["u0"],
        "grains": b["grains"],
        "ranks": b["ranks"],
        "richardson_zaki": rz,
        "pressure_drop_over_weight_second_half": float(dp[late].mean() / weight),
        "pressure_drop_over_weight_second_half_std": float(dp[late].std() / weight),
        "time": [float(x) for x in t[::10]],
        "pressure_drop_over_weight": [float(x) for x in (dp / weight)[::10]],
        "writes": writes,
    }
    nscdpost.write_json(os.path.join(case, "results.json"), res)
    return res


def plot(case, res):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(res["time"], res["pressure_drop_over_weight"], label="vansFoam")
    ax[0].axhline(1, color="k", ls="--", label="buoyant weight per area")
    ax[0].set_ylim(0.8, 1.2)
    ax[0].set_xlabel("t [s]")
    ax[0].set_ylabel("dp / (W_b / A)")
    ax[0].legend()
    w = res["writes"]
    ax[1].plot([r["time"] for r in w], [r["bed_void_fraction"] for r in w], "o-", label="vansFoam")
    ax[1].axhline(
        res["richardson_zaki"]["void_fraction"],
        color="k",
        ls="--",
        label="Richardson & Zaki (1954)",
    )
    ax[1].set_xlabel("t [s]")
    ax[1].set_ylabel("mean void fraction of the bed")
    ax[1].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(case, "fluidisedBed3D.png"), dpi=100)


if __name__ == "__main__":
    c = sys.argv[1] if len(sys.argv) > 1 else here
    r = analyse(c)
    plot(c, r)
    print(
        f"{c}: dp/(W_b/A) over the second half {r['pressure_drop_over_weight_second_half']:.4f}"
        f" (std {r['pressure_drop_over_weight_second_half_std']:.4f}); bed void fraction at the end"
        f" {r['writes'][-1]['bed_void_fraction']:.3f}, Richardson-Zaki"
        f" {r['richardson_zaki']['void_fraction']:.3f}"
    )
