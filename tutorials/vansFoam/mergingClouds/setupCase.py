#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Set up a falling-cloud case (thesis section 3.3, Figures 3.10-3.11; after
MigFlow's 2D drop example): clouds ("droplets") of radius R = 3.3 mm made of
glass discs (2450 kg/m^3) at solid fraction 0.2, in a fluid of 1030 kg/m^3
and 0.6 Pa s, released at rest in a closed box of square cells.

usage: setupCase.py CASEDIR [--clouds 1|2] [--cells-per-radius N]
                    [--grain-diameter D] [--width W] [--height H]
                    [--end T] [--write-interval T] [--max-delta-t DT]
                    [--drop [--drop-viscosity-ratio L]]
  --clouds 2 (default): two clouds one above the other, centres 10 mm apart
  (the trailing cloud above); 1: one cloud (the convergence study).
  --cells-per-radius: R/h (default 4); --grain-diameter: default 200 um,
  218 discs per cloud (README, "Grain size": the thesis' 25 um grains,
  13,939 discs per cloud, or MigFlow's drop example's 50 um, 3,485, run
  less than 0.1 s here before a contact between two drag-bound grains sets
  off a local jet).  --width, --height: the box [m] (default 12 R x 60 R),
  rounded to whole cells.
  --drop: the pure-fluid reference instead (baseDrop/, vansInterFoam, no
  grains): each cloud a drop of the cloud's mean density rho_f + phi
  (rho_p - rho_f) = 1314 kg/m^3 and L times the fluid's viscosity (default
  L = 1), no surface tension, alpha.water the drop's area fraction per cell.

The discs of a cloud: random sequential addition of N = round(phi R^2 /
r^2) discs (r = d/2), centres uniform in the disc of radius R - r, no two
centres closer than 1.05 d (MigFlow's 2.1 r), the same seed for every mesh.
Cloud k's discs are grains k N .. (k + 1) N - 1 (grainId), cloud 0 the
lower (leading) one.  setup.json records the clouds for postProcess.py.
"""

import argparse
import math
import os

import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))

R_CLOUD = 3.3e-3  # [m] cloud radius (thesis section 3.3)
PHI = 0.2  # solid fraction in a cloud
SPACING = 10e-3  # [m] between the two clouds' centres
RHO_P, RHO_F, MU = 2450.0, 1030.0, 0.6  # [kg/m^3], [kg/m^3], [Pa s]
SEED = 3
RHO_CLOUD = RHO_F + PHI * (RHO_P - RHO_F)  # [kg/m^3] the cloud's mean density


def cloud_discs(radius, d, phi=PHI, seed=SEED):
    """(N, 2) disc centres of one cloud centred at the origin: random
    sequential addition in the disc of radius `radius` - d/2, N = round(phi
    radius^2 / (d/2)^2), minimum centre distance 1.05 d (a grid of cells of
    side 1.05 d finds the neighbours)."""
    n = round(phi * (2 * radius / d) ** 2)
    gap = 1.05 * d
    rin = radius - 0.5 * d
    rng = np.random.default_rng(seed)
    grid = {}
    out = []
    while len(out) < n:
        for x, y in rng.uniform(-rin, rin, (4 * n, 2)):
            if x * x + y * y > rin * rin:
                continue
            i, j = int(math.floor(x / gap)), int(math.floor(y / gap))
            near = (grid.get((a, b), ()) for a in range(i - 1, i + 2) for b in range(j - 1, j + 2))
            if any((x - p) ** 2 + (y - q) ** 2 < gap * gap for c in near for p, q in c):
                continue
            grid.setdefault((i, j), []).append((x, y))
            out.append((x, y))
            if len(out) == n:
                break
    return np.array(out)


def layout(clouds, width, height):
    """Centres of the clouds: on the box's axis, the upper cloud's centre 4 R
    below the lid, the other SPACING below it."""
    top = height - 4 * R_CLOUD
    return [(0.5 * width, top - SPACING * (clouds - 1 - k)) for k in range(clouds)]


def drop_fraction(centres, nx, ny, h, sub=8):
    """Area fraction of the drops (discs of radius R_CLOUD at `centres`) in
    each cell of the nx x ny blockMesh grid of side h (x fastest), from
    sub x sub points per cell."""
    s = (np.arange(sub) + 0.5) / sub
    xc = (np.arange(nx)[:, None] + s[None, :]).reshape(-1) * h
    yc = (np.arange(ny)[:, None] + s[None, :]).reshape(-1) * h
    inside = np.zeros((ny * sub, nx * sub), dtype=bool)
    for cx, cy in centres:
        inside |= (xc[None, :] - cx) ** 2 + (yc[:, None] - cy) ** 2 < R_CLOUD**2
    return inside.reshape(ny, sub, nx, sub).mean(axis=(1, 3)).reshape(-1)


def write_drop_case(a, subs, centres, nx, ny, h):
    """The pure-fluid reference case: baseDrop/ with base/'s blockMeshDict
    and alpha.water of the drops."""
    nu = MU * a.drop_viscosity_ratio / RHO_CLOUD
    subs = {**subs, "@DROPRHO@": f"{RHO_CLOUD:.9g}", "@DROPNU@": f"{nu:.9g}"}
    nscdpost.instantiate_case(os.path.join(here, "baseDrop"), a.case, subs)
    with open(os.path.join(here, "base", "system", "blockMeshDict")) as f:
        text = f.read()
    for k, v in subs.items():
        text = text.replace(k, v)
    with open(os.path.join(a.case, "system", "blockMeshDict"), "w") as f:
        f.write(text)
    alpha = drop_fraction(centres, nx, ny, h)
    path = os.path.join(a.case, "0", "alpha.water")
    with open(path) as f:
        text = f.read()
    values = "\n".join(f"{v:.9g}" for v in alpha)
    field = f"nonuniform List<scalar>\n{len(alpha)}\n(\n{values}\n)"
    with open(path, "w") as f:
        f.write(text.replace("internalField   uniform 0;", f"internalField   {field};"))
    return float(alpha.sum() * h * h / (len(centres) * math.pi * R_CLOUD**2))


def arguments():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("case")
    p.add_argument("--clouds", type=int, choices=(1, 2), default=2)
    p.add_argument("--cells-per-radius", type=float, default=4.0, metavar="N")
    p.add_argument("--grain-diameter", type=float, default=200e-6, metavar="D")
    p.add_argument("--width", type=float, default=12 * R_CLOUD, metavar="W")
    p.add_argument("--height", type=float, default=60 * R_CLOUD, metavar="H")
    p.add_argument("--end", default="10", metavar="T")
    p.add_argument("--write-interval", default="0.1", metavar="T")
    p.add_argument("--max-delta-t", default="2e-3", metavar="DT")
    p.add_argument("--drop", action="store_true")
    p.add_argument("--drop-viscosity-ratio", type=float, default=1.0, metavar="L")
    a = p.parse_args()
    if not 0 < a.grain_diameter < 0.5 * R_CLOUD:
        p.error("--grain-diameter must lie in (0, R/2)")
    if a.width < 4 * R_CLOUD or a.height < 8 * R_CLOUD + SPACING * (a.clouds - 1):
        p.error("--width must be >= 4 R and --height >= 8 R (+ 10 mm for two clouds)")
    return a


def main():
    a = arguments()
    h = R_CLOUD / a.cells_per_radius
    nx, ny = max(1, round(a.width / h)), max(1, round(a.height / h))
    W, H = nx * h, ny * h
    centres = layout(a.clouds, W, H)
    subs = {
        "@WIDTH@": f"{W:.9g}",
        "@HEIGHT@": f"{H:.9g}",
        "@H@": f"{h:.9g}",
        "@NX@": str(nx),
        "@NY@": str(ny),
        "@ENDTIME@": a.end,
        "@WRITE@": a.write_interval,
        "@MAXDT@": a.max_delta_t,
    }
    if a.drop:
        area = write_drop_case(a, subs, centres, nx, ny, h)
        nscdpost.write_json(
            os.path.join(a.case, "setup.json"),
            {
                "cloud_radius": R_CLOUD,
                "centres": [list(c) for c in centres],
                "h": h,
                "width": W,
                "height": H,
                "drop_density": RHO_CLOUD,
                "drop_viscosity_ratio": a.drop_viscosity_ratio,
                "drop_area_ratio": area,
            },
        )
        print(f"{a.case}: {a.clouds} drop(s), area / pi R^2 = {area:.4f}, mesh {nx} x {ny}")
        return
    disc = cloud_discs(R_CLOUD, a.grain_diameter)
    d = a.grain_diameter * (1 - 1e-9)
    lines = [f"({cx + x:.9g} {cy + y:.9g} 0 {d:.12g})" for cx, cy in centres for x, y in disc]
    nscdpost.instantiate_case(os.path.join(here, "base"), a.case, subs)
    with open(os.path.join(a.case, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
        )
        f.write(f"// {a.clouds} cloud(s) of {len(disc)} discs, released at rest at t = 0\n")
        f.write("material glass;\nmethod list;\ngrains\n(\n" + "\n".join(lines) + "\n);\n")
    nscdpost.write_json(
        os.path.join(a.case, "setup.json"),
        {
            "cloud_radius": R_CLOUD,
            "grain_diameter": a.grain_diameter,
            "grains_per_cloud": len(disc),
            "solid_fraction": len(disc) * (0.5 * a.grain_diameter / R_CLOUD) ** 2,
            "centres": [list(c) for c in centres],
            "cells_per_radius": a.cells_per_radius,
            "h": h,
            "width": W,
            "height": H,
        },
    )
    print(
        f"{a.case}: {a.clouds} cloud(s) x {len(disc)} discs (d = {a.grain_diameter * 1e6:.0f} um), "
        f"box {W * 1e3:.1f} x {H * 1e3:.1f} mm, mesh {nx} x {ny} (R/h = {a.cells_per_radius:g}), "
        f"endTime {a.end} s"
    )


if __name__ == "__main__":
    main()
