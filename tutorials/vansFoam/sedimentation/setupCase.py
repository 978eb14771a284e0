#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Create a sedimentation case from base/ (thesis section 3.2.2 / MigFlow's
grid deposit): discs r = 1.5 mm filling the top 0.15 m of the 0.4 x 0.6 m
box, in a square lattice (6,650 discs, the default) or the thesis' hexagonal
packing (7,553 discs; packing.py).

usage: setupCase.py CASEDIR METHOD [ENDTIME] [ROWS] [--packing square|hexagonal]
                    [--perturb A [--seed S] | --shrink A] [--friction MU]
                    [--max-delta-t DT] [--effective-diameter-factor K]
                    [--resolved-cells-per-diameter N]
  METHOD: overlap | centroid.  --perturb: every centre moved by a uniform
  random offset in [-A, A] d in x and y, diameters (1 - 2 A) d (no overlap);
  --shrink: the same diameters on the lattice (the control run); --friction:
  the grains' friction coefficient instead of base/'s 0.3; --max-delta-t:
  controlDict maxDeltaT instead of base/'s 5e-3 s; --effective-diameter-factor:
  couplingProperties voidFraction.effectiveDiameterFactor instead of 1;
  --resolved-cells-per-diameter: couplingProperties resolvedCellsPerDiameter
  (0: the thesis' semi-implicit scheme for every grain; default: off).
"""

import argparse
import os

import nscdpost
import packing
from foamlib import FoamFile

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


def arguments():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("case")
    p.add_argument("method", choices=list(METHODS))
    p.add_argument("end", nargs="?", default="2")
    p.add_argument("rows", nargs="?", type=int, default=None)
    p.add_argument("--packing", choices=list(packing.ROWS), default="square")
    p.add_argument("--perturb", type=float, default=0.0, metavar="A")
    p.add_argument("--shrink", type=float, default=0.0, metavar="A")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--friction", type=float, default=None, metavar="MU")
    p.add_argument("--max-delta-t", type=float, default=None, metavar="DT")
    p.add_argument("--effective-diameter-factor", type=float, default=None, metavar="K")
    p.add_argument("--resolved-cells-per-diameter", type=float, default=None, metavar="N")
    a = p.parse_args()
    if a.perturb and a.shrink:
        p.error("--perturb already shrinks the discs: give one of --perturb, --shrink")
    if not 0 <= max(a.perturb, a.shrink) < 0.25:
        p.error("--perturb / --shrink A must lie in [0, 0.25)")
    return a


def main():
    a = arguments()
    xy, _ = packing.lattice(a.packing, a.rows)
    xy, factor = packing.perturb(xy, a.perturb or a.shrink, a.seed, move=a.perturb > 0)
    d = 2 * packing.R * factor * (1 - 1e-9)
    lines = [f"({x:.9g} {y:.9g} 0 {d:.12g})" for x, y in xy]
    nscdpost.instantiate_case(
        os.path.join(here, "base"),
        a.case,
        {"@METHOD@": a.method, "@ENDTIME@": a.end, **METHODS[a.method]},
    )
    if a.friction is not None:
        with FoamFile(os.path.join(a.case, "constant", "grainProperties")) as f:
            f["materials", "grains", "friction"] = a.friction
    if a.max_delta_t is not None:
        with FoamFile(os.path.join(a.case, "system", "controlDict")) as f:
            f["maxDeltaT"] = a.max_delta_t
    with FoamFile(os.path.join(a.case, "constant", "couplingProperties")) as f:
        if a.effective_diameter_factor is not None:
            f["voidFraction", "effectiveDiameterFactor"] = a.effective_diameter_factor
        if a.resolved_cells_per_diameter is not None:
            f["resolvedCellsPerDiameter"] = a.resolved_cells_per_diameter
    with open(os.path.join(a.case, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
        )
        f.write(
            f"// {a.packing} lattice, nearest neighbours d apart (perturb {a.perturb}, "
            f"shrink {a.shrink}, seed {a.seed}), no settling (released at t = 0)\n"
        )
        f.write("material grains;\nmethod list;\ngrains\n(\n" + "\n".join(lines) + "\n);\n")
    print(
        f"{a.case}: {len(lines)} discs, {a.packing} packing, void fraction method {a.method} "
        f"(epsMin {METHODS[a.method]['@EPSMIN@']}, pressureDiffusion "
        f"{METHODS[a.method]['@PRESSUREDIFFUSION@']}), endTime {a.end} s"
    )


if __name__ == "__main__":
    main()
