#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Granular Rayleigh-Taylor post-processing: results.json and fingers.png.

usage: postProcess.py CASEDIR

The lower edge of the granular layer y_low(x): in columns 2 d_max wide, the
10 % quantile of the grain heights (robust to the single grains that rain
out of the layer; columns without grains: the floor).
mean_front_position(t): the mean of y_low over the width (thesis Fig. 3.14:
the layer's lower edge descends as fingers form).  finger_count(t): the
number of separate x-intervals where the edge hangs more than 4 d_max below
its median, i.e. fingers of grains falling into the air (thesis section
3.3.1, Vinningland et al. 2007).
"""

import json
import os
import sys

import nscdpost
import nscdrender
import numpy as np


def lower_edge(g, width, dmax):
    nb = max(1, int(width / (2 * dmax)))
    xb = np.clip((g["x"][:, 0] / width * nb).astype(int), 0, nb - 1)
    yb = g["x"][:, 1] - 0.5 * g["d"]
    edge = np.zeros(nb)
    for b in range(nb):
        s = yb[xb == b]
        edge[b] = np.percentile(s, 10) if len(s) else 0.0
    return edge


def fingers(edge, dmax):
    below = edge < np.median(edge) - 4 * dmax
    return int(np.sum(below[1:] & ~below[:-1]) + (1 if below[0] else 0))


def main():
    case = sys.argv[1]
    setup = json.load(open(os.path.join(case, "setup.json")))
    W, dmax = setup["width"], setup["d_max"]
    t, front, count, edges = [], [], [], []
    for time, name in nscdpost.time_dirs(case):
        g = nscdpost.read_grains(case, name)
        e = lower_edge(g, W, dmax)
        t.append(time)
        front.append(float(e.mean()))
        count.append(fingers(e, dmax))
        edges.append(e)
    res = {
        "time": t,
        "mean_front_position": front,
        "finger_count": count,
        "grains": setup["grains"],
        "width": W,
        "height": setup["height"],
    }
    nscdpost.write_json("results.json", res)
    for a, b, c in zip(t, front, count):
        print(f"t = {a:.3f} s: mean lower edge {b * 1e3:.2f} mm, fingers {c}")
    plt = nscdrender.pyplot("fingers.png")
    if plt is not None:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
        xs = (np.arange(len(edges[0])) + 0.5) * W / len(edges[0])
        for k, (ti, e) in enumerate(zip(t, edges)):
            a1.plot(
                xs * 1e3, e * 1e3, color=plt.cm.viridis(k / max(1, len(t) - 1)), label=f"{ti:.2f} s"
            )
        a1.set_xlabel("x [mm]")
        a1.set_ylabel("lower edge of the grains [mm]")
        a1.legend(fontsize=6)
        a2.plot(t, np.array(front) * 1e3, "o-", label="mean lower edge [mm]")
        a2b = a2.twinx()
        a2b.plot(t, count, "s--", color="C1", label="fingers")
        a2.set_xlabel("t [s]")
        a2.set_ylabel("mean lower edge [mm]")
        a2b.set_ylabel("finger count")
        fig.suptitle("Granular Rayleigh-Taylor instability (thesis 3.3.1)")
        fig.tight_layout()
        fig.savefig("fingers.png", dpi=120)


if __name__ == "__main__":
    main()
