#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark: where the falling cylinder's drag differs from the fixed one's
(thesis 3.3.3, issue 59 item 3).

The freely falling light cylinder of tutorials/vansFoam/cylinderSedimentation
(rho_s/rho_f = 1.01) sways through its shedding wake.  Its reference speed,
U_t = 2.501 cm/s (Namkoong, Yoo & Choi 2008, J. Fluid Mech. 604:33-53),
balances its net weight with C_D = 1.232, 8 % below the fixed cylinder's
1.34 at Re 156 (Henderson 1995, Phys. Fluids 7:2102).  These variants of the
same set-up (walls 12 D from the axis, D/h given, resolved scheme) separate
the scheme's drag from the free motion's:

  light      the tutorial's cylinder (setupCase.py CASE 8 D/h 0.28 yes 1e-3
             resolved 12): rotation coupling on
  norotation the same with rotationCoupling no and rigidViscosityRatio 0
             (the thesis' model: no grain rotation, no viscosity penalty)
  rigid      rotationCoupling no with the resolved scheme's default for it,
             the rigid interior (rigidViscosityRatio 1000)
  heavy      rho_s/rho_f = 10 under gravity 0.0109 m/s^2: the light
             cylinder's net weight, released at U_t; ten times the inertia
             against the lift, so it hardly sways: the free scheme in
             translation
  kinematic  the fixed (infinite-mass) disc moving at U_t through fluid at
             rest between walls at rest, 48 D of box ahead and 24 D behind:
             the Galilean image of fixedShedding.py's case
  upstream16 fixedShedding.py's fixed disc in a uniform inflow with the inlet
             16 D upstream instead of 8 D

Measures, per half second of the writes (every 0.05 s): the drag
coefficient C_D = D_f / (rho_f U^2 D / 2), D_f the grain's Ffluid (per unit
depth) along the motion less the hydrostatic buoyancy rho_f g V, U its speed
(free grains) or U_t (fixed ones); the mean fall speed and the lateral
velocity's rms.

usage: cylinderFreeMotion.py setup VARIANT CASE [D/h]   (default D/h 10)
       (cd CASE && blockMesh && grainDeposit)
       cylinderFreeMotion.py start VARIANT CASE   (heavy, kinematic: the
           start velocity in the deposited state)
       (cd CASE && vansFoam)   (one core; D/h 10, 8 s: 20-45 CPU minutes)
       cylinderFreeMotion.py post OUT.json VARIANT:CASE ...
"""

import datetime
import json
import os
import sys

import h5py
import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
tutorial = os.path.join(here, "..", "..", "..", "tutorials", "vansFoam", "cylinderSedimentation")
setupCase = nscdpost.load_module("cs_setupCase", os.path.join(tutorial, "setupCase.py"))
fixedShedding = nscdpost.load_module("cs_fixedShedding", os.path.join(tutorial, "fixedShedding.py"))

D, RHO_F, UT = setupCase.D, setupCase.RHO_F, setupCase.UT_REF
HEAVY = 10.0  # rho_s / rho_f of the heavy variant
#: gravity [m/s^2] that gives the heavy cylinder the light one's net weight
HEAVY_G = 0.01 * 9.81 / (HEAVY - 1)
VARIANTS = ("light", "norotation", "rigid", "heavy", "kinematic", "upstream16")


def _replace(path, old, new):
    text = open(path).read()
    assert text.count(old) == 1, (path, old)
    open(path, "w").write(text.replace(old, new))


def set_start_velocity(case, velocity):
    """Set grain 0's velocity in 0/grainState.h5 and 0/lagrangian/grains/U
    (after grainDeposit)."""
    with h5py.File(os.path.join(case, "0", "grainState.h5"), "r+") as f:
        f["velocities"][0] = velocity
    _replace(
        os.path.join(case, "0", "lagrangian", "grains", "U"),
        "1((0 0 0))",
        "1((%.12g %.12g 0))" % tuple(velocity[:2]),
    )


def setup(variant, case, cells_per_d=10.0):
    """Write the case of a variant; the kinematic and heavy start
    velocities are set by `start` after grainDeposit."""
    if variant in ("light", "norotation", "rigid", "heavy"):
        # setupCase.py CASE 8 D/h 0.28 ROTATION 1e-3 resolved 12
        setupCase.cylinder_case(
            case,
            8.0,
            cells_per_d,
            0.28,
            write_interval=0.05,
            rotation=variant not in ("norotation", "rigid"),
            max_dt=1e-3,
            wall_distance=12 * D,
            rho_s=HEAVY * RHO_F if variant == "heavy" else None,
        )
        setupCase.opt_in_resolved(
            case, "rigidViscosityRatio 0;\n" if variant == "norotation" else ""
        )
        if variant == "heavy":
            _replace(os.path.join(case, "constant", "g"), "(0 -9.81 0)", "(0 %.10g 0)" % -HEAVY_G)
    elif variant == "kinematic":
        h = D / cells_per_d
        lo, hi = (-48 * D, -12 * D), (24 * D, 12 * D)
        cells = (round((hi[0] - lo[0]) / h), round((hi[1] - lo[1]) / h))
        setupCase.write_case(
            case,
            lo,
            hi,
            cells,
            [(0.0, fixedShedding.SEED * D, D)],
            setupCase.RHO_S,
            RHO_F,
            setupCase.NU,
            gravity=(0, 0, 0),
            end_time=8.0,
            write_interval=0.05,
            max_co=0.5,
            max_dt=2e-3,
            fixed=True,
        )
    elif variant == "upstream16":
        fixedShedding.UPSTREAM = 16
        fixedShedding.setup(case, cells_per_d, 8.0, 24)
    else:
        sys.exit(
            f"cylinderFreeMotion.py: unknown variant {variant}; variants: {', '.join(VARIANTS)}"
        )


def start(variant, case):
    """The start velocities (after grainDeposit): heavy falls at U_t, the
    kinematic disc moves at U_t along -x."""
    if variant == "heavy":
        set_start_velocity(case, [0.0, -UT, 0.0])
    elif variant == "kinematic":
        set_start_velocity(case, [-UT, 0.0, 0.0])


def history(variant, case):
    """Per write: time, drag coefficient, speed along the motion, lateral
    velocity."""
    t, F, U = [], [], []
    for time, name in nscdpost.time_dirs(case):
        d = os.path.join(case, name, "lagrangian", "grains")
        if time > 0 and os.path.isfile(os.path.join(d, "Ffluid")):
            t.append(time)
            F.append(nscdpost.read_vector_field(os.path.join(d, "Ffluid"))[0])
            U.append(nscdpost.read_vector_field(os.path.join(d, "U"))[0])
    t, F, U = np.array(t), np.array(F), np.array(U)
    V = np.pi * D * D / 4
    if variant in ("kinematic", "upstream16"):  # motion along x, no gravity
        drag, speed, lateral = F[:, 0], np.full(len(t), UT), np.zeros(len(t))
    else:
        g = HEAVY_G if variant == "heavy" else 9.81
        drag, speed, lateral = F[:, 1] - RHO_F * g * V, -U[:, 1], U[:, 0]
    return t, drag / (0.5 * RHO_F * speed**2 * D), speed, lateral


#: the references of both benchmarks' JSON
REFERENCE = (
    "Namkoong, Yoo & Choi (2008) J. Fluid Mech. 604:33-53: U_t = 2.501 cm/s, "
    "C_D = 1.232 from the net weight; Henderson (1995) Phys. Fluids 7:2102: fixed cylinder "
    "1.350 (Re 100), 1.341 (Re 200); Williamson (1996) Annu. Rev. Fluid Mech. 28:477: "
    "St = 0.2175 - 5.1064/Re (0.185 at Re 156)"
)

#: the columns of half_second_rows
HALF_SECOND_COLUMNS = ["window start [s]", "C_D", "speed [m/s]", "lateral velocity rms [m/s]"]


def half_second_rows(t, cd, speed, lateral):
    """Per half second of the samples (t [s]): mean drag coefficient, mean
    speed [m/s], rms of the lateral velocity [m/s]."""
    rows = []
    for a in np.arange(0.0, t[-1] - 1e-9, 0.5):
        s = (t > a) & (t <= a + 0.5)
        if s.any():
            rows.append(
                [
                    float(a),
                    float(np.mean(cd[s])),
                    float(np.mean(speed[s])),
                    float(np.std(lateral[s])),
                ]
            )
    return rows


def post(out, pairs):
    variants = {}
    for pair in pairs:
        variant, case = pair.split(":", 1)
        t, cd, speed, lateral = history(variant, case)
        variants[variant] = {
            "end_time": float(t[-1]),
            "per_half_second": half_second_rows(t, cd, speed, lateral),
            "columns": HALF_SECOND_COLUMNS,
        }
    result = {
        "benchmark": "cylinderFreeMotion",
        "date": datetime.date.today().isoformat(),
        "reference": REFERENCE,
        "command": "cylinderFreeMotion.py setup VARIANT CASE 10; blockMesh; grainDeposit; "
        "cylinderFreeMotion.py start VARIANT CASE; taskset -c K vansFoam; cylinderFreeMotion.py post "
        + " ".join([os.path.basename(out)] + [p.split(":", 1)[0] + ":CASE" for p in pairs]),
        "variants": variants,
    }
    json.dump(result, open(out, "w"), indent=1)
    for v, r in variants.items():
        print(v, " ".join("%.1f:%.3f" % (row[0], row[1]) for row in r["per_half_second"]))


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "setup":
        setup(sys.argv[2], sys.argv[3], float(sys.argv[4]) if len(sys.argv) > 4 else 10.0)
    elif len(sys.argv) >= 4 and sys.argv[1] == "start":
        start(sys.argv[2], sys.argv[3])
    elif len(sys.argv) >= 4 and sys.argv[1] == "post":
        post(sys.argv[2], sys.argv[3:])
    else:
        sys.exit(__doc__)
