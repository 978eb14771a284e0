#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Post-process granularCollapse configurations (thesis section 5.2).

usage: postProcess.py OUTDIR CASEDIR [CASEDIR ...]

For each case (made by setupCase.py and run): the front Froude number
Fr_f = v_f / sqrt(g h0) written by the granularFront function object (max
horizontal front velocity at y = h0, least-squares slope over 0.05 s), the
maximum free-surface elevation at the first wave gauge (waveGauges), the
regime of Sarlin et al. (2021, JFM 919 R6; thesis section 5.2: nonlinear
transition Fr_f < 0.35, solitary 0.35-0.87, bore > 0.87), and a PNG of the
elevation vs time at the gauges next to the reference amplitude of the
piston model: a vertical piston advancing at v_f into water of depth h0
drives a bore of height h1 with v_f = (h1 - h0) sqrt(g (h1 + h0)/(2 h1 h0))
(shallow-water bore, Stoker 1957, Water Waves, section 10.6; Sarlin et al.
use this piston picture for the bore and solitary regimes).  OUTDIR gets
results.json (one entry per configuration) and <config>.png.
"""

import json
import math
import os
import sys

import numpy as np

G = 9.81
# thesis Table 5.1: Fr_f of the PFEM-DEM runs and of Sarlin et al.'s experiments
TABLE_5_1 = {
    "nonlinearTransition": {"experiment": 1, "thesis": 0.27, "sarlin": 0.19},
    "solitary": {"experiment": 2, "thesis": 0.83, "sarlin": 0.65},
    "bore": {"experiment": 3, "thesis": 1.93, "sarlin": 1.39},
}
EXPECTED_REGIME = {
    "nonlinearTransition": "nonlinear_transition",
    "solitary": "solitary",
    "bore": "bore",
}


def regime(fr):
    """Wave regime of Sarlin et al. (2021) from the front Froude number."""
    if not math.isfinite(fr) or fr < 0:
        raise ValueError(f"front Froude number {fr} is not a finite value >= 0")
    if fr < 0.35:
        return "nonlinear_transition"
    if fr <= 0.87:
        return "solitary"
    return "bore"


def piston_bore_amplitude(v, h0, g=G):
    """Bore height h1 - h0 [m] ahead of a piston moving at v [m/s] into water
    of depth h0 [m] (shallow-water bore relations), by bisection."""

    def f(h1):
        return (h1 - h0) * math.sqrt(g * (h1 + h0) / (2 * h1 * h0)) - v

    lo, hi = h0, 2 * h0
    while f(hi) < 0:
        hi *= 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi) - h0


def read_dat(path):
    rows = []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        rows.append([float(v) for v in line.split()])
    return np.array(rows)


def dat_path(case, name, fname):
    base = os.path.join(case, "postProcessing", name)
    times = sorted(os.listdir(base), key=float)
    return os.path.join(base, times[0], fname)


def measure(case):
    params = json.load(open(os.path.join(case, "caseParameters.json")))
    front = read_dat(dat_path(case, "front", "granularFront.dat"))
    gauges = read_dat(dat_path(case, "gauges", "waveGauges.dat"))
    vf = float(np.nanmax(front[:, 3]))
    fr = vf / math.sqrt(G * params["h0"])
    return (
        params,
        front,
        gauges,
        {
            "front_froude_number": fr,
            "max_front_velocity": vf,
            "max_wave_amplitude": float(np.max(gauges[:, 1])),
            "gauge_x": params["gauges"][0],
            "water_depth": params["h0"],
            "column_height": params["H0"],
            "column_width": params["L0"],
            "regime": regime(fr),
        },
    )


def plot(path, config, params, gauges, res):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    for k, x in enumerate(params["gauges"]):
        ax.plot(gauges[:, 0], gauges[:, 1 + k] * 1e3, label=f"nscdFoam, x = {x:.2f} m")
    a = piston_bore_amplitude(res["max_front_velocity"], params["h0"])
    ax.axhline(
        a * 1e3, color="k", ls="--", label=f"piston bore at v_f (Stoker 1957): {a * 1e3:.1f} mm"
    )
    ax.set_xlabel("t [s]")
    ax.set_ylabel("free-surface elevation [mm]")
    ax.set_title(
        f"{config}: Fr_f = {res['front_froude_number']:.2f} -> {res['regime']}"
        f" (thesis {TABLE_5_1[config]['thesis']}, Sarlin {TABLE_5_1[config]['sarlin']})"
    )
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    """argv: OUTDIR CASEDIR [CASEDIR ...] (default: the command line, sys.argv[1:])."""
    args = sys.argv[1:] if argv is None else list(argv)
    if len(args) < 2:
        sys.exit(__doc__)
    out = args[0]
    results = {}
    for case in args[1:]:
        params, front, gauges, res = measure(case)
        config = params["config"]
        res["piston_bore_amplitude"] = piston_bore_amplitude(
            res["max_front_velocity"], params["h0"]
        )
        res["thesis_front_froude_number"] = TABLE_5_1[config]["thesis"]
        res["sarlin_front_froude_number"] = TABLE_5_1[config]["sarlin"]
        res["expected_regime"] = EXPECTED_REGIME[config]
        results[config] = res
        plot(os.path.join(out, f"{config}.png"), config, params, gauges, res)
        print(
            f"{config}: Fr_f = {res['front_froude_number']:.3f} ({res['regime']}), "
            f"max elevation {res['max_wave_amplitude'] * 1e3:.2f} mm"
        )
    path = os.path.join(out, "results.json")
    if os.path.isfile(path):
        old = json.load(open(path))
        old.update(results)
        results = old
    with open(path, "w") as f:
        json.dump(results, f, indent=2, sort_keys=True)
        f.write("\n")


if __name__ == "__main__":
    main()
