# SPDX-License-Identifier: GPL-3.0-or-later
"""Packed-bed heat transfer measured from the air side (thesis
section 4.1.2, eq. 4.4-4.13): air at T_in flows up through a fixed bed of
hot spheres held at T_p (very large heat capacity: no keyword holds a grain
temperature fixed), the bed's Nusselt number is measured as an experiment
would (tutorials/vansFoam/packedBedHeat/README.md):
    Q = rho Cp U_s A (T_out - T_in),  dT_lm = (dT_in - dT_out)/ln(dT_in/dT_out),
    h = Q/(S dT_lm), S = sum pi d^2,  Nu = h d/k,  Re = U_s d/nu,
and compared with the closure the run selected, written here independently
(the formulas of tests/cases/test_nusselt.py).

1. Lattice bed (verification, tight): a simple cubic lattice of spheres
   (d = 0.999 s), one per cubic cell of side s, 3 x 3 columns, 6 layers, in
   a column of 3 x 10 x 3 cells with slip side walls: the void fraction is
   exactly eps = 1 - pi d^3/(6 s^3) = 0.478 in every bed cell, each grain
   lies in one cell, and the flow is one-dimensional.  With upwind
   convection of T the steady discrete solution is the 1D finite-volume
   chain of well-mixed cells written here (advection, eps k conduction with
   linearly interpolated eps on faces, exchange H_p (T - T_p), H_p = pi d k
   Nu_p, in each bed cell, fixed T_in on the inlet face, zeroGradient
   outlet).  Without conduction each bed cell divides the excess T_p - T by
   1 + n, n = H_p/(rho Cp U_s s^2), so the log-mean measure gives
   Nu ln(1 + n)/n (0.77 at Re 100: the cell-mixing error of cells as long as
   the air's thermal relaxation length, see the tutorial's README).
   Asserted (DiFeliceColburn at Re 100 and 500, Gunn at Re 30):
   - the chain with the closure evaluated at each grain's own Reynolds
     number (Ufluid, the velocity vansFoam gathered at the grain) reproduces
     the simulated outlet temperature with a Nu factor 1 +- 0.005 (measured
     0.9983, 1.000003, 1.000002): closure, S/V = 6/d, spreading and energy
     coupling are right; 0.5 % still catches a Pr exponent 0.4 <-> 1/3
     (1.4 %) and anything bigger (S/V of discs, interstitial instead of
     superficial Re, a missing voidage factor);
   - the four interior layers' grains see U_s/eps within 1 %;
   - the bed's Nu (the uniform Nu that makes the chain reproduce T_out)
     within 10 % of the closure at U_s: measured -6.7 % (DiFeliceColburn),
     -4.5 % (Gunn), because the first and last layers' grains see a slip
     velocity 28-35 % low with vansFoam's default velocity correction
     (test_bed_edge_velocity); with velocityCorrection fluxReconstruction
     every layer sees U_s/eps and the bed's Nu is the closure's within 1 %
     (measured -1.7e-7);
   - the log-mean Nu equals that Nu times ln(1 + n)/n within 2 %.

2. The tutorial's poured bed (300 spheres, W = 8 d, ~4.2 d deep, mesh 2 d x
   d/8 x 2 d, limitedLinear T), two inflow velocities (Re 100 and 500, the
   regime where the fluid-side measure is meaningful, README): the measured
   Nu within [0.85, 1.02] of the closure at the bed's core void fraction and
   U_s.  Measured when written: 0.932 (Re 100), 0.952 (Re 500).  Exactly,
   Nu_measured = Nu_closure,heat-weighted x <T_p - T_f,p>/dT_lm (README):
   the closure at the grains' own eps and Re, weighted by where the heat
   flows, is 2-3 % above the correlation (the gathered eps is 0.428 against
   the core's 0.418), and the air around the grains is warmer than the
   plug-flow picture of the log-mean measure, <T_p - T_f,p>/dT_lm = 0.91 at
   Re 100 (lateral bypass through the looser wall columns: mixed-cup NTU
   0.96 of the column mean; cell-scale void-fraction scatter and cell
   resolution: the rest; axial conduction < 0.2 %).  Lower bound 0.85: twice
   the measured deficit; upper bound 1.02: none of these effects makes the
   air around the grains colder than plug flow, so the measure cannot
   exceed the closure by more than the mapping's few per cent.  A real
   error is far outside (S/V of discs -33 %, interstitial instead of
   superficial Re +70 %, a lost voidage factor x2-3).
   Also asserted: the closure averaged over the grains at their own eps
   and Re within 3 % of the correlation at the bed values (mapping), the
   heat picked up by the air equal to the heat the grains gave (1e-4), and
   the steady state.  ~25 s.
"""

import json
import math
import os
import re

import nscdpost
import numpy as np
import pytest
from correlations import nusselt_difelice_colburn as nu_difelice_colburn
from correlations import nusselt_gunn as nu_gunn
from foamcase import (
    add_fluid,
    add_solver,
    make_box_case,
    read_internal,
    replace_in,
    run,
    tutorial_modules,
    uniform_inflow,
    write,
)

RHO, MU, CP, KAPPA = 1.204, 2e-5, 1010.0, 0.025
NU = MU / RHO
PR = CP * MU / KAPPA
T_IN, T_P = 300.0, 350.0


MODELS = {"DiFeliceColburn": nu_difelice_colburn, "Gunn": nu_gunn}


def heat_lines(case):
    """Mean grain temperature [K] per step (heatBudget.dat, nscdpost.heat_history)."""
    return nscdpost.heat_history(case)["grain_T"]


# ---------------------------------------------------------------------------
# 1. lattice bed
# ---------------------------------------------------------------------------
D = 2e-3
S = D / 0.999
NX, NY, BED0, LAYERS = 3, 10, 2, 6


def chain_outlet(Nu, eps, Us):
    """Steady 1D finite-volume chain of one column of cells (cross-section
    s^2, length s): upwind advection, eps k conduction (eps linear on faces,
    1 on the inlet face), exchange H (T - T_p) in the bed cells, H = pi d k Nu
    (Nu: a scalar or one value per bed layer), fixed T_in on the inlet face
    (distance s/2), zeroGradient outlet.  Returns the outlet (last cell)
    temperature."""
    e = np.ones(NY)
    e[BED0 : BED0 + LAYERS] = eps
    F = RHO * CP * Us * S * S  # advective conductance [W/K]
    Df = KAPPA * 0.5 * (e[1:] + e[:-1]) * S  # k eps_f A/s on internal faces
    H = np.zeros(NY)
    H[BED0 : BED0 + LAYERS] = math.pi * D * KAPPA * np.asarray(Nu)
    A = np.zeros((NY, NY))
    b = np.zeros(NY)
    for c in range(NY):
        A[c, c] += F + H[c]
        b[c] += H[c] * T_P
        if c == 0:
            A[c, c] += 2 * KAPPA * S  # inlet face: eps = 1, distance s/2
            b[c] += (F + 2 * KAPPA * S) * T_IN
        else:
            A[c, c - 1] -= F
            A[c, c] += Df[c - 1]
            A[c, c - 1] -= Df[c - 1]
        if c < NY - 1:
            A[c, c] += Df[c]
            A[c, c + 1] -= Df[c]
    return np.linalg.solve(A, b)[-1]


def lattice_case(case, model, Re, velocity_correction=None):
    """The lattice bed case; velocity_correction: PIMPLE velocityCorrection
    (None: the solver's default), with linearUpwind convection of U (a TVD
    limiter keeps a +-3 % limit cycle next to the void-fraction jump with
    fluxReconstruction, vansFoam's createVelocityCorrection.H)."""
    Us = Re * NU / D
    H = NY * S
    end = 8 * H / Us  # 8 flow-through times
    grains = [
        ((i + 0.5) * S, (j + 0.5) * S, (k + 0.5) * S, D)
        for j in range(BED0, BED0 + LAYERS)
        for i in range(NX)
        for k in range(NX)
    ]
    make_box_case(
        case,
        (0, 0, 0),
        (NX * S, H, NX * S),
        (NX, NY, NX),
        (0, 0, 0),
        {"glass": {"density": 2500, "friction": 0.1}},
        grains=grains,
        end_time=end,
        dt=0.1 * S / Us,
        write_interval=end / 4,
        two_d=False,
    )
    gp = os.path.join(case, "constant", "grainProperties")
    replace_in(
        gp,
        (
            "glass { density 2500; friction 0.1; }",
            "glass { density 2500; friction 0.1; youngModulus 6e10; poissonRatio 0.22;"
            " conductivity 1.4; heatCapacity 8.4e8; }",
        ),
    )
    open(gp, "a").write(f"initialTemperature {T_P};\n")
    open(os.path.join(case, "system", "grainDepositDict"), "a").write("fixed yes;\n")
    add_fluid(case, RHO, NU, max_co=1.0, max_dt=1.0, extra_coupling=f"heatTransferModel {model};\n")
    uniform_inflow(case, Us)
    with open(os.path.join(case, "constant", "transportProperties"), "a") as f:
        f.write(f"Cp {CP};\nkappa {KAPPA};\n")
    write(
        os.path.join(case, "0", "T"),
        "volScalarField",
        "T",
        f"dimensions [0 0 0 1 0 0 0];\ninternalField uniform {T_IN};\n"
        f"boundaryField {{ inlet {{ type fixedValue; value uniform {T_IN}; }}\n"
        " outlet { type zeroGradient; } walls { type zeroGradient; } }\n",
    )
    add_solver(
        case,
        "T",
        "solver PBiCGStab; preconditioner DILU; tolerance 1e-13; relTol 0;",
        extra=[("tolerance 1e-9", "tolerance 1e-11")],
    )
    fs = os.path.join(case, "system", "fvSolution")
    sc = os.path.join(case, "system", "fvSchemes")
    txt = open(sc).read().replace("div(phi,U)", "div(phi,T) Gauss upwind; div(phi,U)")
    if velocity_correction:
        txt = txt.replace(
            "div(phi,U) Gauss limitedLinearV 1", "div(phi,U) Gauss linearUpwind grad(U)"
        )
        assert "linearUpwind" in txt
        fs_txt = open(fs).read()
        open(fs, "w").write(
            fs_txt.replace("PIMPLE {", f"PIMPLE {{ velocityCorrection {velocity_correction};", 1)
        )
        assert "velocityCorrection" in open(fs).read()
    open(sc, "w").write(txt)
    return Us, end


@pytest.mark.fast
@pytest.mark.parametrize(
    "model,Re,vc",
    [
        ("DiFeliceColburn", 100.0, None),
        ("DiFeliceColburn", 500.0, None),
        ("Gunn", 30.0, None),
        ("DiFeliceColburn", 100.0, "fluxReconstruction"),
    ],
)
def test_lattice_bed_nusselt(tmp_path, env, model, Re, vc):
    case = str(tmp_path / f"{model}{Re:g}")
    Us, end = lattice_case(case, model, Re, vc)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("vansFoam", case, env)
    times = sorted(
        (float(t), t) for t in os.listdir(case) if re.fullmatch(r"[0-9.e+-]+", t) and float(t) > 0
    )
    T = read_internal(os.path.join(case, times[-1][1], "T")).reshape(NX, NY, NX, order="F")
    Tprev = read_internal(os.path.join(case, times[-2][1], "T")).reshape(NX, NY, NX, order="F")
    eps_f = read_internal(os.path.join(case, times[-1][1], "voidFraction")).reshape(
        NX, NY, NX, order="F"
    )
    eps = 1 - math.pi * D**3 / (6 * S**3)
    assert eps_f[:, BED0 : BED0 + LAYERS, :] == pytest.approx(eps, rel=1e-9)
    T_out = T[:, -1, :].mean()  # uniform flux: the mixed-cup value
    assert np.ptp(T[:, -1, :]) < 1e-4 * (T_P - T_IN)  # one-dimensional (2e-5)
    Tg = heat_lines(case)[-1]
    dT_in, dT_out = Tg - T_IN, Tg - T_out
    assert abs(Tg - T_P) < 1e-6 * dT_in  # the grains are a heat bath
    drift = abs(T_out - Tprev[:, -1, :].mean()) / dT_out
    assert drift < 1e-5  # steady (two flow-through times)
    # log-mean measure
    A = NX * NX * S * S
    Q = RHO * CP * Us * A * (T_out - T_IN)
    dT_lm = (dT_in - dT_out) / math.log(dT_in / dT_out)
    Nu_meas = Q / (NX * NX * LAYERS * math.pi * D * D * dT_lm) * D / KAPPA
    Nu_corr = MODELS[model](eps, Re, PR)
    n = math.pi * D * KAPPA * Nu_corr / (RHO * CP * Us * S * S)
    # the Nu that makes the 1D chain reproduce T_out (bisection, monotone)
    Nu_chain = invert_chain(lambda f: chain_outlet(f * Nu_corr, eps, Us), T_out) * Nu_corr
    # the closure at each grain's own Reynolds number (Ufluid: the fluid
    # velocity gathered at the grain, what vansFoam put into the closure)
    g = nscdpost.read_grains(case, times[-1][1])
    uf = nscdpost.read_vector_field(
        os.path.join(case, times[-1][1], "lagrangian", "grains", "Ufluid")
    )
    layer = np.rint(g["x"][:, 1] / S - 0.5).astype(int) - BED0
    Re_p = np.linalg.norm(uf, axis=1) * D / NU * eps  # superficial
    Nu_layers = np.array(
        [np.mean([MODELS[model](eps, r, PR) for r in Re_p[layer == j]]) for j in range(LAYERS)]
    )
    factor = invert_chain(lambda f: chain_outlet(f * Nu_layers, eps, Us), T_out)
    u_layers = np.array([np.mean(Re_p[layer == j]) for j in range(LAYERS)]) / Re
    print(
        f"{model} Re {Re:g}: eps {eps:.4f}, T_out {T_out:.8f} K, NTU {math.log(dT_in / dT_out):.4f}, "
        f"Nu log-mean {Nu_meas:.4f}, correlation {Nu_corr:.4f} (ratio {Nu_meas / Nu_corr:.4f}, "
        f"cell mixing ln(1+n)/n {math.log(1 + n) / n:.4f}, n {n:.4f}), Nu from the 1D chain "
        f"{Nu_chain:.5f} ({Nu_chain / Nu_corr - 1:+.2e}); T_out drift {drift:.1e}; "
        f"grain velocity / (U_s/eps) per layer {np.round(u_layers, 4)}, chain with the "
        f"closure at the grains' own Re: factor {factor:.6f}"
    )
    # the heat coupling: the closure at the grains' own eps and Re, spread
    # onto the cells, reproduces the outlet temperature
    assert factor == pytest.approx(1.0, abs=5e-3)
    # interior layers see the interstitial velocity U_s/eps
    assert u_layers[2:-2] == pytest.approx(1.0, abs=0.01)
    # the bed as a whole: with the default velocity correction the first
    # and last layers' grains see a slip velocity ~30 % low (the cell-centred
    # U next to the void-fraction jump, see test_bed_edge_velocity), so the
    # bed's Nu is 5-7 % below the closure's at U_s: within 10 %.  With
    # fluxReconstruction every layer sees U_s/eps and the bed's Nu is the
    # closure's: within 1 %
    if vc == "fluxReconstruction":
        assert u_layers == pytest.approx(1.0, abs=0.01)
        assert Nu_chain == pytest.approx(Nu_corr, rel=0.01)
    else:
        assert Nu_chain == pytest.approx(Nu_corr, rel=0.10)
    # the log-mean measure of a chain of well-mixed cells: Nu ln(1 + n)/n
    n_chain = n * Nu_chain / Nu_corr
    assert Nu_meas == pytest.approx(Nu_chain * math.log(1 + n_chain) / n_chain, rel=0.02)


def invert_chain(outlet, T_out):
    """The factor f with outlet(f) = T_out (bisection; outlet increases with f)."""
    lo, hi = 0.2, 5.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if outlet(mid) < T_out:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@pytest.mark.fast
@pytest.mark.parametrize(
    "vc",
    [
        "fluxReconstruction",
        pytest.param(
            None,
            marks=pytest.mark.xfail(
                strict=True,
                reason=(
                    "vansFoam's default velocity correction (faceForces): the cell-centred "
                    "interstitial velocity U in the cells on both sides of a void-fraction "
                    "jump (the first/last layer of a packed bed) is ~30 % off U_s/eps (the "
                    "face fluxes phi are right): the cell's 1/A multiplies the mean of its "
                    "face forces"
                ),
            ),
        ),
    ],
)
def test_bed_edge_velocity(tmp_path, env, vc):
    """Lattice bed, Re 100: every grain, edge layers included, sees the
    interstitial velocity U_s/eps within 2 % (Ufluid); the empty cells
    next to the bed carry U_s within 2 %.  Reference: continuity (a
    conservation law, not the solver's formula): in this one-dimensional
    flow the superficial velocity eps U is U_s in every cell, so the
    interstitial velocity is U_s/eps in the bed and U_s outside it."""
    case = str(tmp_path / "edge")
    Us, end = lattice_case(case, "DiFeliceColburn", 100.0, vc)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("vansFoam", case, env)
    t = max((float(x), x) for x in os.listdir(case) if re.fullmatch(r"[0-9.e+-]+", x))[1]
    eps = 1 - math.pi * D**3 / (6 * S**3)
    uf = nscdpost.read_vector_field(os.path.join(case, t, "lagrangian", "grains", "Ufluid"))
    U = nscdpost.read_vector_field(os.path.join(case, t, "U"))[:, 1].reshape(NX, NY, NX, order="F")
    print(
        "grain velocity / (U_s/eps):",
        np.round(np.sort(uf[:, 1]) / (Us / eps), 4)[::9],
        "cell U / U_s per layer:",
        np.round(U.mean(axis=(0, 2)) / Us, 4),
    )
    assert uf[:, 1] == pytest.approx(Us / eps, rel=0.02)
    assert U[:, [0, BED0 - 1, BED0 + LAYERS, NY - 1], :] == pytest.approx(Us, rel=0.02)


# ---------------------------------------------------------------------------
# 2. the tutorial's poured bed, two velocities
# ---------------------------------------------------------------------------
@pytest.mark.slow
def test_poured_bed_nusselt(tmp_path, env):
    setup, post = tutorial_modules("vansFoam", "packedBedHeat")
    root = str(tmp_path)
    dep = os.path.join(root, "deposit")
    setup.deposit(root=root)
    run("blockMesh", dep, env)
    run("grainDeposit", dep, env)
    setup.freeze(root=root)
    os.rename(os.path.join(dep, "log.grainDeposit"), os.path.join(dep, "log.grainDeposit.pour"))
    run("grainDeposit", dep, env)
    res = []
    for Re in (100.0, 500.0):
        case = os.path.join(root, f"Re{Re:g}")
        setup.setup(case, Re, root=root)
        run("blockMesh", case, env)
        run("vansFoam", case, env)
        res.append(post.measure(case))
    for r in res:
        ratio = r["nusselt_measured"] / r["nusselt_correlation"]
        msg = json.dumps({k: v for k, v in r.items() if k != "eps_layers"}, indent=1)
        assert 0.35 < r["void_fraction"] < 0.48, msg
        assert 0.85 <= ratio <= 1.02, msg
        assert r["nusselt_closure_grain_mean"] == pytest.approx(
            r["nusselt_correlation"], rel=0.03
        ), msg
        assert abs(r["Q"] - r["Q_grains"]) < 1e-4 * r["Q"], msg
        assert r["steady_drift"] < 1e-3, msg
        assert r["grain_T_drift"] < 1e-6, msg
