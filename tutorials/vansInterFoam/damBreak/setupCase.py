#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Create the damBreak case from base/ at a given mesh resolution.

usage: setupCase.py CASEDIR [N]     N: cells per column width a (default 16)

Copies base/ to CASEDIR (replaced if present), sets the block of
system/blockMeshDict (tank 5a x 2.5a -> 5N x 2.5N cells) and the sample line
of the `floor` function object in system/controlDict (the centres of the
bottom row of cells).
"""

import os
import shutil
import sys

from foamlib import FoamFile

A = 0.05715  # column width a = 2.25 in [m]
LX, LY, LZ = 5.0, 2.5, 0.1  # tank length, height, depth in units of a


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    case = sys.argv[1]
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 16
    if n < 4 or n % 2:
        sys.exit("setupCase.py: N must be an even integer >= 4")
    base = os.path.join(os.path.dirname(os.path.abspath(__file__)), "base")
    if os.path.isdir(case):
        shutil.rmtree(case)
    shutil.copytree(base, case)
    nx, ny = int(LX * n), int(LY * n)
    dx = A / n
    with FoamFile(os.path.join(case, "system", "blockMeshDict")) as f:
        blocks = f["blocks"]  # hex (vertices) (nx ny nz) simpleGrading (...)
        blocks[2] = [nx, ny, 1]
        f["blocks"] = blocks
    # the floor line: the centres of the bottom row of cells (12 digits, as written before)
    y, z = 0.5 * dx, 0.5 * LZ * A
    with FoamFile(os.path.join(case, "system", "controlDict")) as f:
        name, row = f["functions", "floor", "sets"][0]
        row = dict(
            row,
            nPoints=nx,
            start=[float(f"{v:.12g}") for v in (0.5 * dx, y, z)],
            end=[float(f"{v:.12g}") for v in (LX * A - 0.5 * dx, y, z)],
        )
        f["functions", "floor", "sets"] = [(name, row)]
    print(f"{case}: {nx} x {ny} cells (a/{n} = {dx * 1e3:.3f} mm)")


if __name__ == "__main__":
    main()
