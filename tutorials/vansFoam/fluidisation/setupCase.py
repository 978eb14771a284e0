#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Set up the fluidisation cases (thesis section 3.3.2, after Peng et al.).

usage: setupCase.py deposit            the settled bed, once (mesh h/d = 1)
       setupCase.py CASEDIR HD [END [MAXDT]]
                                       a case at mesh h/d = HD with the bed of
                                       deposit/ (the same grains for every mesh),
                                       time step at most MAXDT (default 1e-3 s)

The bed: ~1,600 slightly polydisperse discs (d_min = 0.2 mm, lambda = 1.2,
rho_p = 2630, mu = 0.4) settled under gravity in a W = 8.8 mm wide box
(40 mean diameters); the water column is H = 17.6 mm (twice the bed).  The
thesis does not give its bed size; this one keeps h/d = 8 at 5 cells across.
"""

import os
import sys

import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))

D_MIN, LAMBDA = 0.2e-3, 1.2
D_MEAN = 0.5 * (1 + LAMBDA) * D_MIN  # 0.22 mm
WIDTH, HEIGHT = 40 * D_MEAN, 80 * D_MEAN
N_GRAINS = 1600
P_TOP = 103e3 / 1000.0  # back pressure 103 kPa, kinematic [m^2/s^2]
G = 9.81
N_PROBES = 9
RAMP_TIME = 1.0  # Delta t of eq. 3.53 [s]
MAX_DELTA_T = 1e-3  # maxDeltaT [s] (the drag is implicit in the contact solve)


def mesh_subs(
    hd, end, probes="", max_delta_t=MAX_DELTA_T, width=WIDTH, height=HEIGHT, ramp_time=RAMP_TIME
):
    h = hd * D_MEAN
    nx = max(1, round(width / h))
    # kinematic: p_0 = p_t + g H, p_b(t) = p_0 + g H t / (1 s)   (eq. 3.53-3.54)
    p0 = P_TOP + G * height
    return {
        "@WIDTH@": f"{width:.9g}",
        "@HEIGHT@": f"{height:.9g}",
        "@H@": f"{width / nx:.9g}",
        "@HD@": f"{hd:g}",
        "@MAXDT@": f"{max_delta_t:g}",
        "@NX@": str(nx),
        "@NY@": str(2 * nx),
        "@ENDTIME@": str(end),
        "@PTOP@": f"{P_TOP:.12g}",
        "@P0@": f"{p0:.12g}",
        "@P100@": f"{p0 + G * height * 100 / ramp_time:.12g}",
        "@PROBES@": probes,
    }


def deposit(root=here, width=WIDTH, height=HEIGHT, n_grains=N_GRAINS):
    """The settled bed in root/deposit; width, height [m] of the box, n_grains
    (a reduced bed for the tests; the tutorial's: the defaults)."""
    case = os.path.join(root, "deposit")
    nscdpost.instantiate_case(
        os.path.join(here, "base"), case, mesh_subs(1, 0, width=width, height=height)
    )
    with open(os.path.join(case, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
            "material sand;\nmethod box;\n"
            f"box {{ min (0 0 0); max ({width:.9g} {height:.9g} 1); }}\n"
            f"number {n_grains};\ndMin {D_MIN};\nsizeRatio {LAMBDA};\nseed 3;\n"
            "settle { maxTime 1; deltaT 2e-4; speedTolerance 2e-3; }\n"
        )
    print(f"{case}: {n_grains} grains to settle")


def bed_top(case):
    g = nscdpost.read_grains(case, "0")
    y = g["x"][:, 1] + 0.5 * g["d"]
    # the initial top of the layer: mean of the highest grain tops over
    # columns one d_max wide (the free surface of the packing)
    x = g["x"][:, 0]
    cols = np.floor(x / (LAMBDA * D_MIN)).astype(int)
    tops = [y[cols == c].max() for c in np.unique(cols)]
    return float(np.mean(tops))


def setup(
    case,
    hd,
    end,
    root=here,
    max_delta_t=MAX_DELTA_T,
    width=WIDTH,
    height=HEIGHT,
    ramp_time=RAMP_TIME,
):
    """A case at mesh h/d = hd with the bed of root/deposit; width, height
    [m] as given to deposit(), ramp_time [s] of the inlet pressure."""
    dep = os.path.join(root, "deposit")
    top = bed_top(dep)
    xs = [(i + 0.5) * width / N_PROBES for i in range(N_PROBES)]
    probes = "\n".join(f"            ({x:.9g} {top:.9g} 0)" for x in xs)
    nscdpost.instantiate_case(
        os.path.join(here, "base"),
        case,
        mesh_subs(hd, end, probes, max_delta_t, width, height, ramp_time),
    )
    nscdpost.copy_grain_state(dep, case)
    nscdpost.write_json(
        os.path.join(case, "bed.json"),
        {
            "bed_top": top,
            "width": width,
            "height": height,
            "h_over_d": hd,
            "d_mean": D_MEAN,
            "p_top": P_TOP,
            "p0": P_TOP + G * height,
            "head_rate": height / ramp_time,
        },
    )
    print(
        f"{case}: h/d = {hd}, bed top {top * 1e3:.3f} mm, endTime {end} s, maxDeltaT {max_delta_t:g} s"
    )


if __name__ == "__main__":
    if sys.argv[1] == "deposit":
        deposit()
    else:
        setup(
            sys.argv[1],
            float(sys.argv[2]),
            sys.argv[3] if len(sys.argv) > 3 else "0.9",
            max_delta_t=float(sys.argv[4]) if len(sys.argv) > 4 else MAX_DELTA_T,
        )
