#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Post-process the 3D granular collapse (granularCollapse3D).

usage: postProcess.py CASEDIR

Reads the run-time files of CASEDIR (made by setupCase.py and run) and writes
CASEDIR/results.json and CASEDIR/granularCollapse3D.png:
- the front Froude number Fr_f = v_f / sqrt(g h0) (granularFront: the
  furthest sphere at y = h0, least-squares slope over 0.05 s), taken after
  the first 0.03 s (`front_froude_number`; the whole run's value,
  `front_froude_number_all`, also counts the kick the gate gives the spheres
  next to it at the release) and its regime (Sarlin et al. 2021, JFM 919 R6:
  nonlinear transition < 0.35 < solitary < 0.87 < bore), beside the thesis'
  2D value and Sarlin et al.'s experiment (thesis Table 5.1, case 2);
- the maximum free-surface elevation at each gauge (waveGauges, the gauge
  line at mid-channel) and the bore amplitude ahead of a piston at v_f
  (Stoker 1957; the functions of ../granularCollapse/postProcess.py);
- conservation: the water volume sum(eps alpha V) against the water that
  left through the atmosphere (waterVolume.dat), and the sphere count
  (grainStatistics.dat);
- the contact solve (grainStatistics.dat: steps, sweeps, converged).
"""

import json
import math
import os
import sys

import nscdpost
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
# regime bounds, Table 5.1 and the piston bore of the 2D tutorial
post2d = nscdpost.load_module(
    "granularCollapse_postProcess", os.path.join(HERE, "..", "granularCollapse", "postProcess.py")
)
G = post2d.G
CONFIG = "solitary"  # thesis case 2
FRONT_START = 0.03  # [s] v_f taken after the release kick (README)


def measure(case):
    params = json.load(open(os.path.join(case, "caseParameters.json")))
    front = post2d.read_dat(post2d.dat_path(case, "front", "granularFront.dat"))
    gauges = post2d.read_dat(post2d.dat_path(case, "gauges", "waveGauges.dat"))
    later = front[:, 0] > FRONT_START
    if not later.any():  # a run shorter than FRONT_START (smoke test)
        later[:] = True
    i = int(np.nanargmax(front[later, 2]))
    vf = float(front[later, 2][i])
    h0 = params["h0"]
    fr = vf / math.sqrt(G * h0)
    water = nscdpost.read_step_data(case, "waterVolume")
    total = water["waterVolume"] + water["waterOut"]
    stats = nscdpost.read_step_data(case, "grainStatistics")
    res = {
        "front_froude_number": fr,
        "front_froude_number_all": float(np.nanmax(front[:, 4])),
        "max_front_velocity": vf,
        "max_front_velocity_time": float(front[later, 0][i]),
        "regime": post2d.regime(fr),
        "expected_regime": post2d.EXPECTED_REGIME[CONFIG],
        "thesis_front_froude_number_2d": post2d.TABLE_5_1[CONFIG]["thesis"],
        "sarlin_front_froude_number": post2d.TABLE_5_1[CONFIG]["sarlin"],
        "max_wave_amplitude": [float(v) for v in np.max(gauges[:, 1:], axis=0)],
        "max_wave_amplitude_time": [float(gauges[k, 0]) for k in np.argmax(gauges[:, 1:], axis=0)],
        "gauge_x": params["gauges"],
        "piston_bore_amplitude": post2d.piston_bore_amplitude(vf, h0),
        "water_volume_initial": float(water["waterVolume"][0]),
        "water_volume_max_relative_change": float(np.max(np.abs(total - total[0])) / total[0]),
        "water_out": float(water["waterOut"][-1]),
        "grains_initial": int(stats["grains"][0]),
        "grains_final": int(stats["grains"][-1]),
        "steps": int(len(stats["Time"])),
        "sweeps_median": float(np.median(stats["sweeps"])),
        "steps_not_converged": int(np.sum(stats["converged"] < 0.5)),
        "end_time": float(stats["Time"][-1]),
    }
    for k in (
        "h0",
        "H0",
        "L0",
        "channel_width",
        "n_grains",
        "dx",
        "ranks",
        "contact_tolerance",
        "contact_compliance",
        "contact_relaxation",
    ):
        res[k] = params.get(k)
    return params, front, gauges, res


def plot(path, params, front, gauges, res):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 4))
    ax0.plot(front[:, 0], front[:, 2] / math.sqrt(G * params["h0"]), label="u_f / sqrt(g h0)")
    ax0.axhline(
        res["sarlin_front_froude_number"],
        color="k",
        ls=":",
        label=f"Sarlin et al. 2021: {res['sarlin_front_froude_number']}",
    )
    ax0.axhline(
        res["thesis_front_froude_number_2d"],
        color="grey",
        ls="--",
        label=f"thesis 2D: {res['thesis_front_froude_number_2d']}",
    )
    ax0.set_xlabel("t [s]")
    ax0.set_ylabel("front Froude number")
    ax0.set_title(f"Fr_f = {res['front_froude_number']:.2f} ({res['regime']})")
    ax0.legend(fontsize=8)
    ax0.grid(alpha=0.3)
    for k, x in enumerate(params["gauges"]):
        ax1.plot(gauges[:, 0], gauges[:, 1 + k] * 1e3, label=f"x = {x:.2f} m")
    a = res["piston_bore_amplitude"]
    ax1.axhline(a * 1e3, color="k", ls="--", label=f"piston bore at v_f: {a * 1e3:.1f} mm")
    ax1.set_xlabel("t [s]")
    ax1.set_ylabel("free-surface elevation at mid-channel [mm]")
    ax1.set_title(f"{res['grains_initial']} spheres, channel {params['channel_width']:.2f} m")
    ax1.legend(fontsize=8)
    ax1.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    args = sys.argv[1:] if argv is None else list(argv)
    if len(args) != 1:
        sys.exit(__doc__)
    case = args[0]
    params, front, gauges, res = measure(case)
    plot(os.path.join(case, "granularCollapse3D.png"), params, front, gauges, res)
    nscdpost.write_json(os.path.join(case, "results.json"), res)
    print(
        f"{case}: Fr_f = {res['front_froude_number']:.3f} ({res['regime']}), max elevation "
        f"{', '.join(f'{a * 1e3:.1f}' for a in res['max_wave_amplitude'])} mm, spheres "
        f"{res['grains_initial']} -> {res['grains_final']}, water volume change "
        f"{res['water_volume_max_relative_change']:.2e}"
    )


if __name__ == "__main__":
    main()
