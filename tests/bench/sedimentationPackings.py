#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Square lattice against the thesis' hexagonal packing in the sedimentation
tutorial (issue 59 item 7): leading edge and row spread at 0.5, 1 and 2 s of
vansFoam cases (tutorials/vansFoam/sedimentation/setupCase.py, overlap
method) and MigFlow 1.4 runs (migflowSedimentation.py OUTDIR), and snapshot
figures of the grains coloured by the row they started in.

usage: sedimentationPackings.py OUT.json LABEL=DIR [LABEL=DIR ...]
           [--snapshots PNG=LABEL,LABEL[,...] ...]
  DIR: a vansFoam case (time directories) or a MigFlow OUTDIR (front.json,
  positions.npz).  --snapshots: one PNG of the 0.5, 1 and 2 s grains, one
  row of panels per LABEL.  Measures: packing.front_height (the leading
  edge, postProcess.py's front_height) and packing.row_spread (the standard
  deviation of the heights of the grains that started in one row, in d:
  lowest starting row / median of the lowest 10).
"""

import argparse
import os
import sys

import nscdpost
import nscdrender
import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tutorials", "vansFoam", "sedimentation"))
import packing  # noqa: E402

TIMES = (0.5, 1.0, 2.0)


def positions(path):
    """{time: (n, 2) centres ordered as at t = 0} of a vansFoam case or a
    MigFlow OUTDIR, and the diameter [m]."""
    npz = os.path.join(path, "positions.npz")
    if os.path.isfile(npz):
        z = np.load(npz)
        out = {float(k[1:]): z[k] for k in z.files if k.startswith("t")}
        return out, 2 * packing.R
    out = {}
    for time, name in nscdpost.time_dirs(path):
        if time == 0 or any(abs(time - t) < 1e-6 for t in TIMES):
            g = nscdpost.read_grains(path, name)
            out[time] = g["x"][np.argsort(g["grainId"]), :2]
            d = float(np.mean(g["d"]))
    return out, d


def measure(path):
    xy, d = positions(path)
    row = packing.rows_of(xy[0.0][:, 1])
    res = {"grains": len(row), "rows": int(row.max()) + 1, "d": d}
    for t in (0.0,) + TIMES:
        if t in xy:
            y = xy[t][:, 1]
            lowest, median = packing.row_spread(row, y)
            res[f"t{t:g}"] = {
                "front_height": packing.front_height(y, 0.5 * d),
                "row_spread_lowest": lowest,
                "row_spread_median10": median,
            }
    return res, xy, row, d


def snapshots(png, runs):
    """Panels (one row per run, one column per time) of the grains as discs
    to scale, coloured by starting row (a cycle of 10 colours from the
    bottom row up), y from 0.15 m to the lid."""
    plt = nscdrender.pyplot(png)
    if plt is None:
        return
    from matplotlib.collections import EllipseCollection

    fig, axes = plt.subplots(len(runs), len(TIMES), figsize=(2.3 * len(TIMES), 2.6 * len(runs)))
    axes = np.atleast_2d(axes)
    for i, (label, (xy, row, d)) in enumerate(runs):
        colour = plt.get_cmap("tab10")((row.max() - row) % 10)
        for j, t in enumerate(TIMES):
            ax = axes[i, j]
            if t in xy:
                ax.add_collection(
                    EllipseCollection(
                        d, d, 0.0, units="xy", offsets=xy[t], transOffset=ax.transData, color=colour
                    )
                )
            ax.set_xlim(0, packing.W)
            ax.set_ylim(0.15, packing.H)
            ax.set_aspect("equal")
            ax.set_xticks([])
            ax.set_yticks([0.2, 0.3, 0.4, 0.5, 0.6] if j == 0 else [])
            ax.set_title(f"{label}, t = {t:g} s", fontsize=6)
    fig.tight_layout()
    fig.savefig(png, dpi=80)
    # 32-colour palette: the figures go to docs/ (<= 200 kB each)
    from PIL import Image

    Image.open(png).convert("RGB").quantize(32).save(png, optimize=True)


def main():
    a = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    a.add_argument("out")
    a.add_argument("runs", nargs="+", metavar="LABEL=DIR")
    a.add_argument("--snapshots", action="append", default=[], metavar="PNG=LABEL,...")
    args = a.parse_args()
    res, data = {}, {}
    for spec in args.runs:
        label, path = spec.split("=", 1)
        res[label], *data[label] = measure(path)
        res[label]["dir"] = os.path.basename(os.path.normpath(path))
        print(
            label,
            " ".join(
                f"t={t:g}: front {res[label][f't{t:g}']['front_height']:.4f} m, spread "
                f"{res[label][f't{t:g}']['row_spread_lowest']:.2f}/"
                f"{res[label][f't{t:g}']['row_spread_median10']:.2f} d"
                for t in TIMES
                if f"t{t:g}" in res[label]
            ),
        )
    for spec in args.snapshots:
        png, labels = spec.split("=", 1)
        snapshots(png, [(lb, data[lb]) for lb in labels.split(",")])
    nscdpost.write_json(args.out, res)


if __name__ == "__main__":
    main()
