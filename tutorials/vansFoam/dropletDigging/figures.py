# SPDX-License-Identifier: GPL-3.0-or-later
"""Figures of the dropletDigging tutorial (thesis Figures 4.13-4.19) drawn
from the results of postProcess.py: the final depth against the bed
temperature, the depth, velocity, mean grain temperature and lifetime
against t/t_ff, the vertical forces and the heat rates on the droplet, and
the `--snap` snapshots of the grains around the droplet.  Pure functions of
results.json's `cases` entries, case.json and grains already read (no case
files are read here); used by postProcess.py.
"""

import math
import os

import numpy as np

G = 9.81  # gravity [m/s^2] of the tutorial (free-fall time t_ff = sqrt(2 R_0/G))


def pyplot():
    """matplotlib.pyplot on the non-interactive Agg backend (PNG files only)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, outdir, name):
    """Writes fig as outdir/name (tight layout, 120 dpi) and closes it."""
    plt = pyplot()
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, name), dpi=120)
    plt.close(fig)


def plot_final_depth(res, data, outdir):
    """dropletDigging_finalDepth.png (thesis Figure 4.13): final depth h/D
    against the bed temperature, the runs that stopped early marked, the bed
    height, and the digging regime 350-500 C and maximum depth near 400 C
    that the thesis states in words.  res, data: sorted
    (`sort_by_bed_temperature`)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5, 4))
    D0 = data[0][1]["droplet_diameter"] if data else 2.5e-3
    Tb, hf = np.array(res["bed_temperature"]), np.array(res["final_depth"]) / D0
    ax.plot(Tb, hf, "o-", label="nscdFoam")
    stop = np.array([s is not None for s in res["stopped"]], dtype=bool)
    if stop.any():
        ax.plot(Tb[stop], hf[stop], "rx", ms=10, label="run stopped (e.g. droplet left the mesh)")
    if data:
        top = data[0][1]["bed_top"] / D0
        ax.axhline(top, color="k", lw=0.8, label="bed height")
        ax.set_ylim(0, 1.1 * max(top, hf.max()))
    ax.axvspan(350, 500, color="orange", alpha=0.15, label="thesis: digging regime")
    ax.axvline(400, color="red", ls=":", label="thesis: maximum depth")
    ax.set_xlabel("bed temperature [C]")
    ax.set_ylabel("final depth h/D")
    ax.set_title("final depth (thesis Fig. 4.13)")
    ax.legend(fontsize=8)
    save_figure(fig, outdir, "dropletDigging_finalDepth.png")


# the time series plotted against t/t_ff: results key, y label, title, file
TIME_SERIES_PLOTS = (
    ("depth", "h/D", "droplet depth (thesis Fig. 4.14)", "dropletDigging_depth.png"),
    ("velocity", "u t_ff/R", "droplet velocity (thesis Fig. 4.15)", "dropletDigging_velocity.png"),
    (
        "mean_grain_temperature",
        "(T_p - T_d)/(T_bed - T_d)",
        "mean grain temperature (thesis Fig. 4.16)",
        "dropletDigging_grainTemperature.png",
    ),
    (
        "lifetime",
        "m/mdot [s]",
        "instant lifetime (thesis Fig. 4.17)",
        "dropletDigging_lifetime.png",
    ),
)


def scaled_series(key, info, r):
    """(t/t_ff, y) of the time series `key` of one case's results r, y made
    dimensionless: depth over D, velocity times t_ff/R_0, mean grain
    temperature as (T_p - T_d)/(T_bed - T_d); the lifetime as it is [s]."""
    R0 = info["droplet_diameter"] / 2
    tff = math.sqrt(2 * R0 / G)
    t = np.array(r["time"]) / tff
    y = np.array(r[key], dtype=float)
    if key == "depth":
        y = y / info["droplet_diameter"]
    elif key == "velocity":
        y = y * tff / R0
    elif key == "mean_grain_temperature":
        y = (y - info["T_d"]) / (info["bed_temperature_C"] + 273.15 - info["T_d"])
    return t, y


def plot_time_series(data, outdir):
    """The plots of TIME_SERIES_PLOTS (thesis Figures 4.14-4.17), one curve
    per case (`scaled_series`); the lifetime on a log scale."""
    plt = pyplot()
    for key, ylabel, title, name in TIME_SERIES_PLOTS:
        fig, ax = plt.subplots(figsize=(5, 4))
        for T, info, r in data:
            t, y = scaled_series(key, info, r)
            ax.plot(t, y, label=f"{T:g} C")
        ax.set_xlabel("t / t_ff")
        ax.set_ylabel(ylabel)
        if key == "lifetime":
            ax.set_yscale("log")
        ax.set_title(title)
        ax.legend(fontsize=8)
        save_figure(fig, outdir, name)


def smooth(t, y, width=0.02):
    """Running mean of y over `width` s (t the times; the grain forces of
    the NSCD steps are impulsive), y itself when the window is one step or
    longer than the series."""
    y = np.asarray(y, dtype=float)
    n = max(1, int(round(width / max(np.median(np.diff(t)), 1e-12)))) if len(t) > 1 else 1
    if n <= 1 or len(y) <= n:
        return y
    k = np.ones(n)
    return np.convolve(y, k, mode="same") / np.convolve(np.ones(len(y)), k, mode="same")


def plot_forces(data, outdir):
    """dropletDigging_forces.png (thesis Figure 4.18): the vertical forces
    of the gas and the grains on the droplet over m_0 g, upward, running
    means over 0.02 s (`smooth`), the weight dotted."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    for k, (T, info, r) in enumerate(data):
        tff = math.sqrt(info["droplet_diameter"] / G)
        t, f, col = np.array(r["time"]), r["forces"], f"C{k}"
        ax.plot(t / tff, smooth(t, f["fluid"]), "-", color=col, label=f"{T:g} C: fluid F_f")
        ax.plot(
            t / tff, smooth(t, f["grains"]), "--", color=col, label=f"{T:g} C: grains F_p (+F_c)"
        )
        ax.plot(t / tff, f["weight"], ":", color=col, lw=0.8)
    ax.set_xlabel("t / t_ff")
    ax.set_ylabel("vertical force / m_0 g (dotted: weight)")
    ax.set_title("forces on the droplet (thesis Fig. 4.18)")
    ax.legend(fontsize=6)
    save_figure(fig, outdir, "dropletDigging_forces.png")


def plot_heat(data, outdir):
    """dropletDigging_heat.png (thesis Figure 4.19): the heat rates into
    the droplet, Q_f and Q_p + Q_film, over the first step's L mdot, running
    means over 0.02 s (`smooth`)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    for k, (T, info, r) in enumerate(data):
        tff = math.sqrt(info["droplet_diameter"] / G)
        t, col = np.array(r["time"]), f"C{k}"
        qf, qp, qfilm = (np.array(r[x]) for x in ("Q_f", "Q_p", "Q_film"))
        q0 = qf[0] + qp[0] + qfilm[0]
        ax.plot(t / tff, smooth(t, qf / q0), "-", color=col, label=f"{T:g} C: Q_f")
        ax.plot(
            t / tff, smooth(t, (qp + qfilm) / q0), "--", color=col, label=f"{T:g} C: Q_p (+Q_film)"
        )
    ax.set_xlabel("t / t_ff")
    ax.set_ylabel("heat rate / first-step L mdot")
    ax.set_yscale("log")
    ax.set_title("heat into the droplet (thesis Fig. 4.19)")
    ax.legend(fontsize=6)
    save_figure(fig, outdir, "dropletDigging_heat.png")


def plot_cohesion_sweep(data, outdir):
    """dropletDigging_cohesion.png (thesis section 4.3.4: "digging is
    controlled by the cohesion"): depth h/D against t/t_ff, one curve per
    cohesion, labelled by the granular Bond number F_c^0/(weight of the
    mean disc per unit depth, at the reference grain of the similarity
    scaling when there is one).  data: (Bond, info, results) per case."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5, 4))
    for bond, info, r in sorted(data, key=lambda a: a[0]):
        t, y = scaled_series("depth", info, r)
        ax.plot(t, y, label=f"Bo {bond:.3g}")
    ax.set_xlabel("t / t_ff")
    ax.set_ylabel("depth h / D")
    ax.set_title(f"T_bed {data[0][1]['bed_temperature_C']:g} C, cohesion sweep")
    ax.legend(fontsize=8)
    save_figure(fig, outdir, "dropletDigging_cohesion.png")


def plot_snapshot(g, droplet, t, info, out):
    """PNG out of the grains g (nscdpost.read_grains: x [m], d [m], U [m/s])
    at time t [s], coloured by speed [mm/s], with the droplet circle
    droplet = (x, y, R) [m] and the initial bed top of info (case.json,
    dashed); left the whole cell, right a zoom of 3 R around the droplet."""
    plt = pyplot()
    from matplotlib.collections import EllipseCollection

    xd, yd, R = droplet[0] * 1e3, droplet[1] * 1e3, droplet[2] * 1e3
    sp = np.linalg.norm(g["U"], axis=1) * 1e3
    fig, axs = plt.subplots(1, 2, figsize=(10, 6))
    for ax, zoom in zip(axs, (False, True)):
        ec = EllipseCollection(
            g["d"] * 1e3,
            g["d"] * 1e3,
            0,
            units="xy",
            offsets=g["x"][:, :2] * 1e3,
            transOffset=ax.transData,
            array=sp,
            cmap="viridis",
        )
        ec.set_clim(0, max(5.0, float(np.percentile(sp, 99.5))))
        ax.add_collection(ec)
        ax.add_patch(plt.Circle((xd, yd), R, fill=False, color="r", lw=1.5))
        ax.axhline(info["bed_top"] * 1e3, color="k", ls="--", lw=0.8)
        ax.set_aspect("equal")
        if zoom:
            ax.set_xlim(xd - 3 * R, xd + 3 * R)
            ax.set_ylim(yd - 3 * R, yd + 3 * R)
        else:
            ax.set_xlim(0, info["width"] * 1e3)
            ax.set_ylim(0, info["height"] * 1e3)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
    fig.colorbar(ec, ax=axs, label="grain speed [mm/s]")
    axs[0].set_title(
        f"T_bed {info['bed_temperature_C']:g} C, d {info['grain_diameter'] * 1e3:.3f} mm,"
        f" t = {t:g} s"
    )
    fig.savefig(out, dpi=100)
    plt.close(fig)
