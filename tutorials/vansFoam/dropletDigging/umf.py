#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Minimum fluidisation velocity U_mf of the dropletDigging bed, measured in
vansFoam.

usage: umf.py setup CASE DEPOSIT_ROOT [SIMILARITY [PERMEABILITY_RATIO [U_MAX [RAMP]]]]
       umf.py post CASE [CASE ...]

The bed of DEPOSIT_ROOT/deposit in the tutorial's cell with the floor as a
gas inlet (`inlet`, a grain wall: a porous floor; a grain blown to the
top leaves through `outletPatches`) and the gas, grain
porosity and similarity scaling of the digging cases (setupCase.setup, the
same Hele-Shaw wall friction); no droplet, no cohesion (U_mf is the
cohesionless definition: the gas carries the bed's weight).  The inlet
velocity rises linearly from 0 to U_MAX [m/s] (default 4 x Ergun's U_mf of
the case) over RAMP s (default 1.5), slow against the grains' Stokes time.

The standard measurement (Kunii & Levenspiel, Fluidization Engineering, 2nd
ed., 1991, section 3.2, Figure 3.3): the bed's pressure drop dp against the
superficial gas velocity U (the inlet pressure less the gas head and the
gas's Hele-Shaw wall friction over the column: the empty-column drop); the
fixed-bed branch is fitted with
dp = b U + a U^2 (a >= 0) where dp < 0.7 W/A, and U_mf is where the fitted
branch reaches the bed's buoyant weight per unit area W/A.  The plateau
dp/(W/A) above 1.5 U_mf says whether the bed is carried by the gas (1) or
also by the walls (> 1: arching and wall friction of the grains).

post writes CASE/umf.json: `U_mf` [m/s], `U_mf_ergun` [m/s] (Ergun 1952 at
the gas fraction and weight fraction of the cell, `postProcess.ergun_umf`),
`U_mf_wen_yu` [m/s] (Wen & Yu 1966, AIChE J. 12:610, for solid spheres of
the grain density: a correlation, not for porous discs), `weight_per_area`
[Pa], `darcy_coefficient` b [Pa s/m], `inertial_coefficient` a [Pa s^2/m^2],
`plateau` (mean dp/(W/A) for U > 1.5 U_mf), `U_first_dp_095_weight` [m/s]
(the first superficial velocity with dp >= 0.95 W/A), and the series `U`, `dp`.
"""

import json
import math
import os
import sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
import nscdpost  # noqa: E402
import postProcess as pp  # noqa: E402
import setupCase as sc  # noqa: E402

RAMP = 1.5
FIT_FRACTION = 0.7


def ergun_case_umf(info, eps):
    """Ergun's U_mf [m/s] of the case of case.json `info` at gas fraction eps."""
    return pp.ergun_umf(
        info["grain_diameter"],
        eps,
        info["grain_density"],
        rho_f=info["rho"],
        mu=info["mu"],
        weight_fraction=info["bed_weight_fraction"],
    )


def wen_yu_umf(d, rho_p, rho_f, mu, g=9.81):
    """Wen & Yu (1966) U_mf [m/s]: Re_mf = sqrt(33.7^2 + 0.0408 Ar) - 33.7,
    Ar = rho_f (rho_p - rho_f) g d^3 / mu^2 (solid spheres of diameter d)."""
    ar = rho_f * (rho_p - rho_f) * g * d**3 / mu**2
    re = math.sqrt(33.7**2 + 0.0408 * ar) - 33.7
    return re * mu / (rho_f * d)


def setup(case, deposit_root, similarity=None, permeability_ratio=1.0, u_max=None, ramp=RAMP):
    """The fluidisation column CASE on DEPOSIT_ROOT/deposit (module
    docstring).  similarity: reference grain diameter [m] of the similarity
    scaling (None: off), permeability_ratio its correction
    (setupCase.similarity_factors).  u_max [m/s]: inlet velocity at the end of the ramp
    (None: 4 x Ergun's U_mf at gas fraction 1 - 0.4).  Raises ValueError if
    u_max or ramp is not positive."""
    sc.setup(
        case,
        20.0,
        ramp,
        root=os.path.dirname(case) or ".",
        porosity="auto",
        similarity=similarity,
        deposit_root=deposit_root,
        write_interval=ramp / 6,
        permeability_ratio=permeability_ratio or 1.0,
    )
    info = json.load(open(os.path.join(case, "case.json")))
    if u_max is None:
        u_max = 4 * ergun_case_umf(info, 1 - sc.PHI_BED)
    if not (u_max > 0 and ramp > 0):
        raise ValueError(f"umf.setup: U_MAX {u_max} and RAMP {ramp} must be > 0")
    t_k = 20.0 + 273.15
    sc.mesh_and_grains(
        case,
        info["grain_diameter"],
        info["grain_density"] * (1 - info["grain_porosity"]),
        inlet=True,
    )
    with open(os.path.join(case, "constant", "grainProperties"), "a") as f:
        f.write(f"initialTemperature {t_k};\nwallTemperatures {{ walls {t_k}; inlet {t_k}; }}\n")
    emp = "frontAndBack { type empty; }"
    sc.write(
        case,
        "0/U",
        "volVectorField",
        "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
        "boundaryField { walls { type noSlip; }"
        f" inlet {{ type uniformFixedValue; uniformValue table ((0 (0 0 0)) ({ramp:g} (0 {u_max:.9g} 0)));"
        " value uniform (0 0 0); }"
        f" outlet {{ type pressureInletOutletVelocity; value uniform (0 0 0); }} {emp} }}\n",
    )
    sc.write(
        case,
        "0/p",
        "volScalarField",
        "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
        'boundaryField { "(walls|inlet)" { type fixedFluxPressure; value uniform 0; }'
        f" outlet {{ type fixedValue; value uniform 0; }} {emp} }}\n",
    )
    for name, val in (("T", t_k), ("psi", 0)):
        dim = "[0 0 0 1 0 0 0]" if name == "T" else "[0 0 0 0 0 0 0]"
        sc.write(
            case,
            f"0/{name}",
            "volScalarField",
            f"dimensions {dim};\ninternalField uniform {val};\n"
            f'boundaryField {{ "(walls|inlet)" {{ type fixedValue; value uniform {val}; }}'
            f" outlet {{ type inletOutlet; inletValue uniform {val}; value uniform {val}; }} {emp} }}\n",
        )
    path = os.path.join(case, "constant", "couplingProperties")
    text = open(path).read()
    open(path, "w").write(
        "\n".join(ln for ln in text.splitlines() if not ln.startswith("cohesion")) + "\n"
    )
    sc.write(
        case,
        "system/fvOptions",
        "dictionary",
        f"heleShaw {{ type heleShawFriction; selectionMode all; gap {sc.GAP}; fields (U); }}\n",
    )
    os.remove(os.path.join(case, "constant", "dropletProperties"))
    path = os.path.join(case, "system", "controlDict")
    text = open(path).read().replace('libs ("libdropletCoupling.so");\n', "")
    text = text.replace(f"endTime {ramp}", f"endTime {ramp:g}")
    open(path, "w").write(
        text + "functions {\n"
        '  inletPressure { type surfaceFieldValue; libs ("libfieldFunctionObjects.so");'
        " regionType patch; name inlet; operation areaAverage; fields (p); writeFields false;"
        " log false; writeControl timeStep; writeInterval 1; }\n"
        '  inletFlux { type surfaceFieldValue; libs ("libfieldFunctionObjects.so");'
        " regionType patch; name inlet; operation sum; fields (phi); writeFields false;"
        " log false; writeControl timeStep; writeInterval 1; }\n}\n"
    )
    info.update(
        {"umf_ramp": ramp, "umf_u_max": u_max, "bed_temperature_C": 20.0, "cohesion_force": 0.0}
    )
    nscdpost.write_json(os.path.join(case, "case.json"), info)
    print(f"{case}: fluidisation column, inlet 0 -> {u_max * 1e3:.3g} mm/s over {ramp:g} s")


def read_dat(case, name):
    """(time, value) of postProcessing/<name>/<start>/surfaceFieldValue.dat,
    restarts joined (`nscdpost.read_dat_history`)."""
    a = nscdpost.read_dat_history(case, name, "surfaceFieldValue.dat")
    return a[:, 0], a[:, 1]


def measure(case):
    """The U_mf measurement of a finished column CASE (module docstring);
    returns the umf.json dict.  Raises ValueError if the ramp never brings dp
    to W/A (the bed was not fluidised: raise U_MAX)."""
    info = json.load(open(os.path.join(case, "case.json")))
    g = nscdpost.read_grains(case, "0")
    rho_g = info["grain_density"] * (1 - info["grain_porosity"])
    area = np.sum(math.pi * g["d"] ** 2 / 4)  # per unit depth [m^2/m]
    w_a = area * (rho_g - info["rho"]) * 9.81 / sc.W  # [Pa]
    t, p = read_dat(case, "inletPressure")
    tf, phi = read_dat(case, "inletFlux")
    flux = np.interp(t, tf, phi)
    u = -flux / (sc.W * sc.DEPTH)  # superficial velocity [m/s]
    # bed pressure drop [Pa]: the inlet pressure less the gas head and the
    # gas's Hele-Shaw wall friction 12 mu U_s/l^2 per unit volume over the
    # column (fvOption heleShawFriction, thesis eq. 4.14: uniform, the
    # superficial velocity being uniform in the column), the empty-column
    # pressure drop that fluidisation measurements subtract
    hele_shaw = 12 * info["mu"] * u * sc.H / sc.GAP**2
    dp = info["rho"] * (p - 9.81 * sc.H) - hele_shaw
    if not np.any(dp >= w_a):
        raise ValueError(f"{case}: dp reaches {dp.max():.4g} Pa < W/A = {w_a:.4g} Pa: raise U_MAX")
    # first time the drop reaches 0.95 W/A (at the plateau dp hovers within a
    # few % of W/A, so W/A itself is crossed late and at random)
    first = int(np.argmax(dp >= 0.95 * w_a))
    fit = (dp < FIT_FRACTION * w_a) & (u > 0) & (np.arange(len(u)) < first)
    A = np.column_stack([u[fit], u[fit] ** 2])
    (b, a), *_ = np.linalg.lstsq(A, dp[fit], rcond=None)
    if a < 0:
        b, a = float(np.sum(u[fit] * dp[fit]) / np.sum(u[fit] ** 2)), 0.0
    umf = w_a / b if a == 0 else (-b + math.sqrt(b * b + 4 * a * w_a)) / (2 * a)
    above = u > 1.5 * umf
    eps = 1 - sc.PHI_BED
    res = {
        "U_mf": float(umf),
        "U_mf_ergun": ergun_case_umf(info, eps),
        "U_mf_wen_yu": wen_yu_umf(info["grain_diameter"], rho_g, info["rho"], info["mu"]),
        "U_first_dp_095_weight": float(u[first]),
        "weight_per_area": float(w_a),
        "darcy_coefficient": float(b),
        "inertial_coefficient": float(a),
        "fit_points": int(fit.sum()),
        "hele_shaw_drop_at_U_mf": float(12 * info["mu"] * umf * sc.H / sc.GAP**2),
        "plateau": float(np.mean(dp[above]) / w_a) if above.any() else None,
        "gas_fraction": eps,
        "grain_diameter": info["grain_diameter"],
        "gas_viscosity": info["mu"],
        "similarity_reference_diameter": info.get("similarity_reference_diameter"),
        "U": u[:: max(1, len(u) // 400)].tolist(),
        "dp": dp[:: max(1, len(u) // 400)].tolist(),
    }
    return res


def main(argv):
    if len(argv) >= 3 and argv[0] == "setup":
        num = [float(a) if a != "None" else None for a in argv[3:]]
        setup(argv[1], argv[2], *num)
    elif len(argv) >= 2 and argv[0] == "post":
        for case in argv[1:]:
            r = measure(case)
            nscdpost.write_json(os.path.join(case, "umf.json"), r)
            print(
                f"{case}: U_mf {r['U_mf'] * 1e3:.3g} mm/s (Ergun {r['U_mf_ergun'] * 1e3:.3g},"
                f" Wen-Yu {r['U_mf_wen_yu'] * 1e3:.3g}), W/A {r['weight_per_area']:.4g} Pa,"
                f" plateau {r['plateau']}"
            )
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
