#!/usr/bin/env python3
"""Create the damBreak case from base/ at a given mesh resolution.

usage: setupCase.py CASEDIR [N]     N: cells per column width a (default 16)

Copies base/ to CASEDIR (replaced if present), sets the block of
system/blockMeshDict (tank 5a x 2.5a -> 5N x 2.5N cells) and the sample line
of the `floor` function object in system/controlDict (the centres of the
bottom row of cells).
"""
import os
import re
import shutil
import sys

A = 0.05715          # column width a = 2.25 in [m]
LX, LY, LZ = 5.0, 2.5, 0.1   # tank length, height, depth in units of a


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
    bm = os.path.join(case, "system", "blockMeshDict")
    txt = open(bm).read()
    txt = re.sub(r"\(\d+ \d+ 1\) simpleGrading", f"({nx} {ny} 1) simpleGrading", txt)
    open(bm, "w").write(txt)
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read()
    y, z = 0.5 * dx, 0.5 * LZ * A
    txt = re.sub(r"start\s+\([^)]*\);", f"start   ({0.5 * dx:.12g} {y:.12g} {z:.12g});", txt)
    txt = re.sub(r"end\s+\([^)]*\);", f"end     ({LX * A - 0.5 * dx:.12g} {y:.12g} {z:.12g});", txt)
    txt = re.sub(r"nPoints\s+\d+;", f"nPoints {nx};", txt)
    open(cd, "w").write(txt)
    print(f"{case}: {nx} x {ny} cells (a/{n} = {dx * 1e3:.3f} mm)")


if __name__ == "__main__":
    main()
