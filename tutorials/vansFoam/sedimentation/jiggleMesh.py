#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Move the interior points of a sedimentation case's blockMesh mesh by
random offsets (the study of what keeps the square lattice's rows
coherent, docs/validation/sedimentation.md): the cell faces no longer run
along the grain rows, so the grains of one row no longer all see the same
cell void fraction, as on the thesis' and MigFlow's unstructured triangles.

usage: jiggleMesh.py CASEDIR [AMPLITUDE [SEED]]   (after blockMesh)
  every point off the walls moves by independent uniform offsets in
  [-A, A] h in x and y (default A = 0.2, h = 9.09 mm: the cells stay
  convex); the front and back points of one (x, y) move together (2D).
"""

import os
import re
import sys

import numpy as np

W, H, NX, NY = 0.4, 0.6, 44, 67


def main():
    case = sys.argv[1]
    amp = float(sys.argv[2]) if len(sys.argv) > 2 else 0.2
    seed = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    path = os.path.join(case, "constant", "polyMesh", "points")
    text = open(path).read()
    head, body = text.split("(\n", 1)
    body, tail = body.rsplit("\n)", 1)
    p = np.array([[float(v) for v in ln.strip("()").split()] for ln in body.splitlines()])
    h = W / NX, H / NY
    i = np.rint(p[:, 0] / h[0]).astype(int)
    j = np.rint(p[:, 1] / h[1]).astype(int)
    rng = np.random.default_rng(seed)
    offset = rng.uniform(-amp, amp, (NX + 1, NY + 1, 2)) * h
    inside = (i > 0) & (i < NX) & (j > 0) & (j < NY)
    p[inside, :2] += offset[i[inside], j[inside]]
    lines = "\n".join(f"({x:.12g} {y:.12g} {z:.12g})" for x, y, z in p)
    with open(path, "w") as f:
        f.write(head + "(\n" + lines + "\n)" + tail)
    print(f"{path}: {inside.sum()} of {len(p)} points moved by up to {amp} h")


if __name__ == "__main__":
    if len(sys.argv) < 2 or re.match(r"-h|--help", sys.argv[1]):
        sys.exit(__doc__)
    main()
