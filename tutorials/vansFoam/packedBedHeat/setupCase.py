#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Set up the packedBedHeat cases (thesis section 4.1.2).

usage: setupCase.py deposit [NGRAINS]   pour the grains onto a temporary floor
                                         (deposit/, method box + settle)
       setupCase.py freeze              turn the settled grains into a fixed
                                         bed (deposit/, method list, fixed yes)
       setupCase.py CASEDIR RE [MODEL [DY_D [TSCHEME]]]
                                         a case at superficial Reynolds number
                                         RE = U_s d/nu with the bed of deposit/

A column of square cross-section W = 8 d (d = 2 mm glass spheres), height
14 d: an empty inlet section of 4 d, a fixed random bed of NGRAINS spheres
(300: ~4 d deep), an empty outlet section above.  Air (thesis Table 4.1)
enters at T_in = 300 K with the uniform superficial velocity U_s through the
bottom, leaves at the top; the grains are held at T_p = 350 K.
Mesh: lateral cells 2 d (h/d = 2, 4 x 4 across), axial cells DY_D d
(default 0.125: the air's temperature relaxes over ~1/(lambda) = 0.3-1 d
in the bed, see README.md).
"""

import os
import sys

import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))

D = 2e-3  # grain diameter [m]
W = 8 * D  # column width (square) [m]
HEIGHT = 14 * D  # column height [m]
Y_BED = 4 * D  # bottom of the bed (temporary floor while pouring) [m]
N_GRAINS = 300
RHO, MU, CP, KAPPA = 1.204, 2e-5, 1010.0, 0.025
NU = MU / RHO
T_IN, T_P = 300.0, 350.0
FLOWTHROUGHS = 3.0  # run length in column flow-through times H/U_s
MAXCO = 1.0


def subs(dy_d=0.125, re=None, model="DiFeliceColburn", tscheme="limitedLinear 1"):
    ny = int(round(HEIGHT / (dy_d * D)))
    s = {
        "@W@": f"{W:.9g}",
        "@HEIGHT@": f"{HEIGHT:.9g}",
        "@NX@": str(int(round(W / (2 * D)))),
        "@NY@": str(ny),
        "@DY_D@": f"{dy_d:g}",
        "@NU@": f"{NU:.12g}",
        "@MODEL@": model,
        "@TP@": f"{T_P:g}",
        "@TIN@": f"{T_IN:g}",
        "@TSCHEME@": tscheme,
        "@MAXCO@": f"{MAXCO:g}",
        "@FLOWTHROUGHS@": f"{FLOWTHROUGHS:g}",
    }
    us = 0.0 if re is None else re * NU / D
    end = 1.0 if re is None else FLOWTHROUGHS * HEIGHT / us
    s.update(
        {
            "@US@": f"{us:.12g}",
            "@ENDTIME@": f"{end:.9g}",
            "@WRITEINTERVAL@": f"{end / 3:.9g}",
            "@DT0@": f"{0.1 * dy_d * D / max(us, 1e-9):.6g}",
        }
    )
    return s


def deposit(n=N_GRAINS, root=here):
    case = os.path.join(root, "deposit")
    nscdpost.instantiate_case(os.path.join(here, "base"), case, subs())
    with open(os.path.join(case, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
            "// pour: loose lattice above the temporary floor y = Y_BED, settle under gravity\n"
            "material glass;\nmethod box;\n"
            f"box {{ min (0 {Y_BED:.9g} 0); max ({W:.9g} {HEIGHT:.9g} {W:.9g}); }}\n"
            f"number {n};\ndMin {D};\nsizeRatio 1;\nseed 5;\n"
            "settle { maxTime 1; deltaT 2e-4; speedTolerance 2e-3;\n"
            f"  temporaryWalls ( {{ point (0 {Y_BED:.9g} 0); normal (0 1 0); }} ); }}\n"
        )
    print(f"{case}: {n} spheres (d = {D} m) to pour")


def freeze(root=here):
    """Replace deposit/system/grainDepositDict by the settled grains, fixed."""
    case = os.path.join(root, "deposit")
    g = nscdpost.read_grains(case, "0")
    lines = "\n".join(
        f"({x:.15g} {y:.15g} {z:.15g} {d:.15g})" for (x, y, z), d in zip(g["x"], g["d"])
    )
    with open(os.path.join(case, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
            "// the poured bed, frozen: every grain fixed\n"
            f"material glass;\nmethod list;\nfixed yes;\ngrains\n(\n{lines}\n);\n"
        )
    top = float(np.max(g["x"][:, 1] + 0.5 * g["d"]))
    print(f"{case}: {len(g['d'])} grains frozen, bed {Y_BED * 1e3:.3f} .. {top * 1e3:.3f} mm")


def setup(case, re, model="DiFeliceColburn", dy_d=0.125, tscheme="limitedLinear 1", root=here):
    dep = os.path.join(root, "deposit")
    s = subs(dy_d, re, model, tscheme)
    nscdpost.instantiate_case(os.path.join(here, "base"), case, s)
    nscdpost.copy_grain_state(dep, case)
    g = nscdpost.read_grains(dep, "0")
    assert g["fixed"].all(), "run `setupCase.py freeze` and grainDeposit first"
    nscdpost.write_json(
        os.path.join(case, "bed.json"),
        {
            "reynolds": re,
            "superficial_velocity": float(s["@US@"]),
            "model": model,
            "d": D,
            "width": W,
            "height": HEIGHT,
            "bed_bottom": Y_BED,
            "grains": int(len(g["d"])),
            "grain_surface": float(np.sum(np.pi * g["d"] ** 2)),
            "grain_volume": float(np.sum(np.pi / 6 * g["d"] ** 3)),
            "bed_top": float(np.max(g["x"][:, 1] + 0.5 * g["d"])),
            "rho": RHO,
            "nu": NU,
            "cp": CP,
            "kappa": KAPPA,
            "T_in": T_IN,
            "T_p": T_P,
            "dy_over_d": dy_d,
            "T_scheme": tscheme,
        },
    )
    print(
        f"{case}: Re = {re:g}, U_s = {float(s['@US@']):.5g} m/s, endTime {s['@ENDTIME@']} s, "
        f"{s['@NX@']} x {s['@NY@']} x {s['@NX@']} cells, model {model}"
    )


if __name__ == "__main__":
    if sys.argv[1] == "deposit":
        deposit(int(sys.argv[2]) if len(sys.argv) > 2 else N_GRAINS)
    elif sys.argv[1] == "freeze":
        freeze()
    else:
        args = sys.argv[1:]
        setup(
            args[0],
            float(args[1]),
            *(args[2:3] or ["DiFeliceColburn"]),
            *([float(args[3])] if len(args) > 3 else []),
            *(args[4:5]),
        )
