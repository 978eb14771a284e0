#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Set up the 3D granular collapse into a water basin (vansInterFoam).

usage: setupCase.py slab SLABDIR [--dx DX] [--slab-width WS] [--settle-time T]
       setupCase.py case CASEDIR --slab SLABDIR [--copies K] [--basin L]
                    [--end T] [--ranks NP] [--tolerance TOL]
                    [--compliance C] [--relaxation R] [--friction-law L]

The solitary configuration of tutorials/vansInterFoam/granularCollapse (thesis
section 5.2, case 2; Sarlin et al. 2021) with spheres instead of discs: a dry
column of width L0 = 0.06 m and height H0 = 0.16 m on a platform whose top is
at the still-water level h0 = 0.08 m, held by a gate at x = L0 lifted at 1 m/s
from t = 0, spans a channel of width W (z, free-slip side walls); the basin
[L0, L0 + BASIN] x [0, h0] is full of water.  Spheres of mean d = 5 mm,
polydispersity 1.2, rho_p 2500, friction 0.9 (thesis 5.2.1).

Building the column (grainDeposit cannot settle ~10^5 spheres from its loose
lattice in minutes):
  slab: a slice of the column WS wide (default 0.06 m = 3 cells) between two
        side walls, filled from grainDeposit's box lattice and settled (the
        gate holds it);
  case: K copies of the settled slice side by side across the channel, every
        other one mirrored about the plane it shares with its neighbour, so a
        sphere that rested on a side wall rests on its own mirror image
        (grainDeposit `method list`; W = K WS).  The default K = 22 gives
        ~104,000 spheres in a 1.32 m wide channel.
The run starts from the copies at rest, as the 2D tutorial starts from its
settled column.
"""

import argparse
import json
import math
import os

import nscdpost

HERE = os.path.dirname(os.path.abspath(__file__))

H0W, H0, L0 = 0.08, 0.16, 0.06  # water depth, column height, column width [m]
D_MEAN, LAMBDA = 5e-3, 1.2  # mean grain diameter, d_max/d_min
D_MIN = 2 * D_MEAN / (1 + LAMBDA)
PACKING = 0.54  # the settled slab's solid fraction (loose random packing, 3D)
GAUGE_OFFSETS = (0.3, 0.5, 0.7)  # gauges at x = L0 + offset [m]
# the run's contact law (README, "Contact law"); the slab settles with hard
# Coulomb contacts
COMPLIANCE = 1e-4  # [m/N] normal contact compliance
RELAXATION = 1.0  # relaxation of the Gauss-Seidel update
FRICTION_LAW = "anitescu"  # coulomb | anitescu


def snap(v, dx):
    return max(1, round(v / dx)) * dx


def sphere_volume_mean():
    """Mean sphere volume [m^3] for d uniform in [D_MIN, LAMBDA D_MIN]."""
    d3 = D_MIN**3 * (LAMBDA**4 - 1) / (4 * (LAMBDA - 1))
    return math.pi / 6 * d3


HARD = {  # the slab's settle: hard Coulomb contacts
    "tolerance": 1e-4,
    "max_iterations": 1000,
    "compliance": 0.0,
    "relaxation": 1.0,
    "friction_law": "coulomb",
}


def subs_for(lz, nz, dx, basin, ly, end, ranks, contact):
    """The placeholders of base/ for a channel lz [m] wide (nz cells), an
    air top at ly [m] and the contact settings `contact` (keys of HARD)."""
    lp = snap(L0, dx)
    lx = lp + snap(basin, dx)
    gauges = [lp + g for g in GAUGE_OFFSETS if lp + g < lx]
    return {
        "@LP@": f"{lp:.9g}",
        "@LX@": f"{lx:.9g}",
        "@LY@": f"{ly:.9g}",
        "@LZ@": f"{lz:.9g}",
        "@H0W@": f"{H0W:.9g}",
        "@NXP@": str(round(lp / dx)),
        "@NXB@": str(round((lx - lp) / dx)),
        "@NYW@": str(round(H0W / dx)),
        "@NYA@": str(round((ly - H0W) / dx)),
        "@NZ@": str(nz),
        "@ENDTIME@": f"{end:.9g}",
        "@WRITEINTERVAL@": f"{end / 10:.9g}",
        "@GAUGES@": " ".join(f"{g:.9g}" for g in gauges),
        "@NP@": str(ranks),
        "@TOL@": f"{contact['tolerance']:g}",
        "@MAXIT@": str(contact["max_iterations"]),
        "@COMPLIANCE@": f"{contact['compliance']:g}",
        "@RELAX@": f"{contact['relaxation']:g}",
        "@FRICTIONLAW@": contact["friction_law"],
    }, gauges


def slab(case, dx=0.02, width=0.06, settle_time=1.5):
    """The deposit slice: WIDTH [m] across, settled by grainDeposit for at
    most settle_time [s] (it stops earlier at rest)."""
    nz = round(width / dx)
    if nz < 1 or abs(nz * dx - width) > 1e-9:
        raise SystemExit(f"setupCase.py slab: --slab-width {width} must be a multiple of --dx {dx}")
    n = int(round(L0 * H0 * width * PACKING / sphere_volume_mean()))
    spacing = 1.1 * LAMBDA * D_MIN  # grainDeposit's lattice spacing
    # nodes closer than d_max/2 to a wall are not used: one fewer each way
    per_layer = (int(L0 / spacing) - 1) * (int(width / spacing) - 1)
    hbox = H0W + (math.ceil(n / per_layer) + 2) * spacing + D_MEAN
    ly = snap(hbox + 0.02, dx)
    subs, _ = subs_for(width, nz, dx, 2 * dx, ly, 1.0, 1, HARD)
    nscdpost.instantiate_case(os.path.join(HERE, "base"), case, subs)
    with open(os.path.join(case, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
            "// a slice of the dry column between the left wall and the gate, settled\n"
            "material        glass;\nmethod          box;\n"
            f"box             {{ min (0 {H0W:.9g} 0); max ({subs['@LP@']} {hbox:.9g} {width:.9g}); }}\n"
            f"number          {n};\ndMin            {D_MIN:.9g};\nsizeRatio       {LAMBDA};\n"
            "seed            1;\n"
            f"settle {{ maxTime {settle_time:g}; deltaT 5e-4; speedTolerance 5e-3; }}\n"
        )
    nscdpost.write_json(
        os.path.join(case, "slab.json"), {"dx": dx, "width": width, "n_grains": n, "ly": ly}
    )
    print(f"{case}: slab of {n} spheres, {width} m wide, box up to {hbox:.3f} m")


def read_slab_info(slab_case):
    with open(os.path.join(slab_case, "slab.json")) as f:
        return json.load(f)


def tiled(slab_case, ws, copies):
    """(x, y, z, d) of `copies` slices of the settled slab (ws [m] wide) side
    by side in z, every other one mirrored about the plane it shares with its
    neighbour."""
    # grainDeposit writes the start time
    path = os.path.join(slab_case, "0", "grainState.h5")
    xs = nscdpost.read_h5(path, "positions", 3)
    ds = 2 * nscdpost.read_h5(path, "radii")
    out = []
    for k in range(copies):
        for x, d in zip(xs, ds):
            z = x[2] if k % 2 == 0 else ws - x[2]
            out.append((x[0], x[1], z + k * ws, d))
    return out


def case(
    case_dir,
    slab_case,
    copies=22,
    basin=1.0,
    end=0.6,
    ranks=4,
    tolerance=1e-4,
    max_iterations=2000,
    compliance=COMPLIANCE,
    relaxation=RELAXATION,
    friction_law=FRICTION_LAW,
):
    """The run: COPIES slices across a channel of COPIES x slab width."""
    info = read_slab_info(slab_case)
    dx, ws = info["dx"], info["width"]
    grains = tiled(slab_case, ws, copies)
    lz = copies * ws
    ly = snap(H0W + H0 + 0.1, dx)
    contact = {
        "tolerance": tolerance,
        "max_iterations": max_iterations,
        "compliance": compliance,
        "relaxation": relaxation,
        "friction_law": friction_law,
    }
    subs, gauges = subs_for(lz, round(lz / dx), dx, basin, ly, end, ranks, contact)
    nscdpost.instantiate_case(os.path.join(HERE, "base"), case_dir, subs)
    with open(os.path.join(case_dir, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
            f"// {copies} copies of the settled slice {slab_case} (setupCase.py)\n"
            "material glass;\nmethod list;\ngrains (\n"
            + "\n".join("(%.10g %.10g %.10g %.10g)" % t for t in grains)
            + "\n);\n"
        )
    params = {
        "config": "solitary",
        "h0": H0W,
        "H0": H0,
        "L0": float(subs["@LP@"]),
        "channel_width": lz,
        "n_grains": len(grains),
        "dx": dx,
        "basin_length": basin,
        "gauges": gauges,
        "end_time": end,
        "ranks": ranks,
        "contact_tolerance": tolerance,
        "contact_compliance": compliance,
        "contact_relaxation": relaxation,
        "friction_law": friction_law,
    }
    nscdpost.write_json(os.path.join(case_dir, "caseParameters.json"), params)
    print(f"{case_dir}: {len(grains)} spheres, channel {lz:.3f} m wide, {ranks} ranks")
    return params


def main():
    p = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    sub = p.add_subparsers(dest="what", required=True)
    s = sub.add_parser("slab")
    s.add_argument("dir")
    s.add_argument("--dx", type=float, default=0.02)
    s.add_argument("--slab-width", type=float, default=0.06)
    s.add_argument("--settle-time", type=float, default=1.5)
    c = sub.add_parser("case")
    c.add_argument("dir")
    c.add_argument("--slab", required=True)
    c.add_argument("--copies", type=int, default=22)
    c.add_argument("--basin", type=float, default=1.0)
    c.add_argument("--end", type=float, default=0.6)
    c.add_argument("--ranks", type=int, default=4)
    c.add_argument("--tolerance", type=float, default=1e-4)
    c.add_argument("--compliance", type=float, default=COMPLIANCE, help="[m/N], 0: hard contacts")
    c.add_argument("--relaxation", type=float, default=RELAXATION)
    c.add_argument("--friction-law", default=FRICTION_LAW, choices=("coulomb", "anitescu"))
    a = p.parse_args()
    if a.what == "slab":
        slab(a.dir, a.dx, a.slab_width, a.settle_time)
    else:
        case(
            a.dir,
            a.slab,
            a.copies,
            a.basin,
            a.end,
            a.ranks,
            a.tolerance,
            2000,
            a.compliance,
            a.relaxation,
            a.friction_law,
        )


if __name__ == "__main__":
    main()
