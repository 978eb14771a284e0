#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Set up the granular Rayleigh-Taylor case (thesis section 3.3.1, after
Vinningland et al. 2007): frictionless discs d in [d_max/1.2, d_max],
d_max = 230 um (lambda = 1.2), rho_p = 1050, in air, closed box W x H =
56 x 68 mm, mesh h/d = 2 (h = 0.46 mm), released from rest at t = 0.

usage: setupCase.py CASEDIR [SCALE] [ENDTIME]
  SCALE 1 (default): the full case, ~70,000 discs; SCALE s < 1 shrinks the
  box (and the number of grains, ~s^2) for a quick run.

The packing: a triangular lattice of spacing d_max (no overlap, solid
fraction ~0.76) filling the box from the top; the thesis' 70,000 discs then
fill the top 57 mm and leave ~11 mm of air below (the thesis does not say how
its packing was made; it gives the grain count and the box).
"""

import os
import random
import sys

import nscdpost

here = os.path.dirname(os.path.abspath(__file__))

D_MAX, LAMBDA = 230e-6, 1.2
W_FULL, H_FULL, N_FULL = 0.056, 0.068, 70000


def main():
    case = sys.argv[1]
    scale = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
    end = sys.argv[3] if len(sys.argv) > 3 else "0.45"
    W, H = W_FULL * scale, H_FULL * scale
    n_target = round(N_FULL * scale * scale)
    h = 2 * D_MAX
    nx, ny = round(W / h), round(H / h)
    rng = random.Random(7)
    dy = D_MAX * 3**0.5 / 2
    per_row = int((W - D_MAX) / D_MAX)
    lines, j = [], 0
    while len(lines) < n_target:
        y = H - 0.5 * D_MAX * 1.001 - j * dy
        off = 0.5 * D_MAX if j % 2 else 0.0
        for i in range(per_row):
            if len(lines) == n_target:
                break
            x = 0.5 * D_MAX * 1.001 + off + i * D_MAX
            d = D_MAX * (1 / LAMBDA + (1 - 1 / LAMBDA) * rng.random()) * (1 - 1e-6)
            lines.append(f"({x:.9g} {y:.9g} 0 {d:.9g})")
        j += 1
    nscdpost.instantiate_case(
        os.path.join(here, "base"),
        case,
        {
            "@WIDTH@": f"{W:.9g}",
            "@HEIGHT@": f"{H:.9g}",
            "@H@": f"{W / nx:.9g}",
            "@NX@": str(nx),
            "@NY@": str(ny),
            "@ENDTIME@": end,
        },
    )
    with open(os.path.join(case, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
        )
        f.write("// triangular lattice of spacing d_max from the top, released at t = 0\n")
        f.write("material beads;\nmethod list;\ngrains\n(\n" + "\n".join(lines) + "\n);\n")
    nscdpost.write_json(
        os.path.join(case, "setup.json"),
        {
            "width": W,
            "height": H,
            "grains": len(lines),
            "rows": j,
            "initial_interface": H - (j - 1) * dy - D_MAX,
            "d_max": D_MAX,
        },
    )
    print(
        f"{case}: {len(lines)} discs in {j} rows, box {W * 1e3:.1f} x {H * 1e3:.1f} mm, "
        f"mesh {nx} x {ny}, endTime {end} s"
    )


if __name__ == "__main__":
    main()
