#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Create the Lituya Bay case (thesis section 5.3, Fig. 5.9) from base/.

usage: setupCase.py CASEDIR [full|medium|reduced|thesis]
       setupCase.py --packing DIR   (thesis: the packing case for grainDeposit)

Geometry (our reading of thesis Fig. 5.9 and section 5.3.1; x = 0 at the
initial left shoreline, y = 0 at the still-water level, both shores at 45 deg):
- water depth H = 122 m, still-water surface L = 1342 m long from shore to
  shore (flat bottom 1342 - 2 H = 1098 m);
- the slide: a block 970 m long (along the slope) and 92 m thick (normal to
  the slope) lying on the left shore, its lower end at 230 m above the water;
- wave gauge at x = 885 m; run-up measured on the right shore.

Grains: diameters uniform in [dMin, 3 dMin] (polydispersity 3), rho 2640
kg/m^3.  The thesis' numbers are not mutually consistent: 27,960 discs of mean
radius 1.35 m have 1.6e5 m^2 of solid per metre, more than the block's
970 x 92 = 8.9e4 m^2, while the stated slide mass 98.5e3 t/m is 3.73e4 m^2 of
rock.  We keep the block, the grain count and the mass (the quantity that
sets the wave energy): dMin follows from N * pi/4 * E[d^2] = 98.5e6/2640 m^2,
i.e. a mean radius of 0.63 m for the full case (0.42 solid fraction in the
block; the grains compact as they slide).  `reduced` keeps the geometry and
the mass with 150 grains on a coarse mesh (CI, < 60 s).

The grains are placed by random sequential addition (largest first, seeded)
in the block, d/2 off the slope, and written as grainDeposit's `list`.

`thesis` keeps the thesis' grain size and mass instead of its grain count:
6,015 discs of mean radius 1.35 m (d uniform in [1.35, 4.05] m) are the
stated 98.5e3 t/m, packed densely as the thesis did (a space-filling
packing): grainDeposit `method rain` lays them in a 970 m wide box
(packing/, instantiated in CASEDIR_packing by --packing; solid fraction
~0.8, a block ~48 m thick), whose deposit is scaled to the exact mass
(factor ~1 +- 1 %) and rotated onto the slope.  5 m cells over the slide
path, the bay (and 150 m of air above it) and a 60 m band along the whole
run-up shore.
Writes CASEDIR/caseParameters.json (read by postProcess.py) and
CASEDIR/gmshArgs (the -setnumber arguments of lituyaBay.geo).
"""

import json
import math
import os
import sys

import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))

H, L = 122.0, 1342.0  # water depth, shore-to-shore length [m]
SLIDE_LENGTH, SLIDE_THICKNESS, SLIDE_HEIGHT = 970.0, 92.0, 230.0  # [m]
SLIDE_MASS = 98.5e6  # [kg per m of thickness], thesis section 5.3.1
RHO_S, LAMBDA = 2640.0, 3.0  # grain density, d_max/d_min
GAUGE_X = 885.0  # [m] from the initial left shore
DZ = 1.0  # mesh thickness [m] (results per metre)

MODES = {
    # hFine/hCoarse: cell sizes [m]; grains: count; endTime, writeInterval [s]
    "full": dict(
        hFine=4.0,
        hCoarse=40.0,
        grains=27960,
        endTime=100.0,
        writeInterval=0.5,
        gaugeInterval=0.1,
        contactIter=2000,
        ytop=1050.0,
    ),
    "medium": dict(
        hFine=10.0,
        hCoarse=60.0,
        grains=1500,
        endTime=60.0,
        writeInterval=1.0,
        gaugeInterval=0.1,
        contactIter=1000,
        ytop=1050.0,
    ),
    "thesis": dict(
        hFine=5.0,
        hCoarse=40.0,
        grains=6015,
        endTime=100.0,
        writeInterval=0.5,
        gaugeInterval=0.1,
        contactIter=1000,
        ytop=1050.0,
        yFine=150.0,
        bandRight=60.0,
        packing="rain",
    ),
    "reduced": dict(
        hFine=25.0,
        hCoarse=80.0,
        grains=150,
        endTime=55.0,
        writeInterval=1.0,
        gaugeInterval=0.2,
        contactIter=500,
        ytop=1050.0,
    ),
}


def grain_diameters(n, rng):
    """n diameters uniform in [dMin, LAMBDA dMin] with the slide's rock area
    SLIDE_MASS/RHO_S in expectation: E[d^2] = dMin^2 (1 + l + l^2)/3."""
    area = SLIDE_MASS / RHO_S
    dmin = math.sqrt(area / (n * math.pi / 4 * (1 + LAMBDA + LAMBDA**2) / 3))
    d = rng.uniform(dmin, LAMBDA * dmin, n)
    d *= math.sqrt(area / (math.pi / 4 * np.sum(d**2)))  # exact slide mass
    return np.sort(d)[::-1], dmin


def place_block(d, rng, max_tries=20000):
    """Random sequential addition of discs of diameters d (largest first) in
    the slide block; returns the (n, 2) centres.  Raises RuntimeError when a
    disc cannot be placed."""
    t = np.array([-1.0, 1.0]) / math.sqrt(2)  # up the left slope
    nrm = np.array([1.0, 1.0]) / math.sqrt(2)  # out of the slope, into the fluid
    p0 = np.array([-SLIDE_HEIGHT, SLIDE_HEIGHT])  # lower end of the block, on the slope
    cell = d.max()
    grid = {}
    ab = np.zeros((len(d), 2))
    for i, di in enumerate(d):
        r = 0.5 * di
        for _ in range(max_tries):
            a = rng.uniform(r, SLIDE_LENGTH - r)
            b = rng.uniform(r * 1.001, SLIDE_THICKNESS - r)
            ia, ib = int(a // cell), int(b // cell)
            ok = True
            for ja in (ia - 1, ia, ia + 1):
                for jb in (ib - 1, ib, ib + 1):
                    for j in grid.get((ja, jb), ()):
                        if (a - ab[j, 0]) ** 2 + (b - ab[j, 1]) ** 2 < (
                            0.5 * (di + d[j]) * 1.001
                        ) ** 2:
                            ok = False
                            break
                    if not ok:
                        break
                if not ok:
                    break
            if ok:
                ab[i] = (a, b)
                grid.setdefault((ia, ib), []).append(i)
                break
        else:
            raise RuntimeError(f"cannot place grain {i} (d = {di:.3g} m) in the block")
    return p0 + np.outer(ab[:, 0], t) + np.outer(ab[:, 1], nrm)


THESIS_DMIN, PACK_HEIGHT = 1.35, 120.0  # [m] (mean radius 1.35 m); packing box height


def write_packing(case, n):
    """The packing case (packing/): n discs of d in [THESIS_DMIN, 3
    THESIS_DMIN] for grainDeposit method rain in a SLIDE_LENGTH wide box."""
    subs = {
        "@LENGTH@": f"{SLIDE_LENGTH:g}",
        "@HEIGHT@": f"{PACK_HEIGHT:g}",
        "@NX@": str(int(SLIDE_LENGTH / 10)),
        "@NY@": str(int(PACK_HEIGHT / 10)),
        "@NUMBER@": str(n),
        "@DMIN@": f"{THESIS_DMIN:g}",
    }
    nscdpost.instantiate_case(os.path.join(here, "packing"), case, subs)
    print(f"{case}: run blockMesh and grainDeposit here (method rain, {n} grains)")


def packed_block(packing):
    """(x, d, phi, thickness): the rain deposit of the packing case scaled
    to the slide mass (positions and diameters by the same factor: the
    contacts are kept; the positions by 1e-5 more, so that touching discs
    keep a gap above the written round-off) and rotated onto the slope, its
    floor 1 mm off it; phi the solid fraction of the deposit's interior
    (centres from d_max above the floor to d_max below the lowest point of
    its surface, the highest grain top of each 10 m column), thickness the
    surface's mean height."""
    g = nscdpost.read_grains(packing, "0")
    xy, d = g["x"][:, :2], g["d"]
    k = math.sqrt(SLIDE_MASS / RHO_S / (math.pi / 4 * np.sum(d**2)))
    d, xy = k * d, k * (1 + 1e-5) * xy
    column = (xy[:, 0] // 10).astype(int)
    surface = np.full(column.max() + 1, -np.inf)
    np.maximum.at(surface, column, xy[:, 1] + d / 2)
    lo, hi = d.max(), surface.min() - d.max()
    inner = (xy[:, 1] > lo) & (xy[:, 1] < hi)
    phi = float(np.sum(math.pi / 4 * d[inner] ** 2) / (k * SLIDE_LENGTH * (hi - lo)))
    t = np.array([-1.0, 1.0]) / math.sqrt(2)
    nrm = np.array([1.0, 1.0]) / math.sqrt(2)
    p0 = np.array([-SLIDE_HEIGHT, SLIDE_HEIGHT]) + 1e-3 * nrm
    x = p0 + np.outer(xy[:, 0], t) + np.outer(xy[:, 1], nrm)
    return x, d, phi, float(surface.mean())


def env_nonnegative(name, what):
    """The environment variable `name` as a number >= 0, None when unset;
    exits naming the variable and `what` it must be otherwise."""
    text = os.environ.get(name, "").strip()
    if not text:
        return None
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not (value >= 0 and math.isfinite(value)):
        sys.exit(f"setupCase.py: {name}={text!r}: give {what}")
    return value


def slope_friction():
    """SLOPE_FRICTION=<mu> (environment): the Coulomb coefficient of the
    grains on the left shore, the slide's bed (grainProperties wallFriction;
    default: the rock's 0.93).  A sensitivity of issue 58: 0 lets the slide
    reach the shore near its frictionless speed.  None when unset."""
    return env_nonnegative("SLOPE_FRICTION", "a Coulomb coefficient >= 0 (e.g. 0)")


def slide_speed():
    """SLIDE_SPEED=<v> (environment) [m/s]: every grain of the slide starts
    moving down the left slope at v (grainDepositDict initialVelocity), as
    Fritz et al.'s pneumatic generator launched theirs (110 m/s mean speed
    at impact); issue 58's sensitivity.  None when unset."""
    return env_nonnegative("SLIDE_SPEED", "a speed >= 0 in m/s (e.g. 110)")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    if sys.argv[1] == "--packing":
        write_packing(sys.argv[2], MODES["thesis"]["grains"])
        return
    case = sys.argv[1]
    mode = sys.argv[2] if len(sys.argv) > 2 else "full"
    if mode not in MODES:
        sys.exit(f"setupCase.py: mode must be one of {sorted(MODES)}")
    m = MODES[mode]
    slope_mu, v0 = slope_friction(), slide_speed()  # checked before anything is written
    rng = np.random.default_rng(1958)
    if m.get("packing") == "rain":
        packing = case.rstrip("/") + "_packing"
        if not os.path.isdir(os.path.join(packing, "0", "lagrangian")):
            sys.exit(
                f"setupCase.py: no rain deposit in {packing} (setupCase.py --packing {packing},"
                " blockMesh and grainDeposit there first; ./Allrun thesis does it)"
            )
        x, d, phi, thickness = packed_block(packing)
    else:
        d, _dmin = grain_diameters(m["grains"], rng)
        x = place_block(d, rng)
        phi = float(np.pi / 4 * np.sum(d**2) / (SLIDE_LENGTH * SLIDE_THICKNESS))
        thickness = SLIDE_THICKNESS
    grains = "\n".join(
        f"({xi:.10g} {yi:.10g} {0.5 * DZ:.10g} {di:.10g})" for (xi, yi), di in zip(x, d)
    )
    dmax_dt = 0.25 * m["hFine"] / 150.0  # initial step: Co 0.25 at 150 m/s
    subs = {
        "@ENDTIME@": f"{m['endTime']:g}",
        "@WRITEINTERVAL@": f"{m['writeInterval']:g}",
        "@DELTAT@": f"{min(1e-3, dmax_dt):.3g}",
        "@MAXDELTAT@": f"{m['hFine'] / 100:.3g}",
        "@CONTACTITER@": str(m["contactIter"]),
        "@GAUGEINTERVAL@": f"{m['gaugeInterval']:g}",
        "@GRAINS@": grains,
    }
    nscdpost.instantiate_case(os.path.join(here, "base"), case, subs)
    if slope_mu is not None:
        with open(os.path.join(case, "constant", "grainProperties"), "a") as fh:
            fh.write(
                f"wallFriction {{ leftShore {slope_mu:g}; }}   // SLOPE_FRICTION: the slide's bed\n"
            )
    if v0 is not None:
        down = v0 / math.sqrt(2)  # down the 45 deg left slope: (1, -1)/sqrt(2)
        with open(os.path.join(case, "system", "grainDepositDict"), "a") as fh:
            fh.write(
                f"initialVelocity ({down:.10g} {-down:.10g} 0);   // SLIDE_SPEED: the launch\n"
            )
    mass = RHO_S * math.pi / 4 * float(np.sum(d**2)) * DZ
    zc = float(np.sum(d**2 * x[:, 1]) / np.sum(d**2))
    params = {
        "mode": mode,
        "water_depth": H,
        "bay_length": L,
        "gauge_x": GAUGE_X,
        "thickness": DZ,
        "slide_length": SLIDE_LENGTH,
        "slide_thickness": thickness,
        "slide_height": SLIDE_HEIGHT,
        "grain_count": int(len(d)),
        "grain_d_min": float(d.min()),
        "grain_d_max": float(d.max()),
        "grain_mean_radius": float(0.5 * d.mean()),
        "grain_density": RHO_S,
        "slide_mass": mass,
        "slide_centre_height": zc,
        "solid_fraction_block": phi,
        "h_fine": m["hFine"],
        "h_coarse": m["hCoarse"],
        "y_top": m["ytop"],
        "slope_friction": 0.93 if slope_mu is None else slope_mu,
        "slide_launch_speed": 0.0 if v0 is None else v0,
    }
    with open(os.path.join(case, "caseParameters.json"), "w") as fh:
        json.dump(params, fh, indent=2)
    with open(os.path.join(case, "gmshArgs"), "w") as fh:
        fh.write(
            f"-setnumber H {H:g} -setnumber L {L:g} -setnumber Ytop {m['ytop']:g} "
            f"-setnumber dz {DZ:g} -setnumber hFine {m['hFine']:g} "
            f"-setnumber hCoarse {m['hCoarse']:g} -setnumber yFine {m.get('yFine', 250):g} "
            f"-setnumber bandRight {m.get('bandRight', 0):g}\n"
        )
    print(
        f"{case}: {mode}, {len(d)} grains d in [{d.min():.3g}, {d.max():.3g}] m, "
        f"slide {mass / 1e3:.4g} t/m (thesis 98.5e3 t/m), mean radius {d.mean() / 2:.3g} m,"
        " solid fraction in the block "
        f"{params['solid_fraction_block']:.3f}, cells ~{m['hFine']:g} m"
    )


if __name__ == "__main__":
    main()
