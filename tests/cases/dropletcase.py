# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared set-up of the immersed vaporising droplet tests (issue 8;
src/dropletCoupling, fvOption vapourDropletSource in vansFoam), split by
concern into test_droplet_heat.py, test_droplet_motion.py,
test_droplet_grains.py, test_droplet_restart.py and test_droplet_errors.py:
the 2D droplet case, its constants and the drag law written out."""

import math
import os

import correlations
import nscdpost
import numpy as np
from foamcase import add_fluid, add_scalar_transport, make_box_case, replace_in, run, write

D = 2.5e-3
W = 4 * D
DEPTH = 1e-4
RHO, NU, CP, KAPPA = 1.0, 2e-5, 1000.0, 0.05
T_W, T_D = 773.15, 373.15
LATENT = 2.26e6
RHO_V = 0.6


def droplet_case(
    case,
    env,
    n_per_d,
    end_time,
    dt,
    blowing,
    rho_l,
    outlet=False,
    extra="",
    w_over_d=4,
    gravity=0.0,
    nu=NU,
    T_w=None,
    grains=(),
    T_grains=None,
    fixed_grains=True,
    write_interval=None,
    coupling="",
    rho_f=RHO,
    moving=False,
    centre=None,
):
    """2D square box w x w (w = w_over_d D, n_per_d * w_over_d cells a side),
    walls at T_w (default T_W), droplet of diameter D at the centre; with
    outlet the top side is an open patch (p = 0, zeroGradient U, inletOutlet
    T and psi)."""
    w = w_over_d * D
    n = w_over_d * n_per_d
    T_w = T_W if T_w is None else T_w
    make_box_case(
        case,
        (0, 0, 0),
        (w, w, DEPTH),
        (n, n, 1),
        (0, -gravity, 0),
        {"glass": {"density": 2500, "friction": 0.4}},
        grains=list(grains),
        end_time=end_time,
        dt=dt,
        write_interval=end_time if write_interval is None else write_interval,
    )
    if grains and fixed_grains:
        open(os.path.join(case, "system", "grainDepositDict"), "a").write("fixed yes;\n")
    if grains:
        gp = os.path.join(case, "constant", "grainProperties")
        replace_in(
            gp,
            (
                "glass { density 2500; friction 0.4; }",
                "glass { density 2500; friction 0.4; conductivity 1; heatCapacity 800; }",
            ),
        )
        open(gp, "a").write(f"initialTemperature {T_w if T_grains is None else T_grains};\n")
    add_fluid(case, rho_f, nu, max_co=0.5, max_dt=dt)
    tp = os.path.join(case, "constant", "transportProperties")
    open(tp, "a").write(f"Cp {CP};\nkappa {KAPPA};\nvapour {{ D 2.5e-5; rho {RHO_V}; }}\n")
    cp = os.path.join(case, "constant", "couplingProperties")
    open(cp, "a").write(
        "heatTransferModel DiFeliceColburn;\n"
        "DiFeliceColburnCoeffs { delta 500; alpha 0.4; }\n" + coupling
    )
    emp = "frontAndBack { type empty; }"
    if outlet:
        bm = os.path.join(case, "system", "blockMeshDict")
        txt = open(bm).read()
        txt = txt.replace(
            "walls { type wall; faces ((1 5 4 0) (0 4 7 3) (2 6 5 1) (3 7 6 2)); }",
            "walls { type wall; faces ((1 5 4 0) (0 4 7 3) (2 6 5 1)); }\n"
            "outlet { type patch; faces ((3 7 6 2)); }",
        )
        open(bm, "w").write(txt)
        write(
            os.path.join(case, "0", "U"),
            "volVectorField",
            "U",
            "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
            f"boundaryField {{ walls {{ type noSlip; }} outlet {{ type pressureInletOutletVelocity;"
            f" value uniform (0 0 0); }} {emp} }}\n",
        )
        write(
            os.path.join(case, "0", "p"),
            "volScalarField",
            "p",
            "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
            f"boundaryField {{ walls {{ type fixedFluxPressure; value uniform 0; }}"
            f" outlet {{ type fixedValue; value uniform 0; }} {emp} }}\n",
        )
        fs = os.path.join(case, "system", "fvSolution")
        txt = open(fs).read().replace("pRefCell 0; pRefValue 0;", "")
        open(fs, "w").write(txt)
        out_T = f"outlet {{ type inletOutlet; inletValue uniform {T_w}; value uniform {T_w}; }}"
        out_psi = "outlet { type inletOutlet; inletValue uniform 0; value uniform 0; }"
    else:
        out_T = out_psi = ""
    write(
        os.path.join(case, "0", "T"),
        "volScalarField",
        "T",
        f"dimensions [0 0 0 1 0 0 0];\ninternalField uniform {T_w};\n"
        f"boundaryField {{ walls {{ type fixedValue; value uniform {T_w}; }} {out_T} {emp} }}\n",
    )
    write(
        os.path.join(case, "0", "psi"),
        "volScalarField",
        "psi",
        "dimensions [0 0 0 0 0 0 0];\ninternalField uniform 0;\n"
        f"boundaryField {{ walls {{ type zeroGradient; }} {out_psi} {emp} }}\n",
    )
    add_scalar_transport(case, "T", "Gauss upwind")
    add_scalar_transport(case, "psi", "Gauss upwind")
    fs = os.path.join(case, "system", "fvSolution")
    txt = open(fs).read().replace("tolerance 1e-9; relTol 0.01;", "tolerance 1e-12; relTol 0;")
    open(fs, "w").write(txt)
    cd = os.path.join(case, "system", "controlDict")
    open(cd, "a").write('libs ("libdropletCoupling.so");\n')
    write(
        os.path.join(case, "system", "fvOptions"),
        "dictionary",
        "fvOptions",
        "droplet { type vapourDropletSource; }\n",
    )
    cx, cy = (w / 2, w / 2) if centre is None else centre
    write(
        os.path.join(case, "constant", "dropletProperties"),
        "dictionary",
        "dropletProperties",
        f"centre ({cx} {cy} {DEPTH / 2});\ndiameter {D};\nliquidDensity {rho_l};\n"
        f"latentHeat {LATENT};\nvapourisationTemperature {T_D};\nvapourDensity {RHO_V};\n"
        f"blowing {'yes' if blowing else 'no'};\nmoving {'yes' if moving else 'no'};\n" + extra,
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)


read_droplet = nscdpost.read_droplet
RHO_W, MU_W = 958.0, 2.82e-4  # water at 100 C: Incropera & DeWitt Table A.6
# (1/v_f = 958 kg/m^3), IAPWS 2008 (281.8e-6 Pa s)


def difelice_gamma(eps, Re, d, mu, two_d=True):
    """DallavalleDiFelice drag [kg/(m^3 s)] of src/vansCoupling/dragModels
    (Di Felice 1994, correlations.gamma_dallavalle_difelice), per unit disc
    area with the default 2D convention perUnitDepth (8/(3 pi) x the sphere's
    per unit volume) when two_d, per unit sphere volume otherwise."""
    g = correlations.gamma_dallavalle_difelice(eps, Re, d, mu)
    return g * correlations.DISC_PER_UNIT_DEPTH if two_d else g


def water_droplet_case(case, env, dt, n, grains, fixed_grains=False, rho_l=RHO_W, **kw):
    """droplet_case of a liquid droplet (rho_l, default water) at the walls'
    temperature (T_w = T_D), no blowing, 8 cells per D, with grains (free
    unless fixed_grains), n steps of dt; kw: droplet_case's other keywords."""
    kw.update(blowing=False, rho_l=rho_l, T_w=T_D, grains=grains, fixed_grains=fixed_grains)
    droplet_case(case, env, 8, end_time=dt * n, dt=dt, **kw)


def blowing_droplet_case(case, env, n_per_d, dt, n, rho_l=1000.0, **kw):
    """droplet_case of an evaporating (blowing) droplet in the box with the
    open top (outlet), n steps of dt; kw: droplet_case's other keywords."""
    kw.update(blowing=True, rho_l=rho_l, outlet=True)
    droplet_case(case, env, n_per_d, end_time=dt * n, dt=dt, **kw)


def held_suspension_case(case, env, r_frac, n, write_every, nu_gas, dg=5e-5):
    """A HELD droplet (D, water, gravity on, no heat) of diameter D at
    (2D, 2D) whose inner disc r < r_frac R is filled with a square lattice of
    free grains of diameter dg (spacing 1.02 dg, phi_2D = 0.755, no
    contacts), gas viscosity nu_gas; n steps of dt = 5e-4 s, written every
    write_every steps.  Returns (grains, dt)."""
    R0, c, a = D / 2, 2 * D, 1.02 * dg
    k = int(r_frac * R0 / a)
    grains = [
        (c + i * a, c + j * a, DEPTH / 2, dg)
        for j in range(-k, k + 1)
        for i in range(-k, k + 1)
        if math.hypot(i * a, j * a) < r_frac * R0
    ]
    dt = 5e-4
    water_droplet_case(
        case,
        env,
        dt,
        n,
        grains=grains,
        write_interval=dt * write_every,
        gravity=9.81,
        nu=nu_gas,
        extra=f"liquidViscosity {MU_W};\n",
    )
    return grains, dt


def replicated_copy(case, par):
    """Copy case to par for a parallel run with every grain on every rank
    (grainDecomposition replicated, an option: the droplet's sums over the
    ranks rather than over a grain's copies; decomposed grains:
    test_droplet_decomposed.py)."""
    import shutil

    shutil.copytree(case, par)
    with open(os.path.join(par, "constant", "grainProperties"), "a") as f:
        f.write("grainDecomposition replicated;\n")


def rerun_from(case, half, mid, last, env, edit=None, check=True):
    """Copy case to half without its last write (time name last) and its
    postProcessing, apply edit(half) if given, run vansFoam again from mid
    (startFrom latestTime); returns (the droplet.dat of the restarted run,
    None), or (None, the process) when check is False."""
    import shutil

    shutil.copytree(case, half)
    shutil.rmtree(os.path.join(half, last))
    shutil.rmtree(os.path.join(half, "postProcessing"))
    if edit:
        edit(half)
    p = run("vansFoam", half, env, check=check)
    if not check:
        return None, p
    path = os.path.join(half, "postProcessing", "droplet", mid, "droplet.dat")
    return np.loadtxt(path, ndmin=2), None
