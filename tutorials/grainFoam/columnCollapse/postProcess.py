#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Column collapse post-processing: results.json and runout.png.

usage: postProcess.py CASEDIR [CASEDIR ...]   (one per aspect ratio)

Measured per case, from the lagrangian grains of the first and last times:
  initial_width  L_i: the gate position (grains settled against it),
  initial_height H_i: top of the settled column, max(y + r), above the rough
                 floor (a row of fixed grains, excluded from all measures),
  runout         L_f: right-most point, max(x + r), of the deposit, i.e. of the
                 grains connected to the left wall through contacts (gap below
                 5 % of the mean diameter); isolated grains thrown ahead do not
                 count (as in Staron & Hinch 2005),
  final_height   H_f: top of the deposit, max(y + r) over the same grains,
  final_max_speed: largest grain speed in the deposit at the last time,
  runout_change_last_interval: L_f minus the runout one write interval earlier.
Reference: Staron & Hinch (2005) and Lube et al. (2005), see REFERENCE below.
"""

import os
import sys

import nscdpost
import nscdrender
import numpy as np

REFERENCE = {
    "source": "Lube, Huppert, Sparks & Freundt (2005) Phys. Rev. E 72, 041301, 2D columns: "
    "(L_f-L_i)/L_i = 1.2 a for a < 1.8 and 1.9 a^(2/3) for a > 2.8",
}


def runout_law(a):
    """Normalised runout (L_f - L_i)/L_i of the cited law (linear, then a^(2/3))."""
    a = np.asarray(a, dtype=float)
    return np.where(a < 2.3, 1.2 * a, 1.9 * a ** (2.0 / 3.0))


def deposit_cluster(x, r, tol):
    """Indices of the grains connected (gap < tol) to the left wall x = 0."""
    n = len(r)
    dx = x[:, None, 0] - x[None, :, 0]
    dy = x[:, None, 1] - x[None, :, 1]
    gap = np.sqrt(dx * dx + dy * dy) - (r[:, None] + r[None, :])
    adj = gap < tol
    seen = np.zeros(n, dtype=bool)
    front = list(np.where(x[:, 0] - r < tol)[0])
    seen[front] = True
    while front:
        nxt = np.where(adj[front].any(axis=0) & ~seen)[0]
        seen[nxt] = True
        front = list(nxt)
    return np.where(seen)[0]


def measure(case):
    params = dict(l.split() for l in open(os.path.join(case, "caseParameters")))
    times = nscdpost.time_dirs(case)
    if len(times) < 2:
        raise SystemExit(f"{case}: need the initial and a final time with grains")
    g0 = nscdpost.read_grains(case, times[0][1])
    g1 = nscdpost.read_grains(case, times[-1][1])
    L_i = float(params["gateX"])
    # the rough floor (fixed grains) is the reference level y0
    floor = g0["fixed"]
    y0 = float(np.max(g0["x"][floor, 1] + 0.5 * g0["d"][floor])) if floor.any() else 0.0
    m0, m1 = ~g0["fixed"], ~g1["fixed"]
    H_i = float(np.max(g0["x"][m0, 1] + 0.5 * g0["d"][m0])) - y0
    x1 = g1["x"][m1]
    r = 0.5 * g1["d"][m1]
    idx = deposit_cluster(x1, r, 0.05 * np.mean(2 * r))
    L_f = float(np.max(x1[idx, 0] + r[idx]))
    H_f = float(np.max(x1[idx, 1] + r[idx])) - y0
    vmax = float(np.max(np.linalg.norm(g1["U"][m1][idx], axis=1)))
    # runout one write interval earlier: the front must have stopped
    gp = nscdpost.read_grains(case, times[-2][1])
    mp = ~gp["fixed"]
    rp = 0.5 * gp["d"][mp]
    idp = deposit_cluster(gp["x"][mp], rp, 0.05 * np.mean(2 * rp))
    L_prev = float(np.max(gp["x"][mp][idp, 0] + rp[idp]))
    return {
        "aspect_ratio": H_i / L_i,
        "nominal_aspect_ratio": float(params["aspectRatio"]),
        "grains": int(len(r)),
        "fixed_floor_grains": int(np.count_nonzero(g1["fixed"])),
        "friction": float(params["friction"]),
        "initial_width": L_i,
        "initial_height": H_i,
        "runout": L_f,
        "final_height": H_f,
        "normalised_runout": (L_f - L_i) / L_i,
        "reference_normalised_runout": float(runout_law(H_i / L_i)),
        "deposit_fraction": len(idx) / len(r),
        "final_max_speed": vmax,
        "runout_change_last_interval": L_f - L_prev,
        "mean_diameter": float(np.mean(2 * r)),
        "final_time": times[-1][0],
    }


def main():
    cases = sys.argv[1:]
    results = [measure(c) for c in cases]
    out = {"cases": results, "reference": REFERENCE}
    nscdpost.write_json("results.json", out)
    plt = nscdrender.pyplot("runout.png")
    if plt is not None:
        a = np.linspace(0.2, 8, 200)
        fig, ax = plt.subplots(figsize=(5, 4))
        ax.loglog(a, runout_law(a), "k-", label="Lube et al. 2005 (2D)")
        ax.loglog(
            [c["aspect_ratio"] for c in results],
            [c["normalised_runout"] for c in results],
            "o",
            color="C3",
            label="grainFoam (NSCD discs)",
        )
        ax.set_xlabel("aspect ratio a = H_i / L_i")
        ax.set_ylabel("(L_f - L_i) / L_i")
        ax.legend()
        ax.grid(True, which="both", alpha=0.3)
        fig.tight_layout()
        fig.savefig("runout.png", dpi=120)
    for c in results:
        print(
            f"a = {c['aspect_ratio']:.2f}: (L_f-L_i)/L_i = {c['normalised_runout']:.2f} "
            f"(law {c['reference_normalised_runout']:.2f}), H_f/L_i = {c['final_height'] / c['initial_width']:.2f}"
        )


if __name__ == "__main__":
    main()
