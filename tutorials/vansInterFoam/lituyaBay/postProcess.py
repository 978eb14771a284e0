#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""lituyaBay post-processing: gauge elevation, run-up, slide front Froude
number, water volume and energy checks; results.json, gauge.png, runup.png.

usage: postProcess.py CASEDIR

- Gauge (x = 885 m from the initial left shore, as the wave gauge of Fritz et
  al. 2001 at prototype scale): free-surface elevation eta(t) = int alpha dy - H
  along the vertical x = 885 m, alpha.water sampled by the `sets` function
  object `gauge` (cellPoint, 0.5 m spacing) every 0.1 s (reduced: 0.2 s).
- Run-up on the right shore R(t): the highest cell centre with alpha.water
  >= 0.5 beyond the right toe (x > L - H); resolution +-h/2 of the local cell
  size (4 m full, 25 m reduced).  max_runup = max_t R, from engineer B's
  `runUp` function object (every step) when it ran, else from the written
  fields (write times; both are in results.json, and agree at write times).
- Engineer B's `waveGauges` and `granularFront` also run; their values are
  recorded (`waveGauges_eta_*`, `granularFront_froude_number`) but not used:
  on this unstructured gmsh mesh `waveGauges` (probably summing alpha dy over cells whose
  x-extents hold x = 885 m, whose y-extents overlap) gives eta = 68 m at t = 0 in
  the reduced copy instead of 0, and `granularFront`'s front jumps when a
  large grain enters the band at y = 0 (v_f = 167 m/s, Fr = 4.8, against a
  grain speed of ~51 m/s there).
- Slide front: the 10 % lowest grains; the front enters the water when the
  lowest grain centre crosses y = 0; v_f = mean speed of the front grains at
  the write time just before that crossing (and just after, the larger of the
  two), Fr_f = v_f / sqrt(g H) (thesis section 5.3.1: 110 m/s, Fr = 3.18;
  bore regime Fr_f > 0.87, Sarlin et al., thesis section 5.2).
- Impact speed three ways (slideMetrics.py): the front's (above), the
  mass-flux-weighted speed of the grains crossing y = 0 and the centre of
  mass's speed as its height crosses y = 0, both per step from the
  `grainCentreOfMass` function object; F = v / sqrt(g H) for each
  (`impact_froude_number`: the centre of mass's, thesis 3.18).
- Run-up as a water layer: the highest point of the right shore reached by
  an unbroken layer >= 1 m thick measured along the shore's normal
  (`max_runup_layer`, write times), beside the alpha >= 0.5 run-up.
- Water volume sum(eps alpha V) from the solver log (every step); the water
  balance adds the volume that left with spray through the atmosphere
  (`atmosphereFlux`): sum(eps alpha V) + outflow = const to round-off.
- Energy bound (conservation of energy, dissipation >= 0, air's share
  neglected, 2 % margin): the rise of the water's centre of mass satisfies
  dz_w(t) <= dE_slide(t) / (m_w g), dE_slide the potential energy lost by the
  grains up to t plus their kinetic energy at t = 0 (a launched slide,
  SLIDE_SPEED), m_w the water mass.  The run-up bound of the issue is the
  same ratio with the slide's whole drop down to the bay bottom,
  R_E = m_s (g (z_s0 + H) + v_0^2/2) / (m_w g), v_0 the launch speed
  (order-of-magnitude ceiling; a thin film
  can in principle exceed it, the centre-of-mass check cannot).  The same
  check in energies: `water_potential_energy_rise_max` against
  `slide_potential_energy_drop_then` and `energy_bound_excess` <= 0.

References plotted: the thesis' stated numbers (section 5.3): ~60 m initial
wave, 524 m historical run-up, 500-750 m for the thesis' 2D PFEM run.  The
digitised gauge record of Fritz et al. (2001, 2009) (thesis Fig. 5.12) was not
available to us: it is not plotted.
"""

import json
import math
import os
import sys

import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
slideMetrics = nscdpost.load_module("lituyaBay_slideMetrics", os.path.join(here, "slideMetrics.py"))

G = 9.81
RHO_W = 1000.0
WAVE_REF = 60.0  # [m] initial wave height, thesis section 5.3
RUNUP_HISTORICAL = 524.0  # [m] Miller (1960), thesis section 5.3
RUNUP_THESIS = (500.0, 750.0)  # [m] thesis section 5.3.2, Fig. 5.11


def water_volumes(case):
    """(t, V): the times [s] and sum(eps alpha V) [m^3] of every step of a
    vansInterFoam run, from postProcessing/waterVolume/<start>/waterVolume.dat
    (the values of the log's "water volume" line)."""
    d = nscdpost.read_step_data(case, "waterVolume")
    return d["Time"], d["waterVolume"]


def atmosphere_outflow(case, times):
    """(n,) cumulative water volume [m^3] that left through the atmosphere
    by each of `times` (the water-volume steps): sum F_k dt_k over the rows
    of the `atmosphereFlux` function object up to that time, F_k its sum of
    alphaPhi0.water over the patch (m^3/s, outflow > 0).  Aligned by time:
    a run stopped by a signal writes its last step's water volume but not
    that step's flux row (that step's outflow is then counted with the next
    row's flux, over both steps' dt)."""
    d = nscdpost.read_dat_history(case, "atmosphereFlux", "surfaceFieldValue.dat")
    dt = np.diff(np.concatenate([[0.0], d[:, 0]]))
    cum = np.concatenate([[0.0], np.cumsum(d[:, 1] * dt)])
    return cum[np.searchsorted(d[:, 0], np.asarray(times) * (1 + 1e-12), side="right")]


def outflow_known(case, times):
    """(n,) bool: the water-volume steps of `times` whose outflow is known,
    those up to the last `atmosphereFlux` row.  A run stopped by a signal
    writes its last step's water volume without that step's flux row: its
    outflow is unknown and the balance is not checked there."""
    d = nscdpost.read_dat_history(case, "atmosphereFlux", "surfaceFieldValue.dat")
    last = d[-1, 0] if len(d) else -np.inf
    return np.asarray(times) <= last * (1 + 1e-12)


def gauge_history(case, H):
    """(t, eta) [s, m]: eta = int alpha dy - H on the gauge line of the `gauge`
    sets function object (postProcessing/gauge/<time>/x885_alpha.water.xy,
    from the bay bottom y = -H upwards)."""
    root = os.path.join(case, "postProcessing", "gauge")
    t, eta = [], []
    for name in sorted(os.listdir(root), key=float):
        path = os.path.join(root, name, "x885_alpha.water.xy")
        if not os.path.isfile(path):
            continue
        y, alpha = np.loadtxt(path, unpack=True)
        t.append(float(name))
        eta.append(float(nscdpost.trapezoid(np.clip(alpha, 0, 1), y)) - H)
    return np.array(t), np.array(eta)


def field(case, tname, name, n):
    """Internal scalar field `name` at time tname as an (n,) array."""
    a = nscdpost.read_internal_field(os.path.join(case, tname, name))
    return np.full(n, float(a)) if a.ndim == 0 else a


def histories(case, p):
    """Run-up, water centre of mass, slide energy and front at every write time."""
    C = nscdpost.read_internal_field(os.path.join(case, "0", "C"))
    V = nscdpost.read_internal_field(os.path.join(case, "0", "V"))
    n = len(V)
    L, H = p["bay_length"], p["water_depth"]
    shore = C[:, 0] > L - H
    keys = ("t", "runup", "layer_runup", "zw", "mw", "dE", "front_y", "front_v")
    out = {k: [] for k in keys}
    g0 = None
    for t, name in nscdpost.time_dirs(case):
        alpha = np.clip(field(case, name, "alpha.water", n), 0, 1)
        epsf = os.path.join(case, name, "voidFraction")
        eps = field(case, name, "voidFraction", n) if os.path.isfile(epsf) else np.ones(n)
        w = eps * alpha * V
        wet = shore & (alpha >= 0.5)
        out["t"].append(t)
        out["runup"].append(float(C[wet, 1].max()) if wet.any() else -H)
        out["layer_runup"].append(layer_runup(C, alpha, V, p))
        out["mw"].append(RHO_W * float(w.sum()))
        out["zw"].append(float(np.sum(w * C[:, 1]) / w.sum()))
        g = nscdpost.read_grains(case, name)
        m = p["grain_density"] * math.pi / 4 * g["d"] ** 2 * p["thickness"]
        if g0 is None:
            g0 = g
            # the slide's kinetic energy at t = 0 (a launched slide, SLIDE_SPEED)
            ke0 = 0.5 * float(np.sum(m * np.sum(g0["U"] ** 2, axis=1)))
        # the energy the slide has given up by t: its potential-energy drop
        # plus its kinetic energy at t = 0
        out["dE"].append(float(G * np.sum(m * (g0["x"][:, 1] - g["x"][:, 1]))) + ke0)
        k = max(1, len(g["d"]) // 10)
        lead = np.argsort(g["x"][:, 1])[:k]
        out["front_y"].append(float(g["x"][:, 1].min()))
        out["front_v"].append(float(np.mean(np.linalg.norm(g["U"][lead], axis=1))))
    return {k: np.array(v) for k, v in out.items()}


def layer_runup(C, alpha, V, p, min_thickness=1.0):
    """Run-up height [m] above still water of the water layer on the right
    shore: the highest point of an unbroken layer >= min_thickness thick
    (int alpha along the shore's normal, slideMetrics.shore_layer, bins of
    the fine cell size) from the toe up; -H if the toe is dry."""
    L, H = p["bay_length"], p["water_depth"]
    s, h = slideMetrics.shore_layer(C, alpha, V, (L - H, -H), depth=p["thickness"], ds=p["h_fine"])
    top = slideMetrics.layer_runup(s, h, min_thickness)
    return -H if top is None else top / math.sqrt(2) - H


def impact_measures(case, h, p):
    """Impact speeds from the grainCentreOfMass function object (per step):
    the centre of mass's speed as its height crosses y = 0 and the
    mass-flux-weighted speed of the grains crossing y = 0; with their Froude
    numbers F = v / sqrt(g H) (thesis 3.18) and the front's."""
    H = p["water_depth"]
    vf, _fr, t_front = front_froude(h, H)
    d = nscdpost.read_step_data(case, "grainCentreOfMass")
    speed = np.sqrt(d["Ux"] ** 2 + d["Uy"] ** 2 + d["Uz"] ** 2)
    t_com, v_com = slideMetrics.centre_of_mass_impact(d["Time"], d["y"], speed)
    v_flux, m_in = slideMetrics.flux_weighted_speed(d["Time"], d["massFlux"], d["speedMassFlux"])
    return {
        "impact_speed_front": vf,
        "impact_speed_flux_weighted": v_flux,
        "impact_speed_centre_of_mass": v_com,
        "impact_time_centre_of_mass": t_com,
        "impact_crossed_mass_fraction": m_in / d["mass"][0],
        "impact_froude_number": slideMetrics.froude(v_com, H),
        "impact_froude_numbers": {
            "front": slideMetrics.froude(vf, H),
            "flux_weighted": slideMetrics.froude(v_flux, H),
            "centre_of_mass": slideMetrics.froude(v_com, H),
        },
        "impact_froude_definition": "F = v_s / sqrt(g h), h = bay depth at impact = 122 m"
        " (thesis 5.3.1: 110 m/s -> 3.18)",
        "slide_centre_height_initial": float(d["y"][0]),
        "slide_centre_height_min": float(d["y"].min()),
        "slide_potential_energy_drop_per_step_max": float(
            G * d["mass"][0] * (d["y"][0] - d["y"].min())
        ),
    }


def fo_table(case, name):
    """(n, k) table of a function object's <name>/<start>/<type>.dat, restarts
    joined (nscdpost.read_dat_history), or None when it did not run."""
    root = os.path.join(case, "postProcessing", name, "0")
    if not os.path.isdir(root):
        return None
    dats = sorted(f for f in os.listdir(root) if f.endswith(".dat"))
    return nscdpost.read_dat_history(case, name, dats[0]) if dats else None


def front_froude(h, H):
    """(v_f, Fr_f, t_impact): front speed around the water entry."""
    fy, fv, t = h["front_y"], h["front_v"], h["t"]
    after = np.nonzero(fy < 0)[0]
    if len(after) == 0 or after[0] == 0:
        return float("nan"), float("nan"), float("nan")
    i = after[0]
    v = max(fv[i - 1], fv[i])
    return float(v), float(v / math.sqrt(G * H)), float(t[i])


def main():
    case = sys.argv[1] if len(sys.argv) > 1 else "full"
    p = json.load(open(os.path.join(case, "caseParameters.json")))
    H = p["water_depth"]
    tv, vols = water_volumes(case)
    out = atmosphere_outflow(case, tv)
    tg, eta = gauge_history(case, H)
    h = histories(case, p)
    vf, fr, t_imp = front_froude(h, H)
    mw = h["mw"][0]
    dzw = h["zw"] - h["zw"][0]
    ebound = h["dE"] / (mw * G)
    v0 = p.get("slide_launch_speed", 0.0)
    runup_bound = p["slide_mass"] * (G * (p["slide_centre_height"] + H) + 0.5 * v0**2) / (mw * G)
    i = int(np.argmax(h["runup"]))
    j = int(np.argmax(h["layer_runup"]))
    budget = slideMetrics.energy_budget(mw * G * dzw, h["dE"])
    # engineer B's function objects (src/freeSurfaceFunctionObjects), when present
    ru, wg, gf = fo_table(case, "runUp"), fo_table(case, "gauges"), fo_table(case, "front")
    if ru is not None:
        runup_t, runup, max_runup = ru[:, 0], ru[:, 1], float(ru[-1, 2])
        max_runup_time = float(ru[int(np.argmax(ru[:, 1])), 0])
    else:
        runup_t, runup = h["t"], h["runup"]
        max_runup, max_runup_time = float(h["runup"][i]), float(h["t"][i])
    res = {
        "mode": p["mode"],
        "slope_friction": p.get("slope_friction", 0.93),
        "slide_launch_speed": p.get("slide_launch_speed", 0.0),
        "gauge_x": p["gauge_x"],
        "gauge_time": tg.tolist(),
        "gauge_elevation": eta.tolist(),
        "max_gauge_elevation": float(eta.max()),
        "runup_time": runup_t.tolist(),
        "runup": runup.tolist(),
        "max_runup": max_runup,
        "max_runup_time": max_runup_time,
        "runup_measured_by": "runUp function object (every step)"
        if ru is not None
        else "postProcess.py (write times)",
        "max_runup_write_times": float(h["runup"][i]),
        "max_runup_layer": float(h["layer_runup"][j]),
        "max_runup_layer_time": float(h["t"][j]),
        "runup_layer": h["layer_runup"].tolist(),
        "runup_layer_definition": "highest point of an unbroken water layer >= 1 m thick"
        " (int alpha along the shore normal, bins of the fine cell size) on the right shore,"
        " write times",
        "waveGauges_eta_initial": float(wg[0, 1]) if wg is not None else None,
        "waveGauges_eta_max": float(wg[:, 1].max()) if wg is not None else None,
        "granularFront_froude_number": float(gf[-1, 4]) if gf is not None else None,
        "runup_energy_bound": float(runup_bound),
        "front_velocity": vf,
        "front_froude_number": fr,
        "front_impact_time": t_imp,
        "water_volume_relative_change": float(np.max(np.abs(vols - vols[0])) / vols[0]),
        "water_outflow_atmosphere": float(out[-1]),
        "water_balance_relative_error": float(
            np.max(np.abs(vols + out - vols[0])[outflow_known(case, tv)]) / vols[0]
        ),
        "water_com_rise": dzw.tolist(),
        "water_com_energy_bound": ebound.tolist(),
        **budget,
        **impact_measures(case, h, p),
        "water_depth": H,
        "grain_count": p["grain_count"],
        "grain_mean_radius": p["grain_mean_radius"],
        "slide_mass_per_metre": p["slide_mass"] / p["thickness"],
        "cell_size_fine": p["h_fine"],
        "reference": {
            "initial_wave_height": WAVE_REF,
            "runup_historical": RUNUP_HISTORICAL,
            "runup_thesis_2d": list(RUNUP_THESIS),
            "front_froude_number_thesis": 3.18,
            "impact_speed_fritz": 110.0,
            "impact_froude_number_thesis": 3.18,
            "source": "thesis section 5.3 (Fritz et al. 2001 1:675 model, Miller 1960);"
            " gauge record of Fritz et al. not digitised here",
        },
    }
    nscdpost.write_json(os.path.join(case, "results.json"), res)
    plot(case, res, H)
    print(
        f"{case}: max gauge elevation {eta.max():.1f} m, max run-up {res['max_runup']:.1f} m "
        f"(bound {runup_bound:.0f} m), Fr_f = {fr:.2f} (v_f {vf:.1f} m/s), water volume "
        f"change {res['water_volume_relative_change']:.2e} (spray out {out[-1]:.3g} m^3), "
        f"balance error {res['water_balance_relative_error']:.1e}"
    )


def plot(case, res, H):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ts = math.sqrt(G / H)
    tg, eta = np.array(res["gauge_time"]), np.array(res["gauge_elevation"])
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(tg * ts, eta / H, label=f"vansInterFoam ({res['mode']}, {res['grain_count']} grains)")
    ax.axhline(
        WAVE_REF / H, color="k", ls="--", label="~60 m initial wave (thesis 5.3, Fritz et al. 2001)"
    )
    ax.set_xlabel(r"$t\,\sqrt{g/h_0}$")
    ax.set_ylabel(r"$\eta/h_0$ at x = 885 m")
    ax.set_title("Lituya Bay: gauge at 885 m (Fritz et al. record not digitised)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(case, "gauge.png"), dpi=120)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(
        res["runup_time"],
        res["runup"],
        "-",
        label=f"vansInterFoam run-up, right shore ({res['runup_measured_by']})",
    )
    ax.axhline(RUNUP_HISTORICAL, color="r", ls="--", label="524 m historical (Miller 1960)")
    ax.axhspan(*RUNUP_THESIS, color="0.85", label="500-750 m thesis 2D PFEM (Fig. 5.11)")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("run-up [m]")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(case, "runup.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
