#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Create the heat-conduction case from base/ (thesis Figure 4.2 analogue).

usage: setupCase.py CASEDIR [NGRAINS [ENDTIME [DELTAT]]]

2D box of width 30 d_min, NGRAINS discs (d in [1, 1.2] mm) settled by
grainDeposit, floor at 400 K, adiabatic side walls, open top, grains at 300 K.
Contact conduction through Hertzian spots is slow (the time constant of one
disc, m c / H, is ~10^3 s) while the NSCD step is limited by gravity
(sub-step g dt^2 <= 0.1 d_min, ~3 ms). The packing is static, so the contact
forces (hence the conductances H, eq. 4.2) do not depend on time and the heat
equation m c dT/dt = sum H dT is linear: with heatCapacity c/S the temperature
at simulated time t is the one of the real glass (c = 840 J/(kg K)) at time
S t. S = 5e4 by default; postProcess.py reports the physical time S t.
"""

import math
import os
import sys

import nscdpost

here = os.path.dirname(os.path.abspath(__file__))


def main():
    case = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 600
    tend = float(sys.argv[3]) if len(sys.argv) > 3 else 6.0
    dt = float(sys.argv[4]) if len(sys.argv) > 4 else 3e-3
    S = 5e4
    dmin, lam = 1.0e-3, 1.2
    dmean = 0.5 * dmin * (1 + lam)
    lx = 30 * dmin
    spacing = 1.1 * lam * dmin
    per_row = max(1, int(lx / spacing))
    hbox = (math.ceil(n / per_row) + 2) * spacing + dmean
    ly = 1.05 * hbox
    h = 2 * dmean
    subs = {
        "@LX@": f"{lx:.6g}",
        "@LY@": f"{ly:.6g}",
        "@LZ@": f"{dmean:.6g}",
        "@NX@": str(max(1, int(lx / h))),
        "@NY@": str(max(1, int(ly / h))),
        "@HBOX@": f"{hbox:.6g}",
        "@NGRAINS@": str(n),
        "@DMIN@": f"{dmin:.6g}",
        "@LAMBDA@": f"{lam:.6g}",
        "@HEATCAPACITY@": f"{840.0 / S:.6g}",
        "@ENDTIME@": f"{tend:.6g}",
        "@DELTAT@": f"{dt:.6g}",
        "@WRITEINTERVAL@": f"{tend / 10:.6g}",
    }
    nscdpost.instantiate_case(os.path.join(here, "base"), case, subs)
    with open(os.path.join(case, "caseParameters"), "w") as fh:
        fh.write(f"timeScale {S}\nnGrains {n}\nTwall 400\nT0 300\n")
    print(f"{case}: N={n} box {lx:.4f}x{ly:.4f} m, endTime {tend} s, deltaT {dt} s")


if __name__ == "__main__":
    main()
