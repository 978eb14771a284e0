#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Create one granularCollapse configuration from base/ (thesis section 5.2).

usage: setupCase.py CASEDIR CONFIG [DX] [BASIN] [ENDTIME]
    CONFIG   nonlinearTransition | solitary | bore
    DX       cell size [m] (default 0.02 = 4 grain diameters)
    BASIN    basin length [m] (default 1.0)
    ENDTIME  [s] (default 0.8)

Geometry (thesis Figure 5.5, a 2D version of Sarlin et al. 2021): a dry
column of width L0 and height H0 on a platform whose top is at the still-
water level h0, held by a gate at x = L0 (grainProperties: gates) lifted at
1 m/s from t = 0; the basin [L0, L0 + BASIN] x [0, h0] is full of water.
The three configurations vary h0 and the column shape as the thesis does
(case 1: deep basin, thin column; case 2: shallower, thicker; case 3:
shallowest, tallest) so that Fr_f = v_f / sqrt(g h0) lands in the three
regimes of Sarlin et al. (nonlinear transition < 0.35 < solitary < 0.87 <
bore).  Grains: d = 5 mm mean, polydispersity 1.2, rho_p 2500, mu 0.9.
"""

import math
import os
import sys

import nscdpost

HERE = os.path.dirname(os.path.abspath(__file__))

# h0: water depth, H0: column height, L0: column width [m]
CONFIGS = {
    "nonlinearTransition": {"h0": 0.44, "H0": 0.08, "L0": 0.04},
    "solitary": {"h0": 0.08, "H0": 0.16, "L0": 0.06},
    "bore": {"h0": 0.04, "H0": 0.30, "L0": 0.06},
}
D_MEAN, LAMBDA = 5e-3, 1.2  # grain diameter, d_max/d_min
PACKING = 0.82  # dense random packing of discs (2D)
GAUGE_OFFSETS = (0.3, 0.5, 0.7)  # gauges at x = L0 + offset [m]


def snap(v, dx):
    return max(1, round(v / dx)) * dx


def setup(case, config, dx=0.02, basin=1.0, end_time=0.8, settle_tolerance=5e-3):
    """Build the case; settle_tolerance: grainDeposit speedTolerance [m/s]."""
    c = CONFIGS[config]
    dmin = 2 * D_MEAN / (1 + LAMBDA)
    lp = snap(c["L0"], dx)
    h0 = snap(c["h0"], dx)
    ly = snap(h0 + c["H0"] + 0.1, dx)
    lx = lp + snap(basin, dx)
    d2 = dmin**2 * (1 + LAMBDA + LAMBDA**2) / 3
    n = int(round(lp * c["H0"] * PACKING / (math.pi / 4 * d2)))
    spacing = 1.1 * LAMBDA * dmin
    per_row = max(1, int(lp / spacing))
    hbox = h0 + (math.ceil(n / per_row) + 2) * spacing + D_MEAN
    if hbox > ly:
        ly = snap(hbox + 0.02, dx)
    gauges = [lp + g for g in GAUGE_OFFSETS if lp + g < lx]
    subs = {
        "@LP@": f"{lp:.6g}",
        "@LX@": f"{lx:.6g}",
        "@LY@": f"{ly:.6g}",
        "@LZ@": f"{dx:.6g}",
        "@H0W@": f"{h0:.6g}",
        "@NXP@": str(round(lp / dx)),
        "@NXB@": str(round((lx - lp) / dx)),
        "@NYW@": str(round(h0 / dx)),
        "@NYA@": str(round((ly - h0) / dx)),
        "@X0@": "0",
        "@HBOX@": f"{hbox:.6g}",
        "@NGRAINS@": str(n),
        "@DMIN@": f"{dmin:.6g}",
        "@ENDTIME@": f"{end_time:.6g}",
        "@WRITEINTERVAL@": f"{end_time / 10:.6g}",
        "@GAUGES@": " ".join(f"{g:.6g}" for g in gauges),
        "@SETTLETOL@": f"{settle_tolerance:.6g}",
    }
    nscdpost.instantiate_case(os.path.join(HERE, "base"), case, subs)
    params = {
        "config": config,
        "h0": h0,
        "H0": c["H0"],
        "L0": lp,
        "n_grains": n,
        "dx": dx,
        "basin_length": lx - lp,
        "gauges": gauges,
        "end_time": end_time,
    }
    nscdpost.write_json(os.path.join(case, "caseParameters.json"), params)
    print(
        f"{case}: {config} h0={h0} H0={c['H0']} L0={lp} N={n} mesh {lx:.3f} x {ly:.3f} m, dx={dx}"
    )
    return params


def main():
    if len(sys.argv) < 3 or sys.argv[2] not in CONFIGS:
        sys.exit(__doc__)
    args = [float(a) for a in sys.argv[3:6]]
    setup(sys.argv[1], sys.argv[2], *args)


if __name__ == "__main__":
    main()
