#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark: the side walls' effect on the falling cylinder's speed
(thesis 3.3.3).

The reference U_t = 2.501 cm/s (Re = 156) is that of a cylinder falling in
an INFINITE fluid (Namkoong, Yoo & Choi 2008, J. Fluid Mech. 604:33-53,
"... a freely falling circular cylinder in an infinite fluid"), while the
thesis box [-0.02, 0.02] x [-0.16, 0.16] m puts no-slip walls 4 D from
the axis (D/W = 1/8).  Walls slow a falling body (their no-slip condition
and the return flow between body and wall), so part of the box's deficit
against 2.501 cm/s is physics, not error.  This bench separates the two:
the same case (tutorials/vansFoam/cylinderSedimentation, setupCase.py CASE
3.5 D/h 0.32 yes 1e-3 resolved WALLS: resolved scheme, rotation coupling,
maxDeltaT 1e-3 s, released D/100 off the axis) with the walls at WALLS
diameters from the axis, the 8 D wide middle block keeping its uniform
cells and graded side blocks (growth 1.1 per cell, setupCase.side_blocks)
filling the rest, at the same D/h.  A box 0.16 m high instead of 0.32
(HEIGHT argument) halves the cost: at D/h 12 it gives the same plateau to
4 digits (measured), so the finest level is run that way.
Measures as cylinderConvergence.py
(plateau_velocity: mean fall speed over 2.75-3.5 s, fixed before the runs;
the other windows reported too).

usage: cylinderConfinement.py [--walls W ...] [--workdir DIR] [D/h ...]
           run every (D/h, W) pair (default D/h 12, W 4 12 24) one after the
           other, then post-process
           (--height H: box height [m], default 0.32)
       cylinderConfinement.py --post CASEDIR ...
           rebuild the JSON and PNG from existing case directories (D/h and
           the walls' distance read from their blockMeshDict; each must
           reach 3.5 s)
Writes tests/bench/results/cylinderConfinement.json and
tests/bench/cylinderConfinement/cylinderConfinement.png.
Assumes ./Allwmake has run.
"""

import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
OUT = os.path.join(ROOT, "tests", "bench", "results", "cylinderConfinement.json")
PNG = os.path.join(HERE, "cylinderConfinement.png")
sys.path.insert(0, os.path.join(ROOT, "tests", "bench", "cylinderConvergence"))
import cylinderConvergence as conv  # noqa: E402

nscdpost = conv.nscdpost
setupCase = conv.setupCase
postProcess = conv.postProcess
UT_REF = conv.UT_REF
WINDOWS = {
    "mean_0.50_1.00": (0.5, 1.0),
    "mean_1.50_2.00": (1.5, 2.0),
    "mean_2.00_2.75": (2.0, 2.75),
    "plateau_velocity": conv.PLATEAU_WINDOW,
}


def measure(case):
    """conv.measure_level's measures of one case, the extra windows and the
    walls' distance."""
    L = conv.measure_level(case)
    t = np.array(L["series"]["time"])
    u = np.array(L["series"]["streamwise_velocity"])
    for k, (a, b) in WINDOWS.items():
        L[k] = float(np.mean(u[(t >= a - 1e-9) & (t <= b + 1e-9)]))
    _, _, walls, height = setupCase.mesh_layout(case)
    L["walls_from_axis_in_D"] = walls / setupCase.D
    L["box_height"] = height
    return L


def post(cases, wall=None):
    runs = sorted(
        (measure(c) for c in cases),
        key=lambda L: (L["cells_per_diameter"], L["walls_from_axis_in_D"], L["box_height"]),
    )
    pairs = []
    for cpd in sorted({L["cells_per_diameter"] for L in runs}):
        same = [L for L in runs if L["cells_per_diameter"] == cpd]
        box = [L for L in same if abs(L["walls_from_axis_in_D"] - 4.0) < 1e-6]
        if not box:
            continue
        for L in same:
            if L is box[0]:
                continue
            pairs.append(
                {
                    "cells_per_diameter": cpd,
                    "walls_from_axis_in_D": L["walls_from_axis_in_D"],
                    "box_height": L["box_height"],
                    **{f"ratio_{k}": L[k] / box[0][k] for k in WINDOWS},
                    "plateau_velocity": L["plateau_velocity"],
                    "plateau_velocity_error": L["plateau_velocity"] / UT_REF - 1,
                    "box_plateau_velocity_error": box[0]["plateau_velocity"] / UT_REF - 1,
                }
            )
    res = {
        "benchmark": "cylinderConfinement",
        "case": "tutorials/vansFoam/cylinderSedimentation setupCase.py CASE 3.5 D/h HEIGHT yes 1e-3 "
        "resolved WALLS (walls WALLS x D from the axis, 4 = the thesis box; HEIGHT "
        "box_height of each run, 0.32 m = the thesis box)",
        "reference": "Namkoong, Yoo & Choi (2008), J. Fluid Mech. 604:33-53: U_t = 2.501 cm/s, "
        "Re 156, cylinder in an infinite fluid (thesis 3.3.3)",
        "terminal_velocity_reference": UT_REF,
        "windows": {k: list(v) for k, v in WINDOWS.items()},
        "measure": "mean -U_y of the grain at the write times (every 0.05 s) in each window; "
        "plateau_velocity over 2.75-3.5 s as in cylinderConvergence",
        "runs": runs,
        "wide_over_box": pairs,
        "wall_seconds_total": wall,
    }
    os.makedirs(os.path.dirname(OUT), exist_ok=True)
    nscdpost.write_json(OUT, res)
    plot(runs)
    print(
        f"{'D/h':>5} {'walls':>5} {'H':>5} {'cells':>7} {'cpu/step':>8} "
        + " ".join(f"{k[-9:]:>9}" for k in WINDOWS)
        + "   err"
    )
    for L in runs:
        print(
            f"{L['cells_per_diameter']:5g} {L['walls_from_axis_in_D']:5g} {L['box_height']:5g} "
            f"{L['cells']:7d} "
            f"{L['cpu_seconds_per_step_median'] or 0:8.3f} "
            + " ".join(f"{100 * L[k]:9.4f}" for k in WINDOWS)
            + f" {100 * L['plateau_velocity_error']:+6.2f}%"
        )
    for p in pairs:
        print(
            f"D/h {p['cells_per_diameter']:g}, walls {p['walls_from_axis_in_D']:g} D "
            f"(H {p['box_height']:g} m) over 4 D: "
            + ", ".join(f"{k}: {p['ratio_' + k]:.4f}" for k in WINDOWS)
        )
    return res


def plot(runs):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.2))
    for i, L in enumerate(runs):
        s = L["series"]
        ax.plot(
            s["time"],
            np.array(s["streamwise_velocity"]) / UT_REF,
            color=f"C{i}",
            label=f"D/h {L['cells_per_diameter']:g}, walls {L['walls_from_axis_in_D']:g} D "
            f"from the axis, H {L['box_height']:g} m",
        )
    ax.axhline(
        1.0, color="k", ls="--", lw=0.8, label="Namkoong et al. (2008), infinite fluid: 2.501 cm/s"
    )
    ax.axvspan(*conv.PLATEAU_WINDOW, color="0.9", zorder=0)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("$u_{str}/U_t$")
    ax.set_ylim(0, 1.1)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title("Falling cylinder: the side walls' effect (grey: plateau window)")
    fig.tight_layout()
    fig.savefig(PNG, dpi=120)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("levels", nargs="*", help="D/h values (run) or case dirs (--post)")
    ap.add_argument("--post", action="store_true", help="post-process existing case dirs")
    ap.add_argument(
        "--walls",
        nargs="*",
        type=float,
        default=[4.0, 12.0, 24.0],
        help="walls' distances from the axis [D] (4: the thesis box)",
    )
    ap.add_argument("--height", type=float, default=setupCase.HEIGHT, help="box height [m]")
    ap.add_argument("--workdir", default=None)
    a = ap.parse_args()
    if a.post:
        return post(a.levels)
    cpds = [float(v) for v in a.levels] or [12.0]
    conv.run_then_post(
        a.workdir,
        "cylinderConfinement",
        [
            (c, conv.PLATEAU_WINDOW[1], {"walls": None if w == 4.0 else w, "height": a.height})
            for c in cpds
            for w in a.walls
        ],
        post,
    )


if __name__ == "__main__":
    main()
