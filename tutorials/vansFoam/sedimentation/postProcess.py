#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Sedimentation post-processing: results.json and front.png.

usage: postProcess.py CASEDIR [CASEDIR ...]   (one per void-fraction method)

front_height(t): height of the leading (lowest) edge of the falling granular
front, the 0.5 % quantile of the grain centres' heights minus the grain radius
(robust to a few isolated grains); top_height(t): the 99.5 % quantile plus r,
the top of the granular layer.  Thesis section 3.2.2 (Figure 3.9): with the
exact overlap representation only the leading edge moves while the grains
behind stay packed; PCM needs artificial pressure diffusion in the thesis'
finite-element code and opens a void at the top.  row_spread(t): the
coherence of the rows (packing.row_spread: the standard deviation of the
heights of the grains that started in one row, in d, for the lowest starting
row and the median over the lowest 10), grains followed by their grainId.
"""

import os
import sys

import nscdpost
import nscdrender
import numpy as np
import packing
from foamlib import FoamCase


def measure(case):
    t, front, top, spread, row = [], [], [], [], None
    for time, name in nscdpost.time_dirs(case):
        g = nscdpost.read_grains(case, name)
        y, r = g["x"][:, 1], 0.5 * g["d"]
        t.append(time)
        front.append(packing.front_height(y, np.mean(r)))
        top.append(float(np.percentile(y, 99.5) + np.mean(r)))
        y = y[np.argsort(g["grainId"])] if "grainId" in g else y
        if row is None:
            row = packing.rows_of(y)
        spread.append(packing.row_spread(row, y) if len(y) == len(row) else None)
    method = open(os.path.join(case, "constant", "couplingProperties")).read()
    method = "centroid" if "method      centroid" in method else "overlap"
    out = {"time": t, "front_height": front, "top_height": top, "completed": True}
    out["row_spread"] = spread  # per time: (lowest starting row, median of the lowest 10) [d]
    # a run that stopped (the time step collapsed) has its last row of the
    # run-time file postProcessing/continuityErrors before endTime
    end = float(FoamCase(case).control_dict["endTime"])
    last = nscdpost.read_step_data(case, "continuityErrors")["Time"]
    if not len(last) or last[-1] < end * (1 - 1e-5):
        out["completed"] = False
        out["stopped"] = "unstable: the time step collapsed (see log.vansFoam)"
    return method, out


def main():
    res = dict(measure(c) for c in sys.argv[1:])
    nscdpost.write_json("results.json", res)
    plt = nscdrender.pyplot("front.png")
    if plt is not None:
        fig, ax = plt.subplots(figsize=(5, 4))
        for k, (m, r) in enumerate(sorted(res.items())):
            tag = "" if r["completed"] else f" (unstable, stopped after t = {r['time'][-1]:g} s)"
            ax.plot(
                r["time"], r["front_height"], "-o", color=f"C{k}", label=f"{m}: leading edge{tag}"
            )
            ax.plot(r["time"], r["top_height"], "--", color=f"C{k}", label=f"{m}: top of layer")
        nscdrender.save_plot(fig, ax, "front.png", "t [s]", "height [m]")
    for m, r in res.items():
        print(
            f"{m}: front {r['front_height'][0]:.4f} -> {r['front_height'][-1]:.4f} m, "
            f"top {r['top_height'][0]:.4f} -> {r['top_height'][-1]:.4f} m"
        )


if __name__ == "__main__":
    main()
