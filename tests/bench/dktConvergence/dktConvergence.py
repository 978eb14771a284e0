#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark: self-convergence of drafting-kissing-tumbling in the mesh
(thesis 3.3.4, Figure 3.21 at D/h = 12.5; issue 59, item 4).

No published kissing time of this set-up has been verified
(tutorials/vansFoam/draftingKissingTumbling/postProcess.py,
REFERENCE_KISSING_TIME), so the times are compared between meshes: the
tutorial's case (setupCase.py CASE END D/h yes 1e-3 resolved: resolved
scheme, rotation coupling, maxDeltaT 1e-3 s, the same step at every D/h)
at D/h = 12.5, 18 and 25, and the relative change of each time between the
two finest meshes (criterion of the issue: within 5 %).

Times [s], from the discs' centres written every 0.01 s:
  - kissing_time: first gap < h (the tutorial's measure; its threshold
    shrinks with h);
  - kissing_time_fixed_gap: first gap < D/12.5 (h of the thesis mesh: the
    same threshold at every D/h);
  - contact_time: first gap < D/100;
  - tumbling_time: first time after kissing with y1 < y2, and
    tumbling_side: the side (+x or -x) the upper disc passes the lower one
    on (the initial offset puts the upper disc on the -x side: 10 um, D/200,
    as Glowinski et al. 2001, unless --offset says otherwise).
The kissing pair's turning, from its lateral offset s = x1 - x2
(tilt_measures): s/D at the contact, the growth rate of |s| while the
pair touches [1/s], and tumbling_after_tilt, the tumbling time minus the
first time |s| >= 0.1 D: a turning that grows from a seed set by the mesh
tumbles at a time that moves with the seed, while the growth and the time
from a given tilt are properties of the dynamics.
Cost: vansFoam's CPU seconds from stepTiming.dat.

usage: dktConvergence.py [--end T] [--workdir DIR] [--offset M] [D/h ...]
           build and run each level (default 12.5 18 25, 3 s) one after
           the other, then post-process
       dktConvergence.py --post CASEDIR ... [--offset M] [--note TEXT]
           the JSON and PNG from existing case directories
--offset M: the upper disc's initial offset from the centre line [m]
(default 1e-5, the tutorial's).  Writes tests/bench/results/dktConvergence.json
and tests/bench/dktConvergence/dktConvergence.png, or with another offset
dktConvergenceOffset<M in um>um.json / .png.  Assumes ./Allwmake has run.
"""

import argparse
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
TUT = os.path.join(ROOT, "tutorials", "vansFoam", "draftingKissingTumbling")
RESULTS = os.path.join(ROOT, "tests", "bench", "results")
sys.path.insert(0, os.path.join(ROOT, "src", "python"))
import nscdpost  # noqa: E402

setupCase = nscdpost.load_module("dkt_setupCase", os.path.join(TUT, "setupCase.py"))
postProcess = nscdpost.load_module("dkt_postProcess", os.path.join(TUT, "postProcess.py"))
D = setupCase.D
FIXED_GAP = D / 12.5  # h of the thesis mesh [m]
TIMES = ("kissing_time", "kissing_time_fixed_gap", "contact_time", "tumbling_time")


TILT = 0.1 * D  # lateral offset of the kissing pair that starts the tumbling clock [m]


def tilt_measures(t, x, contact, tumble):
    """The kissing pair's turning, from its lateral offset s = x1 - x2 [m]
    (discs' centres x [2, nt, 3], times t [s]): s/D at the first contact;
    the growth rate [1/s] of |s| while the pair touches (least-squares
    slope of ln|s| where 0.02 D <= |s| <= 0.2 D after the contact); the
    first time after the contact with |s| >= TILT (0.1 D) and the
    tumbling time minus it [s].  None where a time is None or no such
    point exists."""
    s = x[0, :, 0] - x[1, :, 0]
    out = {
        "lateral_offset_at_contact_over_D": None,
        "tilt_growth_rate_per_s": None,
        "tilt_time": None,
        "tumbling_after_tilt": None,
    }
    if contact is None:
        return out
    after = t >= contact - 1e-9
    out["lateral_offset_at_contact_over_D"] = float(s[after][0] / D)
    grow = after & (np.abs(s) >= 0.02 * D) & (np.abs(s) <= 0.2 * D)
    if tumble is not None:
        grow &= t <= tumble
    if grow.sum() >= 3:
        out["tilt_growth_rate_per_s"] = float(np.polyfit(t[grow], np.log(np.abs(s[grow])), 1)[0])
    tilted = np.flatnonzero(after & (np.abs(s) >= TILT))
    if tilted.size:
        out["tilt_time"] = float(t[tilted[0]])
        if tumble is not None:
            out["tumbling_after_tilt"] = tumble - out["tilt_time"]
    return out


def measure(case):
    """The times, the gap history and the cost of one case directory."""
    t, x, _ = postProcess.grain_history(case)
    h = postProcess.cell_size(case)
    kiss, tumble, gap = postProcess.dkt_measure(t, x, D, h)
    timing = nscdpost.step_timing(case)
    contact = postProcess.contact_time(t, x, D)
    return {
        "case": os.path.abspath(case),
        "cells_per_diameter": D / h,
        "h": h,
        "end_time": float(t[-1]),
        "kissing_time": kiss,
        "kissing_time_fixed_gap": postProcess.contact_time(t, x, D, tol=FIXED_GAP / D),
        "contact_time": contact,
        "tumbling_time": tumble,
        **tilt_measures(t, x, contact, tumble),
        # the side the upper disc (1) passes the lower one on: the sign of
        # x1 - x2 at the tumbling time
        "tumbling_side": (
            None
            if tumble is None
            else ("+x" if x[0, t == tumble, 0] > x[1, t == tumble, 0] else "-x")
        ),
        "min_gap": float(gap.min()),
        "steps": timing["steps"],
        "vansFoam_cpu_seconds": timing["executionTime"],
        "cpu_seconds_per_step_median": float(np.median(timing["cpu_per_step"])),
        "series": {
            "time": t.tolist(),
            "gap": gap.tolist(),
            "y1": x[0, :, 1].tolist(),
            "y2": x[1, :, 1].tolist(),
            "x1_minus_x2": (x[0, :, 0] - x[1, :, 0]).tolist(),
        },
    }


def output_name(offset):
    """dktConvergence for the tutorial's offset, else dktConvergenceOffset<um>um."""
    if abs(offset - setupCase.OFFSET) < 1e-12:
        return "dktConvergence"
    return f"dktConvergenceOffset{offset * 1e6:g}um"


def run_level(workdir, cpd, end, offset):
    """Build and run one level in workdir/dh<cpd>; returns the case path."""
    case = os.path.join(workdir, f"dh{cpd:g}")
    setupCase.dkt_case(case, end, cpd, rotation=True, max_dt=1e-3, resolved=True, offset=offset)
    nscdpost.run_apps(case, ("blockMesh", "grainDeposit", "vansFoam"))
    return case


def post(cases, offset, note=None):
    name = output_name(offset)
    levels = sorted((measure(c) for c in cases), key=lambda L: L["cells_per_diameter"])
    out = {
        "benchmark": name,
        "what": "tutorials/vansFoam/draftingKissingTumbling (resolved scheme, rotationCoupling "
        "yes, maxDeltaT 1e-3 s) at several D/h: kissing, contact and tumbling times",
        "command": "tests/bench/dktConvergence/dktConvergence.py "
        + ("" if name == "dktConvergence" else f"--offset {offset:g} ")
        + " ".join(f"{L['cells_per_diameter']:g}" for L in levels),
        "upper_disc_offset_m": offset,
        "reference": "self-convergence (no verified published kissing time; postProcess.py)",
        "fixed_gap_threshold_m": FIXED_GAP,
        "note": note,
        "levels": levels,
    }
    if len(levels) >= 2:
        a, b = levels[-2], levels[-1]
        out["change_between_two_finest"] = {
            k: (abs(b[k] - a[k]) / b[k] if a[k] is not None and b[k] is not None else None)
            for k in TIMES + ("tilt_growth_rate_per_s", "tumbling_after_tilt")
        }
    nscdpost.write_json(os.path.join(RESULTS, name + ".json"), out)
    for L in levels:
        print(
            f"D/h {L['cells_per_diameter']:5.3g}: "
            + ", ".join(f"{k} {L[k]}" for k in TIMES)
            + f", x1-x2 at contact {L['lateral_offset_at_contact_over_D']} D"
            + f", tilt growth {L['tilt_growth_rate_per_s']} 1/s"
            + f", tumbling {L['tumbling_after_tilt']} s after |x1-x2| = 0.1 D"
            + f", CPU {L['vansFoam_cpu_seconds']:.0f} s"
        )
    if "change_between_two_finest" in out:
        print("change between the two finest:", out["change_between_two_finest"])
    import nscdrender

    png = os.path.join(HERE, name + ".png")
    plt = nscdrender.pyplot(png)
    if plt is not None:
        fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
        for k, L in enumerate(levels):
            s = L["series"]
            lab = f"D/h = {L['cells_per_diameter']:.3g}"
            ax[0].semilogy(s["time"], np.maximum(np.array(s["gap"]) / D, 1e-6), f"C{k}", label=lab)
            ax[1].plot(s["time"], 100 * np.array(s["y1"]), f"C{k}", label=f"disc 1, {lab}")
            ax[1].plot(s["time"], 100 * np.array(s["y2"]), f"C{k}", ls="--", label=f"disc 2, {lab}")
            ax[2].semilogy(
                s["time"],
                np.maximum(np.abs(np.array(s["x1_minus_x2"])) / D, 1e-5),
                f"C{k}",
                label=lab,
            )
        ax[0].axhline(FIXED_GAP / D, color="k", lw=0.7, ls=":", label="gap D/12.5")
        ax[0].set_ylabel("gap / D")
        ax[1].set_ylabel("y [cm]")
        ax[2].axhline(TILT / D, color="k", lw=0.7, ls=":", label="0.1 D (tilt clock)")
        ax[2].set_ylabel("|x1 - x2| / D (pair's lateral offset)")
        for a in ax:
            a.set_xlabel("t [s]")
            a.grid(alpha=0.3)
            a.legend(fontsize=7)
        fig.suptitle(
            f"Drafting-kissing-tumbling, self-convergence in the mesh (offset {offset * 1e6:g} um)",
            fontsize=9,
        )
        fig.tight_layout()
        fig.savefig(png, dpi=120)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("levels", nargs="*", type=float, default=[12.5, 18, 25])
    ap.add_argument("--end", type=float, default=3.0)
    ap.add_argument("--workdir", default=os.path.join(HERE, "work"))
    ap.add_argument("--post", nargs="+", metavar="CASEDIR")
    ap.add_argument("--note", help="how the runs were made (machine, sharing), kept in the JSON")
    ap.add_argument(
        "--offset", type=float, default=setupCase.OFFSET, help="upper disc's offset [m]"
    )
    a = ap.parse_args()
    if not a.offset > 0:
        ap.error(f"--offset must be > 0 m, not {a.offset!r}")
    if a.post:
        post(a.post, a.offset, a.note)
        return
    os.makedirs(a.workdir, exist_ok=True)
    post([run_level(a.workdir, cpd, a.end, a.offset) for cpd in a.levels], a.offset, a.note)


if __name__ == "__main__":
    main()
