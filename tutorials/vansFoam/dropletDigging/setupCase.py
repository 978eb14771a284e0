#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Set up the dropletDigging cases (thesis section 4.3, Table 4.2).

usage: setupCase.py deposit [D_GRAIN]   the bed: grains of diameter D_GRAIN
                                         [m] (default 1e-3, reduced; tutorial
                                         Allrun: 5e-4; Table 4.2: 55e-6) poured
                                         into the 10 mm wide cell (deposit/)
       setupCase.py CASEDIR T_BED_C [ENDTIME [POROSITY]]
                                         a case at bed temperature T_BED_C
                                         [Celsius] with the bed of deposit/;
                                         POROSITY none | auto | n (default none)

2D Hele-Shaw cell (thesis Figure 4.9): w = 10 mm wide, h = 30 mm high, gap
l = 1.5 mm (front/back wall friction, fvOption heleShawFriction, eq. 4.14),
bed of height ~h_p at T_bed (grains and side/bottom walls), air (Table 4.2)
at T_bed, open top (p = 0).  Water droplet D = 2.5 mm at T_d = 100 C resting
on the bed surface at t = 0 (moving, blowing, grain-droplet force F_p:
constant/dropletProperties, src/dropletCoupling/README.md).  Cohesion
F_c^0 = 7.5e-4 N/m per unit depth where psi < psi^0 = 0.9 (eq. 4.18; Table
4.2's 7.5e-4 is the thesis' 2D value per unit depth: `COHESION_NOTE`).
Porous grains (thesis 4.3.2, couplingProperties grainPorosity):
porosity="auto" gives n = 1 - 0.4/phi_2D (bed solid fraction 0.4) and grain
density (1 - n) rho_s.  Mesh: uniform, D/8 = 0.3125 mm cells (README.md).
case.json keeps what postProcess.py needs (properties, bed, mesh).
Similarity scaling (off by default; Allrun env SIMILARITY=<d_ref>, setup(...,
similarity=d_ref)): gas and liquid viscosity x (d/d_ref)^2, cohesion x d/d_ref,
d the bed's mean grain diameter (`similarity_factors`, docs/validation/dropletDigging.md "Measured,
similarity-scaled 0.2 mm bed").
"""

import math
import os
import sys

import nscdpost
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))

# Table 4.2
RHO, MU, CP, KAPPA, BETA = 1.204, 2e-5, 1040.0, 0.026, 3e-3
NU = MU / RHO
D_V, RHO_V = 2e-5, 1.204
RHO_P, C_P, K_P, FRICTION = 3200.0, 290.0, 234.0, 0.3
E_P, NU_P = 1e11, 0.35  # contact conduction, eq. 4.2-4.3
W, H, H_P, GAP, D_DROP = 10e-3, 30e-3, 22.5e-3, 1.5e-3, 2.5e-3
D_GRAIN_TABLE = 55e-6
DT = 5e-4
F_C0, PSI0 = 7.5e-4, 0.9
COHESION_NOTE = """Table 4.2's F_c^0 = 7.5e-4 is a 2D force per unit depth
[N/m], as every 2D quantity of the thesis' grain code (MigFlow: disc volume
pi r^2, scontact.py): it is 10.0 times the weight per unit depth of a 55 um disc
of 3200 kg/m^3 (rho_s g pi d^2/4 = 7.46e-5 N/m), a granular Bond number of 10.
Read as a force on a grain of length l = 1.5 mm (7.5e-4/l = 0.5 N/m) it would
be 6,700 grain weights, 74 times the largest capillary force between two 55 um
spheres (2 pi R sigma = 1.0e-5 N), which no wet contact can carry."""
# water (not in Table 4.2)
RHO_L, LATENT, T_D = 958.0, 2.257e6, 373.15
DEPTH = GAP  # 2D mesh depth = the Hele-Shaw gap
# uniform cells, D/8 (env CELLS_PER_DROPLET: D/n, the mesh-refinement study)
CELL = D_DROP / int(os.environ.get("CELLS_PER_DROPLET", "8"))
D_GRAIN_REDUCED = 1e-3
PHI_BED = 0.4  # solid fraction of the real bed (thesis 4.3.2)
MU_L = 2.82e-4  # liquid (water, 100 C) viscosity [Pa s]: dropletProperties default
# the environment switches (contact solver, cohesion, droplet options), a
# sibling module loaded by path like postProcess.py's figures
settings = nscdpost.load_module("dropletDigging_runSettings", os.path.join(here, "runSettings.py"))
SIGMA_WATER = settings.SIGMA_WATER
contact_tolerance = settings.contact_tolerance
contact_max_iterations = settings.contact_max_iterations
contact_compliance = settings.contact_compliance
contact_compliance_absolute = settings.contact_compliance_absolute
cohesion_settings = settings.cohesion_settings
surface_tension = settings.surface_tension
vapour_release = settings.vapour_release
absorbed_grains = settings.absorbed_grains
liquid_conductivity = settings.liquid_conductivity
yes_no = settings.yes_no
film_conduction = settings.film_conduction
droplet_offset = settings.droplet_offset


def similarity_factors(d_grain, d_ref, permeability_ratio=1.0):
    """A-priori similarity scaling of a bed of grains d_grain [m] to the
    reference grain d_ref [m] (Table 4.2: 55e-6), docs/validation/dropletDigging.md
    "similarity-scaled 0.2 mm bed".  With s = (d_grain/d_ref)^2 x permeability_ratio:
      - gas dynamic viscosity eta_g x s (transportProperties nu x s, rho kept),
      - liquid viscosity mu_l x s (dropletProperties liquidViscosity),
      - cohesion F_c^0 x d_grain/d_ref,
    which keeps the reference bed's U_mf (Darcy regime: ~ k/eta_g, k ~ d^2),
    the liquid's Darcy seepage speed (~ k/mu_l), the grains' Stokes time
    rho_s d^2/(18 eta_g) and the 2D bed tensile strength ~ F_c/d.
    permeability_ratio: U_mf measured in vansFoam on this bed (umf.py) over
    Ergun's U_mf at the same gas, i.e. how much more permeable the 2D
    porous-disc bed is than Ergun's packing of spheres (1: Ergun's U_mf;
    measured 1.75 on the 0.2 mm bed); with it the
    scaled bed's measured U_mf is the reference bed's Ergun U_mf.  Not kept:
    the droplet's gas Reynolds number (/ s), the gas Prandtl number (x s), the
    grain-gas thermal relaxation time (~ d^2/k_f), the grain Bond number and D/d.
    Returns dict s (viscosity factor) and c (cohesion factor); raises
    ValueError if d_ref <= 0 or permeability_ratio <= 0."""
    if not d_ref > 0:
        raise ValueError(f"similarity_factors: reference grain diameter {d_ref} must be > 0")
    if not permeability_ratio > 0:
        raise ValueError(
            f"similarity_factors: permeability ratio {permeability_ratio} must be > 0"
            " (U_mf measured / U_mf Ergun, umf.py)"
        )
    r = d_grain / d_ref
    return {"s": r * r * permeability_ratio, "c": r}


def header(cls, obj):
    return f"FoamFile {{ version 2.0; format ascii; class {cls}; object {obj}; }}\n"


def write(case, rel, cls, body):
    path = os.path.join(case, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(header(cls, os.path.basename(rel)) + body)


def mesh_and_grains(case, d_grain, rho_grain=RHO_P, inlet=False):
    """blockMeshDict, grainProperties and g of the cell.  inlet: the floor
    is its own patch `inlet` (the fluidisation column of umf.py; a grain wall:
    a porous floor) instead of a part of `walls`, and a grain reaching the
    outlet leaves the case (`outletPatches`)."""
    nx, ny = int(round(W / CELL)), int(round(H / CELL))
    floor = "" if inlet else "(1 5 4 0) "
    write(
        case,
        "system/blockMeshDict",
        "dictionary",
        "scale 1;\nvertices ((0 0 0) (%g 0 0) (%g %g 0) (0 %g 0) (0 0 %g) (%g 0 %g) (%g %g %g) (0 %g %g));\n"
        % (W, W, H, H, DEPTH, W, DEPTH, W, H, DEPTH, H, DEPTH)
        + f"blocks (hex (0 1 2 3 4 5 6 7) ({nx} {ny} 1) simpleGrading (1 1 1));\n"
        + f"boundary (\n walls {{ type wall; faces ({floor}(0 4 7 3) (2 6 5 1)); }}\n"
        + (" inlet { type patch; faces ((1 5 4 0)); }\n" if inlet else "")
        + " outlet { type patch; faces ((3 7 6 2)); }\n"
        " frontAndBack { type empty; faces ((0 3 2 1) (4 5 6 7)); }\n);\n",
    )
    beta, omega = contact_compliance()
    c_abs = contact_compliance_absolute()
    compliance = f" relativeCompliance {beta:g};" if beta > 0 else ""
    compliance += f" compliance {c_abs:g};" if c_abs > 0 else ""
    relaxation = f" relaxation {omega:g};" if omega != 1 else ""
    write(
        case,
        "constant/grainProperties",
        "dictionary",
        f"materials {{ grains {{ density {rho_grain:.9g}; friction {FRICTION}; conductivity {K_P};"
        f" youngModulus {E_P:g}; poissonRatio {NU_P}; heatCapacity {C_P};{compliance} }} }}\n"
        + f"wallPatches (walls{' inlet' if inlet else ''});\n"
        + ("outletPatches (outlet);\n" if inlet else "")
        + f"contactSolver {{ tolerance {contact_tolerance(d_grain):g};"
        f" maxIterations {contact_max_iterations()};"
        f" overlapTolerance 1e-2;{relaxation} }}\n"
        f"// grain diameter of this bed: {d_grain:g} m (Table 4.2: {D_GRAIN_TABLE:g} m)\n",
    )
    write(
        case,
        "constant/g",
        "uniformDimensionedVectorField",
        "dimensions [0 1 -2 0 0 0 0];\nvalue (0 -9.81 0);\n",
    )


def deposit_system(case):
    """controlDict, fvSchemes and fvSolution of a grainDeposit case."""
    write(
        case,
        "system/controlDict",
        "dictionary",
        "application grainDeposit; startFrom latestTime; startTime 0; stopAt endTime;\n"
        "endTime 1; deltaT 1e-4; writeControl timeStep; writeInterval 1; writeFormat ascii;\n"
        "writePrecision 12; timeFormat general; timePrecision 6; runTimeModifiable false;\n",
    )
    write(
        case,
        "system/fvSchemes",
        "dictionary",
        "ddtSchemes { default Euler; } gradSchemes { default Gauss linear; }\n"
        "divSchemes { default none; } laplacianSchemes { default Gauss linear corrected; }\n"
        "interpolationSchemes { default linear; } snGradSchemes { default corrected; }\n",
    )
    write(case, "system/fvSolution", "dictionary", "solvers {}\n")


def deposit(d_grain=D_GRAIN_REDUCED, root=here):
    case = os.path.join(root, "deposit")
    mesh_and_grains(case, d_grain)
    # ~ the number that fills w x h_p (1 mm grains: 234, bed top 20.8 mm;
    # more do not fit the loose insertion lattice of the 30 mm cell)
    n = int(0.82 * W * H_P / (np.pi / 4 * d_grain**2))
    deposit_system(case)
    write(
        case,
        "system/grainDepositDict",
        "dictionary",
        "material grains;\nmethod box;\n"
        f"box {{ min (0 0 0); max ({W:.9g} {H:.9g} 1); }}\n"
        f"number {n};\ndMin {0.9 * d_grain:.9g};\nsizeRatio {1 / 0.9:.6g};\nseed 8;\n"
        "settle { maxTime 1; deltaT 2e-4; speedTolerance 2e-3; }\n",
    )
    print(f"{case}: {n} grains of {d_grain:g} m to settle")


def tiled_deposit(d_grain, root=here, source=None):
    """A bed of grains of diameter d_grain built from a settled coarser bed
    (source: a deposit directory, default bed_1e-3/deposit, else
    reduced/deposit) scaled down by k = d_source/d_grain (an integer) and
    tiled k x k (columns mirrored alternately so that the flat wall faces of
    the source meet), instead of pouring ~k^2 more grains from the insertion
    lattice (measured 0.4 s per settling step for 5872 grains of 0.2 mm:
    ~30 min).  Each tile is compressed by 1 % in x about its centre and the
    diameters by 2 % (no initial overlaps, with the source's walls or
    between tiles; tiles stacked at their highest grain), then the bed
    settles (grainDeposit settle) into the same kind of random packing
    (phi_2D ~ 0.8).  Writes root/deposit (run blockMesh and grainDeposit
    there).  Raises ValueError if d_source/d_grain is not an integer."""
    if source is None:
        source = os.path.join(here, "bed_1e-3", "deposit")
        if not os.path.isfile(os.path.join(source, "0", "grainState.h5")):
            source = os.path.join(here, "reduced", "deposit")
    g = nscdpost.read_grains(source, "0")
    d_src = float(np.max(g["d"]))  # nominal: dMin = 0.9 d, sizeRatio 1/0.9
    k = int(round(d_src / d_grain))
    if k < 1 or abs(k * d_grain / d_src - 1) > 0.05:
        raise ValueError(
            f"tiled_deposit: source grain {d_src:g} m is not an integer multiple of {d_grain:g} m"
        )
    s = 1.0 / k
    x = g["x"][:, 0] * s
    y = g["x"][:, 1] * s
    d = g["d"] * s * 0.98
    wt = W / k
    x = wt / 2 + (x - wt / 2) * 0.99
    tile_top = float(np.max(y + d / 2))
    grains = []
    for j in range(k):
        for i in range(k):
            xi = x if i % 2 == 0 else wt - x
            for a, b, c in zip(xi + i * wt, y + j * (tile_top + 1e-3 * d_grain), d):
                grains.append((a, b, DEPTH / 2, c))
    case = os.path.join(root, "deposit")
    mesh_and_grains(case, d_grain)
    deposit_system(case)
    write(
        case,
        "system/grainDepositDict",
        "dictionary",
        "material grains;\nmethod list;\ngrains (\n"
        + "\n".join("(%.12g %.12g %.12g %.12g)" % gr for gr in grains)
        + "\n);\n"
        "settle { maxTime 0.12; deltaT 2e-4; speedTolerance 2e-3; }\n",
    )
    print(f"{case}: {len(grains)} grains of {d_grain:g} m ({k} x {k} tiles of {source})")


def rain_deposit(d_grain, root=here):
    """A bed of grains of diameter d_grain [m] laid as the thesis builds its
    bed, by a geometric packing (thesis 4.3.2: "a space-filling algorithm
    ... to minimise voids"): grainDeposit `method rain` lays the
    0.82 W H_P/(pi d^2/4) discs of dMin 0.9 d_grain to d_grain one by one,
    each rolled to rest on two below it (Visscher & Bolsterli 1972; solid
    fraction ~0.85), then settles them 0.12 s (deltaT 2e-4 s).  For a deep
    bed give the contacts a compliance first (env CONTACT_COMPLIANCE=2e-3
    CONTACT_RELAXATION=1.5: 7 CPU minutes for the 77,657 discs of 55 um,
    docs/validation/contactCompliance.md "Settling the thesis droplet
    bed"); the settled contact impulses are then written with the bed.
    Writes root/deposit (run blockMesh and grainDeposit there)."""
    case = os.path.join(root, "deposit")
    mesh_and_grains(case, d_grain)
    deposit_system(case)
    n = int(0.82 * W * H_P / (np.pi / 4 * d_grain**2))
    write(
        case,
        "system/grainDepositDict",
        "dictionary",
        "material grains;\nmethod rain;\n"
        f"box {{ min (0 0 0); max ({W:.9g} {H:.9g} 1); }}\n"
        f"number {n};\ndMin {0.9 * d_grain:.9g};\nsizeRatio {1 / 0.9:.6g};\nseed 8;\n"
        "settle { maxTime 0.12; deltaT 2e-4; speedTolerance 2e-3; }\n",
    )
    print(f"{case}: {n} grains of {d_grain:g} m to lay (method rain) and settle")


def bed_top(dep):
    g = nscdpost.read_grains(dep, "0")
    return float(np.percentile(g["x"][:, 1] + 0.5 * g["d"], 98))


def resting_height(g, x_c, radius):
    """Lowest centre height [m] of a droplet of radius [m] at abscissa x_c
    [m] that overlaps none of the grains g (nscdpost.read_grains): the
    droplet lowered onto the bed surface until it touches a grain.  With
    the capillary barrier a grain that starts inside the droplet's surface
    is pushed out with up to 2 sigma and kicks the droplet up (measured on
    the 0.2 mm bed: 19 grains, 0.2 m/s upward in 2 ms)."""
    x, y, r = g["x"][:, 0], g["x"][:, 1], 0.5 * g["d"]
    dx = np.abs(x - x_c)
    near = dx < radius + r
    if not np.any(near):
        return float(radius)
    return float(np.max(y[near] + np.sqrt((radius + r[near]) ** 2 - dx[near] ** 2)))


def packing_2d(g, top):
    """Area fraction of the discs in the bed 0 < y < top, w wide."""
    return float(np.sum(np.pi / 4 * g["d"] ** 2) / (W * top))


def zehner_schlunder(k_s, k_f, eps):
    """Effective conductivity [W/(m K)] of a packed bed of spheres in a
    stagnant gas, Zehner and Schluender (Chem. Ing. Tech. 42 (1970) 933;
    VDI Heat Atlas D6.3, without radiation, flattening or Knudsen terms):
        k/k_f = 1 - sqrt(1 - eps) + 2 sqrt(1 - eps)/(1 - kap B)
                * [(1 - kap) B/(1 - kap B)^2 ln(1/(kap B))
                   - (B + 1)/2 - (B - 1)/(1 - kap B)],
        kap = k_f/k_s, B = 1.25 ((1 - eps)/eps)^(10/9).
    k_s, k_f [W/(m K)] > 0, eps the void fraction in (0, 1).  Raises
    ValueError otherwise."""
    if not (k_s > 0 and k_f > 0 and 0 < eps < 1):
        raise ValueError(
            f"zehner_schlunder: need k_s, k_f > 0 and 0 < eps < 1, got {k_s}, {k_f}, {eps}"
        )
    kap, B = k_f / k_s, 1.25 * ((1 - eps) / eps) ** (10 / 9)
    a = 1 - kap * B
    r = math.sqrt(1 - eps)
    return k_f * (
        1
        - r
        + 2 * r / a * ((1 - kap) * B / a**2 * math.log(1 / (kap * B)) - (B + 1) / 2 - (B - 1) / a)
    )


def front_rear_walls(value=None):
    """Relaxation time tau [s] of the grains to the front and rear walls of
    the Hele-Shaw cell (grainProperties frontRearWalls, src/grainCloud), or
    None (off, the default).  value: True/False if given, else env
    FRONT_REAR_WALLS ("yes"/"no").  The walls (sapphire and aluminium, at
    T_bed, "thermal reservoirs", thesis section 4.3.2) are within l/2 = 0.75
    mm of every grain; a bed slab between them with a uniform sink relaxes
    as (12 k_eff/l^2)(T_w - T) per unit volume (mean deficit q l^2/(12 k)),
        tau = (rho c)_bed l^2/(12 k_eff),
    (rho c)_bed = 0.4 rho_s c_s (Table 4.2 bed, solid fraction 0.4),
    k_eff = zehner_schlunder(k_s, k_f, 0.6) (Table 4.2: 234 and 0.026
    W/(m K)): 0.23 W/(m K), tau = 0.30 s.  Only the grains: the gas holds
    0.3 % of the bed's heat capacity.  Raises ValueError for another word."""
    if not yes_no(value, "FRONT_REAR_WALLS"):
        return None
    k_eff = zehner_schlunder(K_P, KAPPA, 1 - PHI_BED)
    return PHI_BED * RHO_P * C_P * GAP**2 / (12 * k_eff)


def setup(
    case,
    t_bed_c,
    end_time=0.5,
    root=here,
    porosity=None,
    write_interval=None,
    similarity=None,
    deposit_root=None,
    sigma=None,
    release=None,
    film=None,
    permeability_ratio=1.0,
    u_mf=None,
    walls=None,
):
    """Case CASE at bed temperature t_bed_c [C] with the bed of root/deposit.
    porosity: None (solid discs; the gas sees the discs of radius 0.88 r,
    section 3.2.3) or the grain porosity n of the porous-grain correction
    (thesis 4.3.2: the gas sees (1 - n) of each disc, density (1 - n) rho_s;
    "auto": n = 1 - 0.4/phi_2D so that the bed's solid fraction is 0.4).
    Needs couplingProperties grainPorosity (engineer F, src/vansCoupling).
    similarity: None (default, Table 4.2 gas, liquid and cohesion) or the
    reference grain diameter d_ref [m] (e.g. 55e-6) of the similarity scaling
    `similarity_factors(d, d_ref)`, d = the bed's MEAN grain diameter (0.186 mm
    for the 0.2 mm bed).  deposit_root: directory holding deposit/ (default
    root), so that a scaled bed reuses the unscaled bed's deposit.  sigma:
    surface tension of the capillary barrier (`surface_tension(sigma)`).
    release: where the vapour leaves the droplet (`vapour_release(release)`).
    film: Leidenfrost film conduction (`film_conduction(film)`; needs sigma > 0).
    walls: the front and rear walls at T_bed as a heat bath of the grains
    (`front_rear_walls(walls)`).  permeability_ratio: the similarity
    scaling's correction (`similarity_factors`).  u_mf: U_mf [m/s] of this
    bed and gas measured by umf.py (case.json `U_mf_measured`; postProcess
    divides by it instead of Ergun's value)."""
    dep = os.path.join(deposit_root or root, "deposit")
    g = nscdpost.read_grains(dep, "0")
    d_grain = float(np.mean(g["d"]))
    sim = (
        similarity_factors(d_grain, similarity, permeability_ratio)
        if similarity
        else {"s": 1.0, "c": 1.0}
    )
    min_age, c_factor = cohesion_settings()
    nu, mu_l, f_c0 = NU * sim["s"], MU_L * sim["s"], F_C0 * sim["c"] * c_factor
    phi2d = packing_2d(g, bed_top(dep))
    if porosity == "auto":
        porosity = 1 - PHI_BED / phi2d
    rho_grain = RHO_P * (1 - (porosity or 0.0))
    mesh_and_grains(case, d_grain, rho_grain)
    os.makedirs(os.path.join(case, "0"), exist_ok=True)
    nscdpost.copy_grain_state(dep, case)
    t_bed = t_bed_c + 273.15
    top = bed_top(dep)
    with open(os.path.join(case, "constant", "grainProperties"), "a") as f:
        f.write(f"initialTemperature {t_bed};\nwallTemperatures {{ walls {t_bed}; }}\n")
        if "outletPatches" not in open(os.path.join(case, "constant", "grainProperties")).read():
            # a grain the vapour blasts out of the bed to the open top leaves
            # (counted in grainOutlets.dat) instead of stopping the run
            f.write("outletPatches (outlet);\n")
        tau = front_rear_walls(walls)
        if tau:
            f.write(f"frontRearWalls {{ temperature {t_bed}; relaxationTime {tau:.6g}; }}\n")
    emp = "frontAndBack { type empty; }"
    write(
        case,
        "0/U",
        "volVectorField",
        "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
        "boundaryField { walls { type noSlip; } outlet { type pressureInletOutletVelocity;"
        f" value uniform (0 0 0); }} {emp} }}\n",
    )
    write(
        case,
        "0/p",
        "volScalarField",
        "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
        "boundaryField { walls { type fixedFluxPressure; value uniform 0; }"
        f" outlet {{ type fixedValue; value uniform 0; }} {emp} }}\n",
    )
    write(
        case,
        "0/T",
        "volScalarField",
        f"dimensions [0 0 0 1 0 0 0];\ninternalField uniform {t_bed};\n"
        f"boundaryField {{ walls {{ type fixedValue; value uniform {t_bed}; }}"
        f" outlet {{ type inletOutlet; inletValue uniform {t_bed}; value uniform {t_bed}; }} {emp} }}\n",
    )
    write(
        case,
        "0/psi",
        "volScalarField",
        "dimensions [0 0 0 0 0 0 0];\ninternalField uniform 0;\n"
        "boundaryField { walls { type fixedValue; value uniform 0; }"
        f" outlet {{ type inletOutlet; inletValue uniform 0; value uniform 0; }} {emp} }}\n",
    )
    write(
        case,
        "constant/transportProperties",
        "dictionary",
        f"rho {RHO};\nnu {nu:.10g};\nCp {CP};\nkappa {KAPPA};\nbeta {BETA};\nTRef {t_bed};\n"
        f"vapour {{ D {D_V}; rho {RHO_V}; bounded yes; }}\n",
    )
    write(
        case,
        "constant/couplingProperties",
        "dictionary",
        "dragModel DallavalleDiFelice;\ntwoDimensionalDrag perUnitDepth;\nforceModel A;\n"
        "voidFraction { method overlap; epsMin 1e-8; effectiveDiameterFactor "
        + ("0.88; }\n" if porosity is None else f"1; }}\ngrainPorosity {porosity:.6g};\n")
        + "heatTransferModel DiFeliceColburn;\nDiFeliceColburnCoeffs { delta 500; alpha 0.4; }\n"
        f"cohesion {{ force {f_c0:.9g}; vapourThreshold {PSI0}; minAge {min_age}; }}\n",
    )  # N/m: COHESION_NOTE
    sig = surface_tension(sigma)
    release = vapour_release(release)
    film = film_conduction(film)
    absorbed = absorbed_grains()
    k_l = liquid_conductivity()
    if film and not sig > 0:
        raise ValueError(
            "FILM_CONDUCTION=yes needs the capillary barrier: set "
            "SURFACE_TENSION=water (or a value > 0)"
        )
    # with the barrier the droplet starts resting on the bed (no grain inside
    # its surface); without it at the bed top (98th percentile, as measured
    # in README.md)
    x_drop = W / 2 + droplet_offset()
    if not D_DROP / 2 < x_drop < W - D_DROP / 2:
        raise ValueError(
            f"DROPLET_X_OFFSET={x_drop - W / 2:g} m puts the droplet through a side wall:"
            f" keep |offset| < {W / 2 - D_DROP / 2:g} m"
        )
    y_drop = resting_height(g, x_drop, D_DROP / 2) if sig > 0 else top + D_DROP / 2
    write(
        case,
        "constant/dropletProperties",
        "dictionary",
        f"centre ({x_drop:.9g} {y_drop:.9g} {DEPTH / 2:.9g});\ndiameter {D_DROP};\n"
        f"velocity (0 0 0);\nliquidDensity {RHO_L};\nlatentHeat {LATENT};\n"
        f"vapourisationTemperature {T_D};\nvapourDensity {RHO_V};\nmoving yes;\nblowing yes;\n"
        f"liquidViscosity {mu_l:.9g};\nsurfaceTension {sig:.9g};\nvapourRelease {release};\n"
        f"filmConduction {'yes' if film else 'no'};\nabsorbedGrains {absorbed};\n"
        + (f"liquidConductivity {k_l:.9g};\n" if k_l else ""),
    )
    write(
        case,
        "system/fvOptions",
        "dictionary",
        "droplet { type vapourDropletSource; }\n"
        f"heleShaw {{ type heleShawFriction; selectionMode all; gap {GAP}; fields (U); }}\n",
    )
    write(
        case,
        "system/controlDict",
        "dictionary",
        "application vansFoam; startFrom latestTime; startTime 0; stopAt endTime;\n"
        f"endTime {end_time}; deltaT {DT}; adjustTimeStep yes; maxCo 0.5; maxDeltaT {DT};\n"
        f"writeControl adjustableRunTime; writeInterval {write_interval or end_time / 10:g};"
        " writeFormat ascii;\n"
        "writePrecision 12; timeFormat general; timePrecision 6; runTimeModifiable false;\n"
        'libs ("libdropletCoupling.so");\n',
    )
    write(
        case,
        "system/fvSchemes",
        "dictionary",
        "ddtSchemes { default Euler; }\ngradSchemes { default Gauss linear; }\n"
        "divSchemes { default none; div(phi,U) Gauss limitedLinearV 1; div(phi,T) Gauss limitedLinear 1;"
        " div(phi,psi) Gauss limitedLinear01 1; }\n"
        "laplacianSchemes { default Gauss linear corrected; }\n"
        "interpolationSchemes { default linear; }\nsnGradSchemes { default corrected; }\n",
    )
    write(
        case,
        "system/fvSolution",
        "dictionary",
        "solvers {\n  p { solver GAMG; smoother DIC; tolerance 1e-9; relTol 0.01; }\n"
        "  pFinal { $p; relTol 0; }\n"
        '  "(U|UFinal)" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-9; relTol 0; }\n'
        '  "(T|psi)" { solver PBiCGStab; preconditioner DILU; tolerance 1e-12; relTol 0; }\n}\n'
        "PIMPLE { momentumPredictor yes; nOuterCorrectors 1; nCorrectors 2;"
        " nNonOrthogonalCorrectors 0; }\n",
    )
    nscdpost.write_json(
        os.path.join(case, "case.json"),
        {
            "bed_temperature_C": t_bed_c,
            "bed_top": top,
            "grain_diameter": d_grain,
            "grains": int(len(g["d"])),
            "droplet_diameter": D_DROP,
            "width": W,
            "height": H,
            "depth_l": DEPTH,
            "cells": [int(round(W / CELL)), int(round(H / CELL))],
            "rho": RHO,
            "Cp": CP,
            "mu": nu * RHO,
            "liquid_viscosity": mu_l,
            "cohesion_force": f_c0,
            "cohesion_min_age": min_age,
            "cohesion_factor": c_factor,
            "similarity_reference_diameter": similarity,
            "surface_tension": sig,
            "vapour_release": release,
            "absorbed_grains": absorbed,
            "liquid_conductivity": k_l,
            "film_conduction": film,
            "front_rear_walls_tau": tau,
            "similarity_s": sim["s"],
            "permeability_ratio": permeability_ratio if similarity else None,
            "U_mf_measured": u_mf,
            "T_d": T_D,
            "latent_heat": LATENT,
            "grain_density": RHO_P,
            "packing_2d": phi2d,
            "grain_porosity": porosity,
            "bed_weight_fraction": phi2d * (1 - (porosity or 0.0)),
        },
    )
    print(
        f"{case}: T_bed = {t_bed_c:g} C, {len(g['d'])} grains of {d_grain:g} m, bed top "
        f"{top * 1e3:.3f} mm, endTime {end_time} s"
    )


if __name__ == "__main__":
    if sys.argv[1] == "deposit":
        deposit(float(sys.argv[2]) if len(sys.argv) > 2 else D_GRAIN_REDUCED)
    else:
        por = sys.argv[4] if len(sys.argv) > 4 else "none"
        setup(
            sys.argv[1],
            float(sys.argv[2]),
            *(float(a) for a in sys.argv[3:4]),
            porosity=None if por == "none" else ("auto" if por == "auto" else float(por)),
        )
