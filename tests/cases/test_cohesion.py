# SPDX-License-Identifier: GPL-3.0-or-later
"""vansFoam cohesion switched by the vapour field (thesis eq. 4.18).

    F_c = F_c^0 if psi < psi^0 at the contact point, 0 otherwise,

and only at contacts that persist (couplingProperties cohesion.minAge,
nscd::System::Settings::cohesionMinAge; the nscd law itself is tested in
src/nscd/tests/testCohesion.cpp against the Signorini condition with
r~_n = r_n + F_c dt).

Case: 2D box of air (2 mm cells), a row of five fixed discs (d = 2 mm) near
the top and, under its two end discs, two free glass discs hanging in
contact (gap 0), weight
W = rho_p pi r^2 g = 0.077 N/m per unit depth < F_c^0 = 0.2 N/m.  psi is
a fixed-value initial field (Python-written nonuniform internalField): 0 in
the left half, 1 in the right half, psi^0 = 0.5; D_v = 2.5e-5 m^2/s
diffuses it over sqrt(D_v t) = 1 mm in 0.05 s, far from the contacts (5 mm
from the step); vapour { bounded yes; } since the 2 mm discs are as large as
the cells (the conservative form overshoots there, see test_vapour.py).  Reference: the force balance of a hanging disc: cohesive
(F_c^0 > W) it stays (the gap-based contact law closes any gap within one
step, so the disc moves at most g dt^2 = 1e-7 m, in the first step before
psi is looked up), not cohesive it falls freely, g t^2/2 = 12 mm in 0.05 s
(air drag < 10 %).  Tolerances: the hanging disc moves < 1e-3 d in 0.05 s,
the falling one > 0.1 d.
- vapourThreshold 0.5: the dry (left) disc hangs, the wet (right) one falls;
- no vapour at all, cohesion everywhere (dry cohesion): both hang;
- dry cohesion with minAge 5: both fall (an unloaded contact opens in its
  first step, so it never gets old enough: a bond needs a persisting contact);
- input errors: FatalIOError naming couplingProperties, the keyword and the fix.
"""

import os

import nscdpost
import numpy as np
import pytest
from foamcase import add_fluid, add_scalar_transport, make_box_case, run, run_parallel, write

D = 2e-3  # disc diameter [m]
RHO_P = 2500.0
FC0 = 0.2  # cohesion force [N/m] per unit depth (2D)
W, H, DEPTH = 0.02, 0.04, 0.002
NX, NY = 10, 20
XL, XR, Y0 = 0.005, 0.015, 0.031  # fixed row (5 discs) from (XL, Y0) to (XR, Y0)


def hanging_case(case, cohesion, vapour, y0=Y0):
    make_box_case(
        case,
        (0, 0, 0),
        (W, H, DEPTH),
        (NX, NY, 1),
        (0, -9.81, 0),
        {"glass": {"density": RHO_P, "friction": 0.4}},
        grains=[(XL, y0 - D, 0, D), (XR, y0 - D, 0, D)],
        end_time=0.05,
        dt=1e-4,
        write_interval=0.05,
    )
    open(os.path.join(case, "system", "grainDepositDict"), "a").write(
        f"fixedRow {{ from ({XL} {y0} 0); to ({XR} {y0} 0); diameter {D}; }}\n"
    )
    add_fluid(
        case,
        1.2,
        1.5e-5,
        max_dt=1e-4,
        extra_coupling=f"cohesion {{ {cohesion} }}\n" if cohesion is not None else "",
    )
    if vapour:
        open(os.path.join(case, "constant", "transportProperties"), "a").write(
            "vapour { D 2.5e-5; rho 0.6; bounded yes; }\n"
        )
        # psi = 0 (dry) for x < W/2, 1 (wet) for x > W/2 (cell order: x fastest)
        values = [
            0.0 if (i + 0.5) * W / NX < 0.5 * W else 1.0 for j in range(NY) for i in range(NX)
        ]
        write(
            os.path.join(case, "0", "psi"),
            "volScalarField",
            "psi",
            "dimensions [0 0 0 0 0 0 0];\n"
            f"internalField nonuniform List<scalar> {len(values)} (\n"
            + "\n".join(f"{v:g}" for v in values)
            + "\n);\n"
            "boundaryField { walls { type zeroGradient; } frontAndBack { type empty; } }\n",
        )
        add_scalar_transport(
            case,
            "psi",
            "Gauss limitedLinear01 1",
            "solver PBiCGStab; preconditioner DILU; tolerance 1e-12; relTol 0;",
        )


def displacements(case, env, mesh=True, solve=True):
    """Run the case; downward displacements of the two hanging discs and the log."""
    if mesh:
        run("blockMesh", case, env)
        run("grainDeposit", case, env)
    log = run("vansFoam", case, env).stdout if solve else ""
    x = {}
    for name in ("0", "0.05"):
        g = nscdpost.read_grains(case, name)
        ids = g["grainId"]
        order = np.argsort(ids)
        assert list(ids[order]) == list(range(7))  # every grain written once
        assert list(g["fixed"][order]) == [False, False] + [True] * 5
        x[name] = g["x"][order]
    # downward displacement of the left and right hanging discs (grains 0, 1)
    drop = [x["0"][k][1] - x["0.05"][k][1] for k in (0, 1)]
    return drop, log


@pytest.mark.fast
def test_vapour_switches_cohesion(tmp_path, env):
    case = str(tmp_path / "vapour")
    hanging_case(case, f"force {FC0}; vapourThreshold 0.5; minAge 0;", vapour=True)
    (left, right), log = displacements(case, env)
    weight = RHO_P * 3.141592653589793 * (D / 2) ** 2 * 9.81
    print(
        f"weight {weight:.4g} N/m, F_c0 {FC0} N/m: dry disc moved {left:.3e} m, wet disc {right:.3e} m"
    )
    assert weight < FC0
    assert abs(left) < 1e-3 * D
    assert right > 0.1 * D
    # cohesion.dat (the log's "cohesion:" line): one cohesive contact (the
    # dry pair), the dry pair looked up dry
    c = nscdpost.read_step_data(case, "cohesion")
    assert len(c["Time"]) and c["cohesiveContacts"][-1] == 1
    assert c["dryPairs"][-1] >= 1 and c["wetPairs"].max() >= 1


@pytest.mark.fast
def test_dry_cohesion_everywhere(tmp_path, env):
    case = str(tmp_path / "dry")
    hanging_case(case, f"force {FC0};", vapour=False)
    (left, right), log = displacements(case, env)
    print(f"dry cohesion: discs moved {left:.3e} m, {right:.3e} m")
    assert "everywhere (dry)" in log
    assert abs(left) < 1e-3 * D and abs(right) < 1e-3 * D


@pytest.mark.fast
def test_cohesion_none_is_off(tmp_path, env):
    """`cohesion none;` is the run-time selected "off": both discs fall
    freely (0.05 s of free fall is 12 mm, 12 diameters)."""
    case = str(tmp_path / "none")
    hanging_case(case, None, vapour=False)
    open(os.path.join(case, "constant", "couplingProperties"), "a").write("cohesion none;\n")
    (left, right), log = displacements(case, env)
    print(f"cohesion none: discs fell {left:.3e} m, {right:.3e} m")
    assert left > 0.1 * D and right > 0.1 * D


@pytest.mark.fast
def test_min_age_needs_a_persisting_contact(tmp_path, env):
    case = str(tmp_path / "minAge")
    hanging_case(case, f"force {FC0}; minAge 5;", vapour=False)
    (left, right), log = displacements(case, env)
    print(f"minAge 5, unloaded contacts: discs fell {left:.3e} m, {right:.3e} m")
    assert left > 0.1 * D and right > 0.1 * D


def serial_and_parallel(tmp_path, env, cohesion, vapour, y0=Y0, split=None):
    """The hanging case (fixed row at height y0) run serial and on 2 ranks
    (cut at x = W/2, between the pairs; split (1, 2, 1): at y = H/2);
    returns the serial and the parallel drops (left, right) and the
    parallel log."""
    import shutil

    serial = str(tmp_path / "serial")
    hanging_case(serial, cohesion, vapour=vapour, y0=y0)
    run("blockMesh", serial, env)
    run("grainDeposit", serial, env)
    par = str(tmp_path / "parallel")
    shutil.copytree(serial, par)
    drops, _ = displacements(serial, env, mesh=False)
    log = run_parallel("vansFoam", par, env, split=split).stdout
    run("reconstructPar", par, env, args=("-latestTime",))
    drops_par, _ = displacements(par, env, mesh=False, solve=False)
    return drops, drops_par, log


@pytest.mark.slow
@pytest.mark.mpi
def test_parallel_same_decision(tmp_path, env):
    """mpirun -np 2, the ranks split at x = W/2 between the dry and the wet
    pair, the grains decomposed: each rank looks psi up at the contact
    points of the contacts it solves, so both take the serial decision (dry
    disc hangs, wet disc falls, displacements equal to the serial ones
    within 1e-9 m: solver tolerance) and every grain is written once (the
    fixed disc at x = W/2 lies on the processor boundary)."""
    (ls, rs), (lp, rp), log = serial_and_parallel(
        tmp_path, env, f"force {FC0}; vapourThreshold 0.5;", vapour=True
    )
    print(f"serial drops {ls:.3e} {rs:.3e} m, parallel {lp:.3e} {rp:.3e} m")
    assert "grains decomposed over 2 ranks" in log, log[-3000:]
    assert abs(lp) < 1e-3 * D and rp > 0.1 * D
    assert abs(lp - ls) < 1e-9 and abs(rp - rs) < 1e-9


@pytest.mark.slow
@pytest.mark.mpi
def test_parallel_contact_point_across_the_cut(tmp_path, env):
    """The ranks split at y = H/2 = 20 mm, the fixed row at 21.5 mm (rank 1)
    and the hanging discs at 19.5 mm (rank 0): each hanging pair's contact
    is solved by rank 0 (the owner of the grain with the smaller id, the
    hanging disc) while its contact point, at 20.5 mm, lies in rank 1's
    cells, so rank 0 gets psi there from rank 1. A lookup that failed
    would leave the dry pair without cohesion and its disc would fall; it
    hangs, as in the serial run (within 1e-9 m), and the wet one falls."""
    (ls, rs), (lp, rp), log = serial_and_parallel(
        tmp_path, env, f"force {FC0}; vapourThreshold 0.5;", vapour=True, y0=0.0215, split=(1, 2, 1)
    )
    print(f"cut at y = 20 mm: serial drops {ls:.3e} {rs:.3e} m, decomposed {lp:.3e} {rp:.3e} m")
    assert "grains decomposed over 2 ranks" in log, log[-3000:]
    assert abs(ls) < 1e-3 * D and rs > 0.1 * D
    assert abs(lp) < 1e-3 * D and rp > 0.1 * D
    assert abs(lp - ls) < 1e-9 and abs(rp - rs) < 1e-9


@pytest.mark.fast
@pytest.mark.mpi
def test_dry_cohesion_decomposed(tmp_path, env):
    """The same with dry cohesion, which needs no replication: the grains
    decomposed, both discs hang as in the serial run (displacements within
    1e-9 m), every grain written once.  Cohesive contacts across a rank
    interface: src/nscdMPI/tests/testDecomposed.cpp
    (CohesiveChainHangsAcrossTheInterfacesAsSerial)."""
    (ls, rs), (lp, rp), log = serial_and_parallel(tmp_path, env, f"force {FC0};", vapour=False)
    print(f"dry cohesion, serial drops {ls:.3e} {rs:.3e} m, decomposed {lp:.3e} {rp:.3e} m")
    assert "grains decomposed over 2 ranks" in log, log[-3000:]
    assert abs(lp) < 1e-3 * D and abs(rp) < 1e-3 * D
    assert abs(lp - ls) < 1e-9 and abs(rp - rs) < 1e-9


@pytest.mark.fast
@pytest.mark.parametrize("what", ["noVapour", "unknownKeyword", "noForce", "negativeAge"])
def test_cohesion_input_errors(tmp_path, env, what):
    case = str(tmp_path / what)
    body = {
        "noVapour": f"force {FC0}; vapourThreshold 0.5;",
        "unknownKeyword": f"force {FC0}; minage 2;",
        "noForce": "minAge 2;",
        "negativeAge": f"force {FC0}; minAge -1;",
    }[what]
    hanging_case(case, body, vapour=False)
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace("endTime 0.05;", "endTime 0.0002;")
    open(cd, "w").write(txt)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "FOAM FATAL IO ERROR" in out and "couplingProperties.cohesion" in out, out[-2000:]
    expect = {
        "noVapour": "Fix: add vapour { D <m^2/s>; rho <kg/m^3>; } to constant/transportProperties",
        "unknownKeyword": "Unknown keyword 'minage'",
        "noForce": "Missing keyword force",
        "negativeAge": "minAge -1",
    }[what]
    assert expect in out, out[-2000:]
