#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Drafting-kissing-tumbling post-processing: results.json and positions.png.

usage: postProcess.py CASEDIR [OTHER_RESULTS.json ...]
  OTHER_RESULTS.json: results.json files of other runs of this set-up (e.g.
  another D/h), drawn dashed in positions.png for comparison and listed in
  results.json under "compared_runs" (their kissing, contact, min-gap and
  inversion times).

x1, y1 (upper disc at t = 0) and x2, y2 (lower disc) [m] at the write times;
kissing_time [s]: the first time the gap between the discs, |x1 - x2| - D,
is below one cell size h (the contact resolution of the penalised fluid;
NSCD contacts are hard, so the gap can reach 0); tumbling_time: the first
later time the upper disc is below the lower one (y1 < y2).  None when it
does not happen within the run.  contact_time: the first time the gap is
below 1 % of D (the discs touch: NSCD contact).

reference_kissing_time: None.  No published kissing time for exactly this
set-up (Glowinski et al. 2001 JCP 169:363 / Int J Multiphase Flow 25 (1999);
Wan & Turek 2006; Feng, Hu & Joseph 1994) could be verified from the stored
literature, and no number is written here from memory.  Searched: thesis 3.3.4 (cites Feng et al. [102] for
the set-up, figures only, no number); the stored papers' texts (Li et al.
2022 Energies 15:3297, Tofighi et al. 2015 JCP 297:207, Ghosh & Stockie
2013 arXiv:1304.0804, Zhang et al. 2014 arXiv:1407.6704: only their
openings are stored, no kissing time quotable); solver examples and their
reference files: OpenLB examples/particles/dkt2d (dkt2d.cpp, dkt.p plot only
the run's own output), taha-re/2D_NNF_LBM 2_DKT_Newtonian (compared with
Wan & Turek in JPEG figures only, lower disc at x = 0.97 cm), an IBAMR DKT
driver (Eleven7825/2dRotatingCylinder, no data), Basilisk (ghigo sandbox:
the Uhlmann 2005 set-up, d = 0.25 cm, rho 1.5), GeoTaichi (3D spheres,
Lai et al. 2023).  Definitions met in those codes: contact when the
centre distance is <= 1.005 D (FeatFloWer tools/dkt_export_series.py),
collision at the velocity peak (GeoTaichi); here kissing_time is gap < h
and contact_time gap < D/100.  min_gap [m] and min_gap_time [s]: the
smallest gap and when; inversion_time [s]: the first time y1 < y2 (the pair
has tumbled), with or without kissing.  Until a
number is verified the comparison is a self-convergence one: the kissing
time at D/h = 6 and 12.5 (the tutorial's README, "Measured"),
REFERENCE_KISSING_TIME below to fill in.
"""

import json
import os
import sys

import nscdpost
import nscdrender
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))


# by path: both tutorials have a setupCase.py / postProcess.py
setupCase = nscdpost.load_module(
    "draftingKissingTumbling_setupCase", os.path.join(here, "setupCase.py")
)
grain_history = nscdpost.load_module(
    "cylinderSedimentation_postProcess",
    os.path.join(here, "..", "cylinderSedimentation", "postProcess.py"),
).grain_history


# Published kissing time [s] of this set-up and its source; None: not verified.
REFERENCE_KISSING_TIME = None
REFERENCE_KISSING_SOURCE = (
    "none verified: Glowinski et al. (2001), Wan & Turek (2006), Feng et al. "
    "(1994) and the codes reproducing them (OpenLB dkt2d, ...) give no quotable "
    "kissing time in the searched literature"
)


def cell_size(case):
    """The cell size [m] of a case written by setupCase (uniform mesh)."""
    return setupCase.W / setupCase.cyl.mesh_layout(case)[0]


def dkt_measure(t, x, D, h):
    """Kissing and tumbling times [s] (None if absent) of two discs with
    centres x[2, nt, 3]."""
    gap = np.linalg.norm(x[0] - x[1], axis=1) - D
    k = np.nonzero(gap < h)[0]
    kiss = float(t[k[0]]) if k.size else None
    tumble = None
    if kiss is not None:
        j = np.nonzero((t > kiss) & (x[0, :, 1] < x[1, :, 1]))[0]
        tumble = float(t[j[0]]) if j.size else None
    return kiss, tumble, gap


def contact_time(t, x, D, tol=0.01):
    """First time [s] the gap between the two discs is below tol * D (None)."""
    gap = np.linalg.norm(x[0] - x[1], axis=1) - D
    k = np.nonzero(gap < tol * D)[0]
    return float(t[k[0]]) if k.size else None


def main():
    case = sys.argv[1] if len(sys.argv) > 1 else "case"
    others = [json.load(open(f)) for f in sys.argv[2:]]
    t, x, u = grain_history(case)
    h = cell_size(case)
    kiss, tumble, gap = dkt_measure(t, x, setupCase.D, h)
    res = {
        "time": t.tolist(),
        "x1": x[0, :, 0].tolist(),
        "y1": x[0, :, 1].tolist(),
        "x2": x[1, :, 0].tolist(),
        "y2": x[1, :, 1].tolist(),
        "gap": gap.tolist(),
        "kissing_time": kiss,
        "tumbling_time": tumble,
        "cell_size": h,
        "contact_time": contact_time(t, x, setupCase.D),
        "min_gap": float(gap.min()),
        "min_gap_time": float(t[int(np.argmin(gap))]),
        "inversion_time": (
            float(t[np.nonzero(x[0, :, 1] < x[1, :, 1])[0][0]])
            if np.any(x[0, :, 1] < x[1, :, 1])
            else None
        ),
        "reference_kissing_time": REFERENCE_KISSING_TIME,
        "reference_kissing_source": REFERENCE_KISSING_SOURCE,
        "cells_per_diameter": setupCase.D / h,
        "rotation_coupling": "rotationCoupling yes"
        in open(os.path.join(case, "constant", "couplingProperties")).read(),
    }
    res["compared_runs"] = [
        {
            k: o.get(k)
            for k in (
                "cells_per_diameter",
                "rotation_coupling",
                "kissing_time",
                "contact_time",
                "tumbling_time",
                "min_gap",
                "min_gap_time",
                "inversion_time",
            )
        }
        for o in others
    ]
    import nscdpost

    nscdpost.write_json("results.json", res)
    print(
        f"kissing at t = {kiss} s, tumbling (y1 < y2) at t = {tumble} s, min gap {gap.min():.2e} m"
    )
    plt = nscdrender.pyplot("positions.png")
    if plt is not None:
        fig, ax = plt.subplots(1, 2, figsize=(9, 4))
        ax[0].plot(t, 100 * x[0, :, 0], "C0", label="disc 1 (upper at t = 0)")
        ax[0].plot(t, 100 * x[1, :, 0], "C3", label="disc 2")
        ax[0].set_ylabel("x [cm]")
        ax[1].plot(t, 100 * x[0, :, 1], "C0", label="disc 1")
        ax[1].plot(t, 100 * x[1, :, 1], "C3", label="disc 2")
        for k, o in enumerate(others):
            lab = f"D/h = {o['cells_per_diameter']:.3g}" + (
                ", rotation" if o.get("rotation_coupling") else ""
            )
            for j, key in enumerate(("1", "2")):
                ax[0].plot(
                    o["time"],
                    100 * np.array(o["x" + key]),
                    ("C0", "C3")[j],
                    ls=("--", ":", "-.")[k % 3],
                    lw=0.8,
                    label=f"disc {key}, {lab}",
                )
                ax[1].plot(
                    o["time"],
                    100 * np.array(o["y" + key]),
                    ("C0", "C3")[j],
                    ls=("--", ":", "-.")[k % 3],
                    lw=0.8,
                    label=f"disc {key}, {lab}",
                )
        ax[1].set_ylabel("y [cm]")
        for a in ax:
            if kiss is not None:
                a.axvline(kiss, color="k", ls="--", lw=0.8, label="kissing (gap < h)")
            if REFERENCE_KISSING_TIME is not None:
                a.axvline(
                    REFERENCE_KISSING_TIME,
                    color="C2",
                    ls=":",
                    lw=1.2,
                    label=f"reference kissing time ({REFERENCE_KISSING_SOURCE})",
                )
            a.set_xlabel("t [s]")
            a.grid(alpha=0.3)
            a.legend(fontsize=8)
        fig.suptitle(
            f"DKT, vansFoam D/h = {setupCase.D / h:.3g} (thesis 3.3.4); kissing "
            f"{kiss} s"
            + ("" if REFERENCE_KISSING_TIME is not None else " (no verified published reference)"),
            fontsize=9,
        )
        fig.tight_layout()
        fig.savefig("positions.png", dpi=120)


if __name__ == "__main__":
    main()
