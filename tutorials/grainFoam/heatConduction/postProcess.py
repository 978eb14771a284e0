#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Heat conduction post-processing: results.json, meanTemperature.png, snapshot.png.

usage: postProcess.py CASEDIR

From postProcessing/grainHeat/<start>/grainHeat.dat (one row per step, the
values of the log's `heat:` line): the mean grain temperature vs time; the
time is the physical time S t of glass (S = timeScale of
caseParameters, see setupCase.py). From the last written time: the grain
temperatures (lagrangian field T) for a temperature-coloured snapshot and the
mean temperature of each horizontal layer of one mean diameter.
"""

import os
import sys

import nscdpost
import nscdrender
import numpy as np


def main():
    case = sys.argv[1] if len(sys.argv) > 1 else "case"
    params = dict(l.split() for l in open(os.path.join(case, "caseParameters")))
    S = float(params["timeScale"])
    # postProcessing/grainHeat/<start>/grainHeat.dat: a row per step
    h = nscdpost.read_step_data(case, "grainHeat")
    t = list(h["Time"] * S)
    Tm = list(h["grainMeanT"])
    Qw = list(h["wallHeat"])
    times = nscdpost.time_dirs(case)
    tl, name = times[-1]
    g = nscdpost.read_grains(case, name)
    T = nscdpost.read_scalar_field(os.path.join(case, name, "lagrangian", "grains", "T"))
    y, d = g["x"][:, 1], g["d"]
    dm = float(np.mean(d))
    layers = []
    for k in range(int(np.ceil(y.max() / dm))):
        sel = (y >= k * dm) & (y < (k + 1) * dm)
        if sel.any():
            layers.append(
                {"y": (k + 0.5) * dm, "mean_T": float(T[sel].mean()), "grains": int(sel.sum())}
            )
    # keep the json small: every step would be thousands of entries
    stride = max(1, len(t) // 200)
    res = {
        "description": "2D contact conduction (thesis 4.1.1, Fig. 4.2 analogue): floor 400 K, "
        "adiabatic sides, open top, discs initially 300 K, glass beads",
        "material": {
            "density": 2500,
            "youngModulus": 6e10,
            "poissonRatio": 0.22,
            "conductivity": 1.4,
            "heatCapacity": 840,
        },
        "time_scale_S": S,
        "n_grains": int(len(d)),
        "time": [float(v) for v in t[::stride]] + ([t[-1]] if (len(t) - 1) % stride else []),
        "mean_grain_temperature": [float(v) for v in Tm[::stride]]
        + ([Tm[-1]] if (len(t) - 1) % stride else []),
        "final_time": t[-1],
        "final_mean_grain_temperature": Tm[-1],
        "total_wall_heat_J_per_m": float(np.sum(Qw)),
        "heat_gained_J_per_m_from_T": None,
        "final_layer_temperature": layers,
    }
    # energy check: sum m c (T - T0) with the glass c (simulated c = 840/S and
    # the scaled time give the same temperatures; the wall heat in the log is
    # for the simulated c)
    m = 2500 * np.pi * d**2 / 4
    res["heat_gained_J_per_m_from_T"] = float(np.sum(m * 840.0 / S * (T - float(params["T0"]))))
    nscdpost.write_json("results.json", res)
    print(
        f"{len(d)} grains, final time {t[-1]:.4g} s (physical): mean T {Tm[-1]:.2f} K; "
        f"wall heat (simulated c) {res['total_wall_heat_J_per_m']:.4g} J/m vs grain heat gain "
        f"{res['heat_gained_J_per_m_from_T']:.4g} J/m"
    )
    plt = nscdrender.pyplot("heatConduction PNGs")
    if plt is None:
        return
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle

    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(np.array(t) / 3600, Tm)
    ax.set_xlabel("time [h] (glass beads)")
    ax.set_ylabel("mean grain temperature [K]")
    ax.set_title("Floor at 400 K, grains initially 300 K")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig("meanTemperature.png", dpi=120)
    fig, ax = plt.subplots(figsize=(5, 6))
    pc = PatchCollection([Circle((x[0], x[1]), r) for x, r in zip(g["x"], 0.5 * d)], cmap="inferno")
    pc.set_array(T)
    pc.set_clim(300, 400)
    ax.add_collection(pc)
    ax.set_xlim(0, g["x"][:, 0].max() + d.max())
    ax.set_ylim(0, y.max() + d.max())
    ax.set_aspect("equal")
    fig.colorbar(pc, ax=ax, label="T [K]")
    ax.set_title(f"t = {tl * S / 3600:.1f} h")
    fig.tight_layout()
    fig.savefig("snapshot.png", dpi=120)


if __name__ == "__main__":
    main()
