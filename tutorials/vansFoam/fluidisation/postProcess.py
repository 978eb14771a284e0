#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Fluidisation post-processing: results.json and fluidisation.png.

usage: postProcess.py CASEDIR [CASEDIR ...]   (one per mesh, made by setupCase.py)

Thesis section 3.3.2: a grain is mobilised when it has moved more than the
largest diameter from its initial position; first movement when 5 % of the
grain mass is mobilised, total heave at 95 %.  The differential head between
the bottom and the initial top of the layer (eq. 3.52),
    dh = psi_bottom - psi_top,  psi = y + p/(rho g) + |u|^2/(2 g),
with p/rho the kinematic pressure: at the bottom the imposed p_b(t)
(eq. 3.53, the floor is the boundary) and u from the inflow, at the top the
mean of the probes on the initial top of the layer (system/controlDict).
Reference for the heave head: the buoyant weight of the bed per unit width,
dh_w = sum_p V_p (rho_p - rho)/(rho W) (the whole bed lifts when the
pressure force on it balances its weight), and the thesis' 0.22 m (2D) /
0.19 m (experiment) for its own, taller bed.
"""

import json
import os
import sys

import nscdpost
import nscdrender
import numpy as np

G, RHO, RHO_P = 9.81, 1000.0, 2630.0


def read_probes(path):
    """(time, values[nt, nprobe, ncomp]) of an OpenFOAM probes file."""
    t, rows = [], []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        parts = line.replace("(", " ").replace(")", " ").split()
        t.append(float(parts[0]))
        rows.append([float(x) for x in parts[1:]])
    return np.array(t), np.array(rows)


def crossing(t, f, level):
    """First time f(t) reaches level (linear interpolation), or None."""
    idx = np.nonzero(f >= level)[0]
    if len(idx) == 0:
        return None
    k = idx[0]
    if k == 0:
        return float(t[0])
    return float(t[k - 1] + (level - f[k - 1]) * (t[k] - t[k - 1]) / (f[k] - f[k - 1]))


def measure(case):
    bed = json.load(open(os.path.join(case, "bed.json")))
    times = nscdpost.time_dirs(case)
    g0 = nscdpost.read_grains(case, times[0][1])
    mass = RHO_P * np.pi / 4 * g0["d"] ** 2  # per unit depth (2D)
    dmax = g0["d"].max()
    t, mobilised = [], []
    for time, name in times:
        g = nscdpost.read_grains(case, name)
        moved = np.linalg.norm(g["x"][:, :2] - g0["x"][:, :2], axis=1) > dmax
        t.append(time)
        mobilised.append(float(mass[moved].sum() / mass.sum()))
    t, mobilised = np.array(t), np.array(mobilised)
    # differential head
    pdir = os.path.join(case, "postProcessing", "headProbes", "0")
    tp, p = read_probes(os.path.join(pdir, "p"))
    _, U = read_probes(os.path.join(pdir, "U"))
    n = p.shape[1]
    u2 = (U.reshape(len(tp), n, 3) ** 2).sum(axis=2).mean(axis=1)
    p_top = p.mean(axis=1)
    p_bot = bed["p0"] + G * bed["head_rate"] * tp  # eq. 3.53 (kinematic)
    head = p_bot / G - (bed["bed_top"] + p_top / G + u2 / (2 * G))
    t_first = crossing(t, mobilised, 0.05)
    t_heave = crossing(t, mobilised, 0.95)
    heave_head = float(np.interp(t_heave, tp, head)) if t_heave is not None else None
    buoyant = float(np.sum(np.pi / 4 * g0["d"] ** 2) * (RHO_P - RHO) / RHO / bed["width"])
    return {
        "h_over_d": bed["h_over_d"],
        "first_movement_time": t_first,
        "heave_time": t_heave,
        "heave_head": heave_head,
        "buoyant_weight_head": buoyant,
        "bed_height": bed["bed_top"],
        "time": t.tolist(),
        "mobilised_mass_fraction": mobilised.tolist(),
        "head_time": tp[:: max(1, len(tp) // 400)].tolist(),
        "differential_head": head[:: max(1, len(tp) // 400)].tolist(),
    }


def main():
    res = {}
    for case in sys.argv[1:]:
        r = measure(case)
        res[f"{r['h_over_d']:g}"] = r
    nscdpost.write_json("results.json", res)
    for k, r in sorted(res.items(), key=lambda kv: float(kv[0])):
        hh = r["heave_head"]
        print(
            f"h/d = {k}: first movement {r['first_movement_time']} s, heave {r['heave_time']} s, "
            f"heave head {hh if hh is None else round(hh, 5)} m (bed buoyant weight "
            f"{r['buoyant_weight_head']:.5f} m)"
        )
    plt = nscdrender.pyplot("fluidisation.png")
    if plt is not None:
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
        for k, r in sorted(res.items(), key=lambda kv: float(kv[0])):
            a1.plot(r["time"], r["mobilised_mass_fraction"], label=f"h/d = {k}")
            a2.plot(r["head_time"], r["differential_head"], label=f"h/d = {k}")
        any_r = next(iter(res.values()))
        for lvl in (0.05, 0.95):
            a1.axhline(lvl, color="k", lw=0.5, ls=":")
        a2.axhline(
            any_r["buoyant_weight_head"], color="k", ls="--", label="bed buoyant weight / (rho g W)"
        )
        a1.set_xlabel("t [s]")
        a1.set_ylabel("mobilised mass fraction [-]")
        a2.set_xlabel("t [s]")
        a2.set_ylabel("differential head [m]")
        a1.legend(fontsize=8)
        a2.legend(fontsize=8)
        a1.grid(alpha=0.3)
        a2.grid(alpha=0.3)
        fig.suptitle("Fluidisation of a granular layer (thesis Fig. 3.17)")
        fig.tight_layout()
        fig.savefig("fluidisation.png", dpi=120)


if __name__ == "__main__":
    main()
