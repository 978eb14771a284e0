#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Set up the bubbling fluidised bed cases (thesis section 4.2, Table 4.1,
after the pseudo-2D experiment of Patil et al.).

usage: setupCase.py deposit                 the settled bed, once
       setupCase.py CASEDIR V [END [S]]     a case with inflow velocity V [m/s]
                                            (superficial), END [s] simulated (default 8),
                                            heat time-scale factor S (default 5)

Geometry (Table 4.1): w = 8 cm wide, h = 25 cm high, Hele-Shaw gap p = 1.5 cm
(front/rear walls: eq. 4.14), closed central nozzle l = 1.2 cm in the porous
bottom plate, cells of ~4 mm (h/d ~ 4.4; 8 + 3 + 8 across, 62 high).  Bed: glass discs with d
uniform in [0.8, 1] mm, as many as make m = 75 g over the gap p
(N = m / (rho_p p pi <d^2>/4) = 3,131), settled by grainDeposit.

Heat: grains at T0 = 363 K (Table 4.1 does not give the initial bed
temperature; Patil et al. heated their beads to ~90 C; the results are given
as the excess temperature (T - 290)/(T0 - 290) too, which the linear heat
equations make independent of T0 up to the weak Boussinesq effect), air in at
290 K, side walls at 290 K (h_w = 350 W m^-2 K^-1), front/rear walls through
q_l = lambda (T_w - T), lambda = 4e4 W m^-3 K^-1 (thesis 4.2.1).
The grain heat capacity is c/S: cooling runs S times faster than the bed
hydrodynamics, and the post-processing reports physical time = S t.
"""

import os
import sys

import nscdpost

here = os.path.dirname(os.path.abspath(__file__))

WIDTH, HEIGHT, GAP, NOZZLE = 0.08, 0.25, 0.015, 0.012
CELL = 4e-3  # cell size ~4 mm (h/d ~ 4.4)
D_MIN, LAMBDA = 0.8e-3, 1.25
RHO_P, MASS = 2500.0, 0.075
MU_AIR, RHO_AIR = 2e-5, 1.204
T_IN, T_WALL, T0 = 290.0, 290.0, 363.0
H_WALL, LAMBDA_L = 350.0, 4e4
C_GRAIN, CP_AIR = 840.0, 1010.0
MEAN_D2 = D_MIN**2 * (1 + LAMBDA + LAMBDA**2) / 3  # <d^2>, d uniform
N_GRAINS = round(MASS / (RHO_P * GAP * 3.141592653589793 * MEAN_D2 / 4))
RAMP = 0.5  # inflow switched on over RAMP [s]
AVG_START = 5.0  # thesis Fig. 4.6-4.7


def subs(v=1.54, end=0, S=5.0, fvoptions=True):
    nside = round((WIDTH - NOZZLE) / 2 / CELL)
    nnoz = round(NOZZLE / CELL)
    x1 = (WIDTH - NOZZLE) / 2
    s = {
        "@WIDTH@": f"{WIDTH:.9g}",
        "@HEIGHT@": f"{HEIGHT:.9g}",
        "@H@": f"{CELL:.9g}",
        "@X1@": f"{x1:.9g}",
        "@X2@": f"{x1 + NOZZLE:.9g}",
        "@NSIDE@": str(nside),
        "@NNOZZLE@": str(nnoz),
        "@NY@": str(round(HEIGHT / CELL)),
        "@UIN@": f"{v * WIDTH / (WIDTH - NOZZLE):.9g}",
        "@RAMP@": f"{RAMP:g}",
        "@ENDTIME@": f"{end:g}",
        "@MAXDT@": "4e-4",
        "@WRITEINTERVAL@": "0.05",
        "@AVGSTART@": f"{AVG_START:g}",
        "@HEATSCALE@": f"{S:g}",
        "@CGRAIN@": f"{C_GRAIN / S:.9g}",
        "@T0@": f"{T0:g}",
    }
    lam = LAMBDA_L / (RHO_AIR * CP_AIR)  # kinematic: [1/s]
    s["@FVOPTIONS@"] = (
        (
            "heleShawFriction\n{\n    type            heleShawFriction;\n    selectionMode   all;\n"
            f"    gap             {GAP:g};     // p [m]: gamma = 12 mu/p^2 = {12 * MU_AIR / GAP**2:.4g} kg m^-3 s^-1\n"
            "}\n"
            "frontRearWallHeat\n{\n    type            scalarSemiImplicitSource;\n    selectionMode   all;\n"
            "    volumeMode      specific;\n"
            f"    // q_l/(rho Cp) = lambda/(rho Cp) (T_w - T), lambda = {LAMBDA_L:g} W m^-3 K^-1\n"
            f"    injectionRateSuSp {{ T ({lam * T_WALL:.9g} {-lam:.9g}); }}\n}}\n"
        )
        if fvoptions
        else ""
    )
    s["@TWALL@"] = (
        f"type convectiveHeatFlux; h {H_WALL:g}; Tinf {T_WALL:g}; value uniform {T_IN:g};"
        if fvoptions
        else "type zeroGradient;"
    )
    return s


def deposit(root=here):
    case = os.path.join(root, "deposit")
    nscdpost.instantiate_case(os.path.join(here, "base"), case, subs())
    with open(os.path.join(case, "system", "grainDepositDict"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary; object grainDepositDict; }\n"
            "material glass;\nmethod box;\n"
            f"box {{ min (0.002 0 0); max ({WIDTH - 0.002:.9g} 0.1 1); }}\n"
            f"number {N_GRAINS};\ndMin {D_MIN};\nsizeRatio {LAMBDA};\nseed 7;\n"
            "settle { maxTime 1; deltaT 2e-4; speedTolerance 2e-2; }\n"
        )
    print(
        f"{case}: {N_GRAINS} grains ({MASS * 1e3:g} g over the gap p = {GAP * 1e2:g} cm) to settle"
    )


def setup(case, v, end, S, root=here):
    dep = os.path.join(root, "deposit")
    nscdpost.instantiate_case(os.path.join(here, "base"), case, subs(v, end, S))
    nscdpost.copy_grain_state(dep, case)
    nscdpost.write_json(
        os.path.join(case, "case.json"),
        {
            "inflow_velocity": v,
            "heat_time_scale": S,
            "T0": T0,
            "T_in": T_IN,
            "n_grains": N_GRAINS,
            "bed_mass": MASS,
            "gap": GAP,
            "width": WIDTH,
            "avg_start": AVG_START,
            "end_time": end,
        },
    )
    print(f"{case}: v = {v} m/s, endTime {end} s, heat time scale S = {S}")


if __name__ == "__main__":
    if sys.argv[1] == "deposit":
        deposit()
    else:
        setup(
            sys.argv[1],
            float(sys.argv[2]),
            float(sys.argv[3]) if len(sys.argv) > 3 else 8.0,
            float(sys.argv[4]) if len(sys.argv) > 4 else 5.0,
        )
