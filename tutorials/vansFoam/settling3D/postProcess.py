#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""settling3D post-processing: results.json (time, mean_grain_velocity) and
settling.png.  mean_grain_velocity: mean vertical grain velocity [m/s].  The
reference curve is the terminal velocity of one grain of the mean diameter
(Dallavalle's C_d, the eps = 1 limit of the DallavalleDiFelice drag):
a dense cloud (solid fraction ~0.3-0.5) falls slower than a lone grain
(hindered settling: return flow of the displaced water, Richardson & Zaki
1954) and stops on the floor."""

import correlations
import nscdpost
import nscdrender
import numpy as np


def terminal(d, rhop=2500.0, rho=1000.0, nu=1e-6):
    """Lone-sphere terminal velocity with Dallavalle's C_d (the eps -> 1 limit
    of DallavalleDiFelice)."""
    return correlations.terminal_velocity(correlations.cd_dallavalle, d, nu, rho, rhop)


def main():
    t, v = [], []
    dmean = None
    for time, name in nscdpost.time_dirs("."):
        g = nscdpost.read_grains(".", name)
        t.append(time)
        v.append(float(np.mean(g["U"][:, 1])))
        dmean = float(np.mean(g["d"]))
    wt = terminal(dmean)
    nscdpost.write_json(
        "results.json",
        {
            "time": t,
            "mean_grain_velocity": v,
            "single_grain_terminal_velocity": -wt,
            "mean_diameter": dmean,
        },
    )
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(5, 3.5))
        ax.plot(t, v, "o-", label="vansFoam, 1,500 spheres")
        ax.axhline(-wt, color="k", ls="--", label="single-grain terminal velocity")
        nscdrender.save_plot(fig, ax, "settling.png", "t [s]", "mean vertical grain velocity [m/s]")
    except ImportError:
        pass
    print("min mean velocity", min(v), "single-grain terminal", -wt)


if __name__ == "__main__":
    main()
