#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Falling-cloud post-processing: results.json, convergence.png, merging.png.

usage: postProcess.py [--convergence CASE ...] [--drop CASE ...]
                      [--merging CASE] [--window T0 T1] [--out results.json]

--convergence: single-cloud cases on different meshes (setupCase.py
--clouds 1 --cells-per-radius N); the cloud's terminal velocity is the
fall of its centroid (mean grain centre) between T0 and T1 (default 0.3
and 0.9 s: the plateau after the start-up of ~0.2 s, before the cloud's
slow deformation slows it), divided by T1 - T0, and the velocities are
fitted by v(h) = v_inf + C h^p (nscdpost.power_law_fit).  --drop: the
pure-fluid reference cases (setupCase.py --drop): the fall of the centroid
of alpha.water over the same window.  --merging: a two-cloud case: per
written time each cloud's centroid, mean velocity and extent, the gap
between the upper cloud's lowest grain edge and the lower cloud's highest
one; the merging time is when that gap first reaches 0 (linear between
written times).
"""

import argparse
import json
import os

import correlations
import nscdpost
import nscdrender
import numpy as np

THESIS_ORDER = 1.65  # thesis section 3.3: terminal velocity error O(h^1.65)
RHO_P, RHO_F, MU, PHI = 2450.0, 1030.0, 0.6, 0.2  # as setupCase.py


def references(radius, width):
    """Stokes terminal velocities of a body of the cloud's excess weight
    (rho_p - rho_f) phi g pi R^2 per unit length: in 2D midway between the
    box's side walls (correlations.faxen_cylinder_drag, k = 2 R / W) as a
    solid cylinder and as a drop of the fluid's viscosity (lambda = 1); the
    3D Hadamard-Rybczynski drop for scale."""
    drho = (RHO_P - RHO_F) * PHI
    weight = drho * correlations.G * np.pi * radius**2
    k = 2 * radius / width
    return {
        "channel_k": k,
        "channel_solid_cylinder": weight / (MU * correlations.faxen_cylinder_drag(k)),
        "channel_drop_lambda1": weight / (MU * correlations.faxen_cylinder_drag(k, 1.0)),
        "hadamard_rybczynski_3d": correlations.hadamard_rybczynski_velocity(drho, radius, MU),
    }


def setup(case):
    with open(os.path.join(case, "setup.json")) as f:
        return json.load(f)


def cloud_history(case):
    """Per written time, per cloud (grainId // grains per cloud): centroid
    height, mean vertical velocity, lowest and highest grain edge, count."""
    n = setup(case)["grains_per_cloud"]
    out = []
    for t, name in nscdpost.time_dirs(case):
        g = nscdpost.read_grains(case, name)
        k = np.asarray(g["grainId"], int) // n
        y, v, r = g["x"][:, 1], g["U"][:, 1], 0.5 * g["d"]
        row = {"time": t, "clouds": []}
        for c in range(int(k.max()) + 1):
            s = k == c
            row["clouds"].append(
                {
                    "centroid": float(y[s].mean()),
                    "velocity": float(v[s].mean()),
                    "lowest": float((y[s] - r[s]).min()),
                    "highest": float((y[s] + r[s]).max()),
                    "grains": int(s.sum()),
                }
            )
        out.append(row)
    return out


def drop_history(case):
    """(time, centroid height of alpha.water) of a pure-fluid drop case."""
    s = setup(case)
    h = s["h"]
    nx = round(s["width"] / h)
    t_out, y_out = [], []
    for t, name in nscdpost.numeric_dirs(case):
        path = os.path.join(case, name, "alpha.water")
        if not os.path.isfile(path):
            continue
        a = np.broadcast_to(nscdpost.read_internal_field(path), (nx * round(s["height"] / h),))
        yc = (np.arange(len(a)) // nx + 0.5) * h
        t_out.append(t)
        y_out.append(float((a * yc).sum() / a.sum()))
    return t_out, y_out


def fall_velocity(t, y, t0, t1):
    """-(y(t1) - y(t0)) / (t1 - t0), y interpolated linearly in t."""
    y0, y1 = np.interp([t0, t1], t, y)
    if t[-1] < t1 - 1e-9:
        raise ValueError(f"the run ends at {t[-1]} s, before the window's end {t1} s")
    return float(-(y1 - y0) / (t1 - t0))


def convergence(cases, window):
    rows = []
    for case in cases:
        s = setup(case)
        hist = cloud_history(case)
        t = [r["time"] for r in hist]
        y = [r["clouds"][0]["centroid"] for r in hist]
        grains_kept = all(r["clouds"][0]["grains"] == s["grains_per_cloud"] for r in hist)
        rows.append(
            {
                "case": os.path.basename(os.path.normpath(case)),
                "cells_per_radius": s["cells_per_radius"],
                "h": s["h"],
                "terminal_velocity": fall_velocity(t, y, *window),
                "grains_kept": grains_kept,
            }
        )
    rows.sort(key=lambda r: -r["h"])
    h = np.array([r["h"] for r in rows])
    v = np.array([r["terminal_velocity"] for r in rows])
    res = {"levels": rows, "window": list(window), "thesis_order": THESIS_ORDER}
    if len(rows) >= 3:
        p, vinf, c, rms = nscdpost.power_law_fit(h, v, np.linspace(0.2, 4.0, 381))
        res["fit"] = {"order": p, "v_inf": vinf, "C": c, "rms": rms}
        for r in rows:
            r["error"] = abs(r["terminal_velocity"] - vinf) / vinf
    return res


def merging(case):
    hist = cloud_history(case)
    t = np.array([r["time"] for r in hist])
    gap = np.array([r["clouds"][1]["lowest"] - r["clouds"][0]["highest"] for r in hist])
    dist = np.array([r["clouds"][1]["centroid"] - r["clouds"][0]["centroid"] for r in hist])
    res = {
        "time": t.tolist(),
        "gap": gap.tolist(),
        "centroid_distance": dist.tolist(),
        "velocity_lower": [r["clouds"][0]["velocity"] for r in hist],
        "velocity_upper": [r["clouds"][1]["velocity"] for r in hist],
        "grains": [sum(c["grains"] for c in r["clouds"]) for r in hist],
        "merging_time": None,
    }
    hit = np.nonzero(gap <= 0)[0]
    if len(hit) and hit[0] > 0:
        i = hit[0]
        res["merging_time"] = float(
            t[i - 1] + (t[i] - t[i - 1]) * gap[i - 1] / (gap[i - 1] - gap[i])
        )
    return res


def plots(res):
    plt = nscdrender.pyplot("convergence.png")
    if plt is None:
        return
    conv = res.get("convergence")
    if conv and "fit" in conv:
        h = np.array([r["h"] for r in conv["levels"]])
        e = np.array([r["error"] for r in conv["levels"]])
        fig, ax = plt.subplots(figsize=(5, 4))
        ax.loglog(h * 1e3, e, "o", label="|v - v_inf| / v_inf")
        hh = np.geomspace(h.min(), h.max())
        fit = conv["fit"]
        ax.loglog(
            hh * 1e3,
            abs(fit["C"]) * hh ** fit["order"] / fit["v_inf"],
            "-",
            label=f"fit: order {fit['order']:.2f}",
        )
        ax.loglog(
            hh * 1e3,
            e[-1] * (hh / h[-1]) ** THESIS_ORDER,
            "--",
            label=f"thesis: order {THESIS_ORDER}",
        )
        nscdrender.save_plot(fig, ax, "convergence.png", "h [mm]", "terminal velocity error")
    mer = res.get("merging")
    if mer:
        fig, ax = plt.subplots(figsize=(5, 4))
        ax.plot(mer["time"], np.array(mer["gap"]) * 1e3, label="gap between the clouds")
        ax.plot(mer["time"], np.array(mer["centroid_distance"]) * 1e3, label="centroid distance")
        if mer["merging_time"] is not None:
            ax.axvline(mer["merging_time"], color="k", ls=":", label="merging")
        nscdrender.save_plot(fig, ax, "merging.png", "t [s]", "[mm]")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--convergence", nargs="*", default=[])
    ap.add_argument("--drop", nargs="*", default=[])
    ap.add_argument("--merging")
    ap.add_argument("--window", nargs=2, type=float, default=(0.3, 0.9))
    ap.add_argument("--out", default="results.json")
    a = ap.parse_args()
    res = {}
    if a.convergence:
        res["convergence"] = convergence(a.convergence, a.window)
        for r in res["convergence"]["levels"]:
            print(
                f"{r['case']}: R/h {r['cells_per_radius']:g}, terminal velocity "
                f"{r['terminal_velocity'] * 1e3:.3f} mm/s"
            )
        if "fit" in res["convergence"]:
            f = res["convergence"]["fit"]
            print(
                f"fit: v_inf {f['v_inf'] * 1e3:.3f} mm/s, order {f['order']:.2f} "
                f"(thesis {THESIS_ORDER})"
            )
    if a.convergence:
        s = setup(a.convergence[0])
        res["reference"] = references(s["cloud_radius"], s["width"])
        print(
            "references [mm/s]: "
            + ", ".join(
                f"{k} {v * 1e3:.3f}" for k, v in res["reference"].items() if k != "channel_k"
            )
        )
    if a.drop:
        res["drop"] = []
        for case in a.drop:
            t, y = drop_history(case)
            s = setup(case)
            v = fall_velocity(t, y, *a.window)
            res["drop"].append(
                {
                    "case": os.path.basename(os.path.normpath(case)),
                    "h": s["h"],
                    "viscosity_ratio": s["drop_viscosity_ratio"],
                    "terminal_velocity": v,
                }
            )
            print(f"{case}: pure-fluid drop, terminal velocity {v * 1e3:.3f} mm/s")
    if a.merging:
        res["merging"] = merging(a.merging)
        print(f"{a.merging}: merging time {res['merging']['merging_time']} s")
    nscdpost.write_json(a.out, res)
    plots(res)


if __name__ == "__main__":
    main()
