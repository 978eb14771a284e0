#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Create one column-collapse case from base/ for an aspect ratio a = H_i/L_i.

usage: setupCase.py CASEDIR ASPECT_RATIO NGRAINS [FRICTION]

The column width L_i follows from the number of discs and an expected packing
fraction of 0.82 (dense random 2D packing of slightly polydisperse discs); the
insertion box is taller than the final column (grains settle from a loose
lattice).  The domain extends far enough for the runout of the scaling law.
"""

import math
import os
import sys

import nscdpost

here = os.path.dirname(os.path.abspath(__file__))


def main():
    case, a, n = sys.argv[1], float(sys.argv[2]), int(sys.argv[3])
    mu = float(sys.argv[4]) if len(sys.argv) > 4 else 0.5
    dmin, lam = 2.0e-3, 1.2
    dmean = 0.5 * dmin * (1 + lam)
    area = n * math.pi / 4 * dmin**2 * (1 + lam + lam**2) / 3
    w0 = math.sqrt(area / (0.82 * a))
    h0 = a * w0
    spacing = 1.1 * lam * dmin
    per_row = max(1, int(w0 / spacing))
    hbox = (math.ceil(n / per_row) + 2) * spacing + dmean
    runout = 1.5 * max(1.2 * a, 1.9 * a ** (2.0 / 3.0)) * w0
    lx = w0 + runout + 10 * dmean
    ly = 1.05 * hbox
    h = 4 * dmean
    tend = round(max(0.6, 5.5 * math.sqrt(h0 / 9.81)), 2)
    subs = {
        "@LX@": f"{lx:.6g}",
        "@LY@": f"{ly:.6g}",
        "@LZ@": f"{dmean:.6g}",
        "@NX@": str(max(1, int(lx / h))),
        "@NY@": str(max(1, int(ly / h))),
        "@W0@": f"{w0:.6g}",
        "@HBOX@": f"{hbox:.6g}",
        "@NGRAINS@": str(n),
        "@DMIN@": f"{dmin:.6g}",
        "@LAMBDA@": f"{lam:.6g}",
        "@FRICTION@": f"{mu:.6g}",
        "@ENDTIME@": f"{tend:.6g}",
        "@WRITEINTERVAL@": f"{tend / 10:.6g}",
        "@ROWTOP@": f"{dmean:.6g}",
        "@ROWY@": f"{0.5 * dmean:.6g}",
        "@ROWX0@": f"{0.5 * dmean:.6g}",
        "@ROWX1@": f"{lx - 0.5 * dmean:.6g}",
        "@DMEAN@": f"{dmean:.6g}",
    }
    nscdpost.instantiate_case(os.path.join(here, "base"), case, subs)
    with open(os.path.join(case, "caseParameters"), "w") as fh:
        fh.write(f"aspectRatio {a}\ngateX {w0}\nnGrains {n}\nfriction {mu}\n")
    print(
        f"{case}: a={a} N={n} L_i={w0:.4f} m H_i~{h0:.4f} m domain {lx:.3f}x{ly:.3f} m, endTime {tend} s"
    )


if __name__ == "__main__":
    main()
