#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Create a sedimentation case from base/ (thesis section 3.2.2 / MigFlow's
grid deposit): 6,600 discs r = 1.5 mm in a square lattice (spacing 2r) filling
the top 0.15 m of the 0.4 x 0.6 m box.

usage: setupCase.py CASEDIR METHOD [ENDTIME] [ROWS]   (METHOD: overlap | centroid)
"""

import os
import sys

import nscdpost

here = os.path.dirname(os.path.abspath(__file__))


# per method: the void fraction floor and the artificial pressure diffusion
# C of couplingProperties.  PCM puts a whole grain into the cell of its
# centre, so a cell's solid fraction can pass 1: its void fraction is
# clipped at about the densest disc packing's (1 - pi/(2 sqrt 3) = 0.093)
# instead of 1e-8 (which stops the run at its second step: the drag of a
# cell at eps = 1e-8 is ~1e21 times the fluid's inertia), and the pressure
# diffusion the thesis gives its PCM runs (section 3.2.2) is on, C = 1.
METHODS = {
    "overlap": {"@EPSMIN@": "1e-8", "@PRESSUREDIFFUSION@": "0"},
    "centroid": {"@EPSMIN@": "0.1", "@PRESSUREDIFFUSION@": "1"},
}


def main():
    case, method = sys.argv[1], sys.argv[2]
    end = sys.argv[3] if len(sys.argv) > 3 else "2"
    rows = int(sys.argv[4]) if len(sys.argv) > 4 else 50
    r = 1.5e-3
    ncol = int(0.4 / (2 * r))  # 133
    x0 = 0.5 * (0.4 - ncol * 2 * r)
    ytop = 0.6 - 2e-3
    lines = []
    for j in range(rows):
        for i in range(ncol):
            lines.append(
                f"({x0 + (2 * i + 1) * r:.9g} {ytop - (2 * j + 1) * r:.9g} 0 {2 * r * (1 - 1e-9):.12g})"
            )
    if method not in METHODS:
        sys.exit(f"setupCase.py: unknown METHOD {method} (use: {' | '.join(METHODS)})")
    nscdpost.instantiate_case(
        os.path.join(here, "base"), case, {"@METHOD@": method, "@ENDTIME@": end, **METHODS[method]}
    )
    with open(os.path.join(case, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
        )
        f.write("// square lattice, spacing 2r, no settling (released at t = 0)\n")
        f.write("material grains;\nmethod list;\ngrains\n(\n" + "\n".join(lines) + "\n);\n")
    print(
        f"{case}: {len(lines)} discs, void fraction method {method} (epsMin "
        f"{METHODS[method]['@EPSMIN@']}, pressureDiffusion {METHODS[method]['@PRESSUREDIFFUSION@']}), "
        f"endTime {end} s"
    )


if __name__ == "__main__":
    main()
