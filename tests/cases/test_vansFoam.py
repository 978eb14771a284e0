# SPDX-License-Identifier: GPL-3.0-or-later
"""vansFoam: exact restart, mixture volume conservation, serial = MPI.

The drag laws against independent references (lone sphere, Ergun, Richardson-
Zaki) are in test_drag.py.
"""

import math
import os
import re
import shutil

import nscdpost
import numpy as np
import pytest
from foamcase import (
    add_fluid,
    gmsh_box,
    make_box_case,
    read_internal,
    replace_in,
    run,
    run_fatal_io,
    run_parallel,
    write,
)

pytestmark = pytest.mark.fast

G = 9.81


def small_sedimentation(
    case, env, method="overlap", end=0.1, write=0.05, nrow=3, ncol=10, shear=0.0, mesh_hook=None
):
    """nrow x ncol discs of 3 mm (1500 kg/m^3) in a square lattice near the
    top of a 2D box of water 40 x 60 mm, 9 x 13 cells; shear: the box
    sheared by it (shear_box; grains moved with it); mesh_hook(case): called
    after blockMesh.  Runs blockMesh and grainDeposit; returns the grains
    (x, y, z, d)."""
    r = 1.5e-3
    grains = [
        (0.005 + (2 * i + 1) * r * 1.0001, 0.055 - (2 * j + 1) * r * 1.0001, 0, 2 * r)
        for j in range(nrow)
        for i in range(ncol)
    ]
    grains = [(x + shear * y, y, z, d) for x, y, z, d in grains]
    make_box_case(
        case,
        (0, 0, 0),
        (0.04, 0.06, 0.003),
        (9, 13, 1),
        (0, -G, 0),
        {"grains": {"density": 1500, "friction": 0.3}},
        grains=grains,
        end_time=end,
        dt=1e-3,
        write_interval=write,
    )
    add_fluid(case, 1000.0, 1e-6, void_method=method, max_dt=2e-3)
    if shear:
        shear_box(case, shear)
    run("blockMesh", case, env)
    if mesh_hook is not None:
        mesh_hook(case)
    run("grainDeposit", case, env)
    return grains


def test_restart_is_exact(tmp_path, env):
    """Stop at t1 = 0.05 s, restart from the written state, reach t2 = 0.1 s:
    grains and fluid equal an uninterrupted run to the 17 digits written."""
    case = str(tmp_path / "full")
    small_sedimentation(case, env)
    run("vansFoam", case, env)
    restart = str(tmp_path / "restart")
    import shutil

    shutil.copytree(case, restart)
    shutil.rmtree(os.path.join(restart, "0.1"))
    run("vansFoam", restart, env)
    for f in (
        "U",
        "p",
        "voidFraction",
        os.path.join("lagrangian", "grains", "positions"),
        os.path.join("lagrangian", "grains", "U"),
    ):
        a = open(os.path.join(case, "0.1", f)).read()
        b = open(os.path.join(restart, "0.1", f)).read()
        assert a == b, f
    g = nscdpost.read_grains(case, "0.1")
    assert np.max(np.abs(g["U"][:, 1])) > 1e-3, "grains should be falling"


RESTART_COLUMNS = {
    "grainContactImpulse": "vectorList",
    "grainDragImpulseDefect": "vectorList",
    "grainHeldFraction": "scalarList",
}


def _to_old_restart_format(time_dir, lists=True):
    """Turn a time directory into what versions before the restart columns
    wrote: grainState.h5 without the coupling's datasets, the per-grain
    lists in <time>/uniform/ (ASCII, shortest round-trip digits: the same
    doubles)."""
    import h5py

    values = {}
    with h5py.File(os.path.join(time_dir, "grainState.h5"), "r+") as f:
        for name in RESTART_COLUMNS:
            values[name] = f[name][()]
            del f[name]
    if not lists:
        return
    uniform = os.path.join(time_dir, "uniform")
    for name, cls in RESTART_COLUMNS.items():
        rows = [
            "(" + " ".join(repr(float(c)) for c in v) + ")" if v.ndim else repr(float(v))
            for v in values[name]
        ]
        with open(os.path.join(uniform, name), "w") as out:
            out.write(
                "FoamFile\n{\n    version     2.0;\n    format      ascii;\n"
                f"    class       {cls};\n    object      {name};\n}}\n"
                f"{len(rows)}\n(\n" + "\n".join(rows) + "\n)\n"
            )


def test_restart_from_an_old_format_case_is_exact(tmp_path, env):
    """A case written before the coupling's restart state moved into the
    grain state (grainState.h5 without grainContactImpulse,
    grainDragImpulseDefect, grainHeldFraction; those as uniform/ lists)
    continues exactly as the uninterrupted run: its lists are read.  The
    same state without the lists continues differently (so the lists
    matter in this case)."""
    case = str(tmp_path / "full")
    small_sedimentation(case, env)
    run("vansFoam", case, env)
    import h5py

    with h5py.File(os.path.join(case, "0.05", "grainState.h5"), "r") as f:
        assert all(f[n].shape[0] == 30 for n in RESTART_COLUMNS)
    for name in RESTART_COLUMNS:
        assert not os.path.exists(os.path.join(case, "0.05", "uniform", name))
    out = {}
    for variant, lists in (("old", True), ("none", False)):
        restart = str(tmp_path / variant)
        shutil.copytree(case, restart)
        shutil.rmtree(os.path.join(restart, "0.1"))
        _to_old_restart_format(os.path.join(restart, "0.05"), lists)
        run("vansFoam", restart, env)
        out[variant] = {
            f: open(os.path.join(restart, "0.1", f)).read()
            for f in ("U", "p", os.path.join("lagrangian", "grains", "positions"))
        }
    for f, text in out["old"].items():
        assert text == open(os.path.join(case, "0.1", f)).read(), f
    assert out["none"] != out["old"], "the restart lists made no difference"


@pytest.mark.parametrize("method", ["overlap", "centroid"])
def test_sedimentation_volume_conservation(tmp_path, env, method):
    """Mixture volume conservation over a sedimentation run: the continuity
    error div(eps U) + div(phi v*) of the final corrector stays at solver
    tolerance and the total fluid volume sum(eps V) equals the box volume
    minus the grain volume (exact overlaps: to 1e-9 relative).  The particle
    centroid method (eq. 3.44) clips eps at epsMin where several centroids
    share a cell (phi_c > 1): there the expected volume is rebuilt
    independently from the grain centres written at 0.2 s, eps_c =
    max(1 - n_c V_p/V_c, epsMin), to the same 1e-9."""
    case = str(tmp_path / method)
    small_sedimentation(case, env, method=method, end=0.2, write=0.1)
    run("vansFoam", case, env)
    # the final corrector's error (continuityErrors.dat)
    errs = nscdpost.read_step_data(case, "continuityErrors")["sumLocal"]
    assert len(errs) and max(errs) < 1e-7
    eps = read_internal(os.path.join(case, "0.2", "voidFraction"))
    V = 0.04 * 0.06 * 0.003 / (9 * 13)
    grains = 30 * math.pi * 1.5e-3**2 * 0.003
    expected = 0.04 * 0.06 * 0.003 - grains
    if method == "centroid":
        g = nscdpost.read_grains(case, "0.2")
        ix = np.floor(g["x"][:, 0] / (0.04 / 9)).astype(int)
        iy = np.floor(g["x"][:, 1] / (0.06 / 13)).astype(int)
        n = np.zeros((13, 9))
        np.add.at(n, (iy, ix), 1)
        Vp = math.pi * 1.5e-3**2 * 0.003
        expected = V * np.sum(np.maximum(1 - n * Vp / V, 1e-8))
    assert np.sum(eps) * V == pytest.approx(expected, rel=1e-9)


@pytest.mark.mpi
def test_parallel_matches_serial(tmp_path, env):
    """mpirun -np 2 gives the serial result: after 0.03 s (~15 steps; few
    enough that the solver-tolerance differences between the serial and the
    decomposed pressure solves, 1e-9 relative, are not amplified by grain
    collisions) every grain is within 1e-5 grain diameters of its serial
    position, and no grain is lost or duplicated across the ranks."""
    serial = str(tmp_path / "serial")
    small_sedimentation(serial, env, end=0.03, write=0.03, nrow=3, ncol=10)
    par = str(tmp_path / "parallel")
    import shutil

    shutil.copytree(serial, par)
    run("vansFoam", serial, env)
    run_parallel("vansFoam", par, env)
    run("reconstructPar", par, env, args=("-latestTime",))
    name = nscdpost.time_dirs(serial)[-1][1]
    gs = nscdpost.read_grains(serial, name)
    gp = nscdpost.read_grains(par, name)
    ids_s, ids_p = gs["grainId"], gp["grainId"]
    assert sorted(ids_p) == sorted(ids_s) == list(range(30))
    xs = gs["x"][np.argsort(ids_s)]
    xp = gp["x"][np.argsort(ids_p)]
    # measured: 2.9e-9 m (1e-6 d) with p solved to 1e-9
    assert np.max(np.abs(xs - xp)) < 1e-5 * 3e-3
    assert np.max(np.abs(gs["U"][:, 1])) > 1e-4, "grains should be moving"


def _with_pressure_diffusion(case, value):
    path = os.path.join(case, "constant", "couplingProperties")
    text = open(path).read()
    open(path, "w").write(text.replace("forceModel", f"pressureDiffusion {value};\nforceModel", 1))


def test_pressure_diffusion_moves_volume_but_creates_none(tmp_path, env):
    """couplingProperties pressureDiffusion C (artificial pressure diffusion
    div(C dt grad p) of the mixture continuity, the stabilisation of the
    thesis' particle-centroid runs, section 3.2.2) on the centroid-method
    sedimentation: conservation law, not a re-derivation.  The diffusion
    moves volume between cells (its local sum is not zero) but creates
    none: it carries no flux through the boundary, so its global sum over
    the mesh is zero to round-off (each step's last corrector); the solver's own
    continuity error, that term removed, stays at solver tolerance; the
    fluid volume sum(eps V) is still the box minus the (clipped) grains."""
    case = str(tmp_path / "pd")
    small_sedimentation(case, env, method="centroid", end=0.2, write=0.1)
    _with_pressure_diffusion(case, 1)
    run("vansFoam", case, env)
    # continuityErrors.dat: the step's last corrector (the log's "pressure
    # diffusion" line)
    c = nscdpost.read_step_data(case, "continuityErrors")
    local, glob = c["pressureDiffusionSumLocal"], c["pressureDiffusionGlobal"]
    assert len(local) > 20
    assert max(local) > 1e-9  # the term acts
    assert max(abs(glob)) < 1e-14  # and creates no volume
    errs = c["sumLocal"]
    assert len(errs) and max(errs) < 1e-7
    g = nscdpost.read_grains(case, "0.2")
    V = 0.04 * 0.06 * 0.003 / (9 * 13)
    n = np.zeros((13, 9))
    np.add.at(
        n,
        (
            np.floor(g["x"][:, 1] / (0.06 / 13)).astype(int),
            np.floor(g["x"][:, 0] / (0.04 / 9)).astype(int),
        ),
        1,
    )
    expected = V * np.sum(np.maximum(1 - n * math.pi * 1.5e-3**2 * 0.003 / V, 1e-8))
    eps = read_internal(os.path.join(case, "0.2", "voidFraction"))
    assert np.sum(eps) * V == pytest.approx(expected, rel=1e-9)


def test_pressure_diffusion_must_not_be_negative(tmp_path, env):
    """Bad input: pressureDiffusion < 0 is a FatalIOError naming the
    keyword, the file and the fix."""
    case = str(tmp_path / "neg")
    small_sedimentation(case, env, method="centroid", end=0.01, write=0.01)
    _with_pressure_diffusion(case, -1)
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "pressureDiffusion -1" in out and "couplingProperties" in out and "Fix" in out, out[
        -2000:
    ]


@pytest.mark.parametrize("rho, nu, bad", [(1000.0, 0.0, "nu 0 in"), (-1.0, 1e-6, "rho -1 and")])
def test_fluid_properties_must_be_positive(tmp_path, env, rho, nu, bad):
    """Bad input: rho or nu <= 0 in constant/transportProperties
    (constantFluidProperties) is a FatalIOError naming the file, the values
    and the fix, before any step."""
    case = str(tmp_path / "props")
    small_sedimentation(case, env, end=0.01, write=0.01)
    write(
        os.path.join(case, "constant", "transportProperties"),
        "dictionary",
        "transportProperties",
        f"rho {rho};\nnu {nu};\n",
    )
    out = run_fatal_io("vansFoam", case, env)
    assert bad in out and "transportProperties" in out, out[-2000:]
    assert "Fix" in out and "Time = " not in out, out[-2000:]


def shear_box(case, shear):
    """Shift the blockMeshDict vertices sideways by shear x their height (y):
    a box whose side faces are non-orthogonal by atan(shear)."""
    bm = os.path.join(case, "system", "blockMeshDict")
    txt = open(bm).read()
    verts = re.search(r"vertices \((.*)\);", txt).group(1)
    pts = [[float(c) for c in v.split()] for v in re.findall(r"\(([^()]*)\)", verts)]
    for v in pts:
        v[0] += shear * v[1]
    open(bm, "w").write(
        txt.replace(verts, " ".join(f"({v[0]:.17g} {v[1]:.17g} {v[2]:.17g})" for v in pts))
    )


@pytest.mark.parametrize(
    "shear, correction, expect, limit",
    [
        (0.0, "auto", "faceForces", 1e-6),
        (0.0375, "auto", "cellGradient", 1e-5),
        (0.0, "fluxReconstruction", "fluxReconstruction", 1e-6),
        (0.0375, "faceForces", "faceForces", 2e-5),
        (0.0375, "fluxReconstruction", "fluxReconstruction", 2e-5),
    ],
)
def test_fluid_at_rest_stays_at_rest(tmp_path, env, shear, correction, expect, limit):
    """Hydrostatics (analytical solution U = 0, p = g.x): water at rest in a
    closed box around one fixed grain stays at rest, |U| < limit after 10
    steps of 1 ms.  Orthogonal box: 5e-10 m/s measured.  Box whose top is
    shifted sideways by 3.75 % of its height (non-orthogonality 2.1 deg, a
    mild gmsh-like mesh): with the face forces reconstructed by OpenFOAM's
    fvc::reconstruct the velocity grew x100 per step and the run blew up at
    4 ms (its aliased product, faceReconstruct.H; the settling3D spheres on
    such a mesh blew up at 4.4 ms, and settle with auto at mean Re_p 323.6
    against 322.0 on the orthogonal mesh at 0.05 s).  With faceReconstruct
    faceForces and fluxReconstruction are stable there: 5.8e-6 m/s at 10 ms
    (5.4e-6 at 0.1 s: not growing).  velocityCorrection auto selects the
    cell-gradient form there, 40 times quieter: 1.3e-7
    m/s at 10 ms, with gravity as the discrete gradient of g.x on the
    non-orthogonal mesh (createVelocityCorrection.H; with g itself 1.0e-3
    m/s next to the tilted walls, whose fixedFluxPressure value ignored the
    tangential part of the boundary face's centre offset)."""
    case = str(tmp_path / f"shear{shear}{correction}")
    make_box_case(
        case,
        (0, 0, 0),
        (0.04, 0.08, 0.004),
        (10, 20, 1),
        (0, -9.81, 0),
        {"glass": {"density": 2500.0, "friction": 0.4}},
        grains=[(0.02, 0.04, 0.002, 0.004)],
        end_time=0.01,
        dt=1e-3,
        write_interval=0.01,
    )
    open(os.path.join(case, "system", "grainDepositDict"), "a").write("fixed yes;\n")
    shear_box(case, shear)
    add_fluid(case, 1000.0, 1e-6)
    fvs = os.path.join(case, "system", "fvSolution")
    txt = open(fvs).read().replace("PIMPLE {", f"PIMPLE {{ velocityCorrection {correction};", 1)
    assert "velocityCorrection" in txt
    open(fvs, "w").write(txt)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    log = run("vansFoam", case, env).stdout
    assert f"velocityCorrection {expect} ({correction}" in log
    U = np.asarray(read_internal(os.path.join(case, "0.01", "U")))
    print(f"shear {shear}, {correction}: |U| max {np.abs(U).max():.3e} m/s")
    assert np.abs(U).max() < limit


def tet_box(case, env, grains=(), gravity=(0, -G, 0), polyhedral=False):
    """A closed 20 x 40 x 20 mm box of water meshed by gmsh in tetrahedra
    (max cell size 4 mm: 1,385 tets, non-orthogonality up to 55 deg, mean
    21 deg), one wall patch `walls`, optional fixed grains (x, y, z, d).
    polyhedral: the tets' dual mesh (OpenFOAM's polyDualMesh, feature
    angle 70 deg), polyhedral cells."""
    make_box_case(
        case,
        (0, 0, 0),
        (0.02, 0.04, 0.02),
        (5, 10, 5),
        gravity,
        {"glass": {"density": 2500.0, "friction": 0.4}},
        grains=list(grains),
        end_time=0.02,
        dt=1e-3,
        write_interval=0.01,
        two_d=False,
    )
    open(os.path.join(case, "system", "grainDepositDict"), "a").write("fixed yes;\n")
    add_fluid(case, 1000.0, 1e-6)
    gmsh_box(case, env, (0, 0, 0), (0.02, 0.04, 0.02), 0.004, polyhedral=polyhedral)
    run("grainDeposit", case, env)


def test_closed_tet_box_flow_matches_pimpleFoam(tmp_path, env):
    """A tetrahedral mesh (gmsh, non-orthogonality up to 55 deg): water
    without gravity moving at (5, 2, 1) cm/s in a closed box slows down by
    wall friction; after 20 steps of 1 ms vansFoam without grains agrees
    with OpenFOAM's pimpleFoam on the same mesh and schemes (the reference:
    an independent solver of the same equations with eps = 1) within 3 % in
    the largest speed and the sum of U^2 (measured 1.1 % and 1.5 %).
    Before the momentum predictor used the corrector's cell-centred forces
    (UEqn.H, cellGradient) the run blew up at the second step (Courant
    number 31)."""
    case = str(tmp_path / "tet")
    tet_box(case, env, gravity=(0, 0, 0))
    u = os.path.join(case, "0", "U")
    txt = open(u).read().replace("uniform (0 0 0)", "uniform (0.05 0.02 0.01)", 1)
    open(u, "w").write(txt)
    ref = str(tmp_path / "pimple")
    os.makedirs(os.path.join(ref, "0"))
    for d in ("constant", "system"):
        shutil.copytree(os.path.join(case, d), os.path.join(ref, d))
    for f in ("U", "p"):
        shutil.copy(os.path.join(case, "0", f), os.path.join(ref, "0", f))
    write(
        os.path.join(ref, "constant", "transportProperties"),
        "dictionary",
        "transportProperties",
        "transportModel Newtonian;\nnu 1e-6;\n",
    )
    write(
        os.path.join(ref, "constant", "turbulenceProperties"),
        "dictionary",
        "turbulenceProperties",
        "simulationType laminar;\n",
    )
    replace_in(
        os.path.join(ref, "system", "fvSchemes"),
        (
            "div(phi,U) Gauss limitedLinearV 1;",
            "div(phi,U) Gauss limitedLinearV 1; div((nuEff*dev2(T(grad(U))))) Gauss linear;",
        ),
    )
    cd = os.path.join(ref, "system", "controlDict")
    txt = re.sub(r"functions.*", "", open(cd).read(), flags=re.S)
    open(cd, "w").write(txt)
    run("vansFoam", case, env)
    run("pimpleFoam", ref, env)
    U = np.asarray(read_internal(os.path.join(case, "0.02", "U")))
    R = np.asarray(read_internal(os.path.join(ref, "0.02", "U")))
    speed, speed_ref = np.linalg.norm(U, axis=1).max(), np.linalg.norm(R, axis=1).max()
    print(
        f"tet box at 0.02 s: |U| max {speed:.5g} (pimpleFoam {speed_ref:.5g}), "
        f"sum U^2 {np.sum(U**2):.5g} ({np.sum(R**2):.5g})"
    )
    assert 0.02 < speed_ref < 0.1
    assert speed == pytest.approx(speed_ref, rel=0.03)
    assert np.sum(U**2) == pytest.approx(np.sum(R**2), rel=0.03)


@pytest.mark.parametrize("mesh", ["tet", "polyhedral"])
def test_water_at_rest_on_unstructured_meshes(tmp_path, env, mesh):
    """Hydrostatics on a tetrahedral mesh and on its polyhedral dual
    (analytical solution U = 0, p = g.x): water at rest around one fixed
    grain stays at rest, |U| < 5e-4 m/s after 10 ms from p = 0 (measured
    1.2e-4 on tets; 1.3e-5 and 9.7e-6 m/s at 0.05 and 0.1 s; without the
    grain and with 2 non-orthogonal correctors 8e-7 m/s).  Gravity is the
    discrete gradient of g.x there (createVelocityCorrection.H, balanced
    gravity); with g itself the Gauss gradient of the hydrostatic pressure
    left 0.07 m/s on tets after 10 ms, 0.3-0.39 m/s after 0.1-0.3 s.
    The grain's overlap volumes over these cells add up to its volume."""
    case = str(tmp_path / mesh)
    tet_box(case, env, grains=[(0.01, 0.02, 0.01, 0.004)], polyhedral=mesh == "polyhedral")
    run("vansFoam", case, env)
    U = np.asarray(read_internal(os.path.join(case, "0.01", "U")))
    print(f"water at rest on the {mesh} mesh: |U| max {np.abs(U).max():.3e} m/s")
    assert np.abs(U).max() < 5e-4
    # the overlap volumes' partition of unity on these cells: the solid
    # volume sum (1 - eps) V equals the sphere's 4/3 pi r^3 (analytical)
    run("postProcess", case, env, args=("-func", "writeCellVolumes", "-time", "0.01"))
    eps = np.asarray(read_internal(os.path.join(case, "0.01", "voidFraction")))
    vol = np.asarray(read_internal(os.path.join(case, "0.01", "V")))
    assert np.sum((1 - eps) * vol) == pytest.approx(4 / 3 * math.pi * 0.002**3, rel=1e-10)


def hydrostatic_start(case, env, gravity=(0, -G, 0)):
    """p = g.x in the cells and on the wall faces at time 0 (OpenFOAM's
    setExprFields and setExprBoundaryFields), the hydrostatic state itself:
    the first step then starts in balance rather than from p = 0."""
    gx = " + ".join(f"({g!r})*pos().{c}()" for g, c in zip(gravity, "xyz"))
    write(
        os.path.join(case, "system", "setExprFieldsDict"),
        "dictionary",
        "setExprFieldsDict",
        f'expressions ( p {{ field p; expression "{gx}"; keepPatches true; }} );\n',
    )
    write(
        os.path.join(case, "system", "setExprBoundaryFieldsDict"),
        "dictionary",
        "setExprBoundaryFieldsDict",
        f'pressure {{ field p; expressions ( {{ target value; patch walls; expression "{gx}"; }} ); }}\n',
    )
    run("setExprFields", case, env, args=("-time", "0"))
    run("setExprBoundaryFields", case, env, args=("-time", "0"))


@pytest.mark.parametrize("mesh", ["tet", "polyhedral"])
def test_water_at_rest_exactly_from_the_hydrostatic_state(tmp_path, env, mesh):
    """Hydrostatics, analytical solution U = 0, p = g.x + const: water
    around one fixed grain on gmsh tets (non-orthogonality up to 55 deg) and
    on their polyhedral dual, started from p = g.x (hydrostatic_start) with
    2 non-orthogonal correctors and the pressure solved to 1e-12 (relTol
    0), stays at rest to round-off: |U| < 1e-8 m/s after 0.1 s (measured
    5.7e-14 on tets, 8.3e-14 on polyhedra) and p - g.x uniform to 1e-9 of
    g H.  Gravity is the discrete gradient of g.x (createVelocityCorrection.H),
    so p = g.x is the discrete solution exactly once its wall values are
    g.x too.  With the defaults (no corrector, relTol 0.01) |U| is 3.8e-8
    (tets) and 7.6e-10 (polyhedra) m/s; from p = 0, 9.7e-6 m/s on tets
    (test_water_at_rest_on_unstructured_meshes): the first step's imbalance
    is damped only by viscosity (L^2/nu ~ 16 s for these cells)."""
    case = str(tmp_path / mesh)
    tet_box(case, env, grains=[(0.01, 0.02, 0.01, 0.004)], polyhedral=mesh == "polyhedral")
    replace_in(
        os.path.join(case, "system", "controlDict"),
        ("endTime 0.02;", "endTime 0.1;"),
        ("writeInterval 0.01;", "writeInterval 0.1;"),
    )
    replace_in(
        os.path.join(case, "system", "fvSolution"),
        ("tolerance 1e-9; relTol 0.01;", "tolerance 1e-12; relTol 0;"),
        ("nNonOrthogonalCorrectors 0;", "nNonOrthogonalCorrectors 2;"),
    )
    hydrostatic_start(case, env)
    run("vansFoam", case, env)
    U = np.asarray(read_internal(os.path.join(case, "0.1", "U")))
    print(f"water at rest on the {mesh} mesh from p = g.x: |U| max {np.abs(U).max():.3e} m/s")
    assert np.abs(U).max() < 1e-8
    run("postProcess", case, env, args=("-func", "writeCellCentres", "-time", "0.1"))
    y = np.asarray(read_internal(os.path.join(case, "0.1", "Cy")))
    p = np.asarray(read_internal(os.path.join(case, "0.1", "p")))
    spread = np.ptp(p + G * y)
    print(f"p - g.x spread {spread:.3e} m^2/s^2")
    assert spread < 1e-9 * G * 0.04


def warp_box(case, degrees, width, height):
    """Move the points of a blockMesh box sideways by
    A sin(pi x/W) sin(2 pi y/H), A = tan(degrees) H/(2 pi): the walls stay
    where they were (same geometry), the cells become curved quadrilaterals
    whose faces are non-orthogonal by up to ~degrees (checkMesh: 9.7 and
    29.0 deg for 10 and 30)."""
    amp = math.tan(math.radians(degrees)) * height / (2 * math.pi)
    path = os.path.join(case, "constant", "polyMesh", "points")
    txt = open(path).read()

    def moved(m):
        x, y, z = (float(c) for c in m.group(1).split())
        x += amp * math.sin(math.pi * x / width) * math.sin(2 * math.pi * y / height)
        return f"({x:.17g} {y:.17g} {z:.17g})"

    i, j = txt.index("\n(\n") + 3, txt.rindex("\n)\n")
    open(path, "w").write(txt[:i] + re.sub(r"\(([^()]*)\)", moved, txt[i:j]) + txt[j:])


@pytest.mark.parametrize(
    "mesh, degrees, rel, correction",
    [
        ("warped", 10, 0.03, "auto"),
        ("warped", 30, 0.03, "auto"),
        ("sheared", 10, 0.05, "auto"),
        ("warped", 30, 0.03, "faceForces"),
    ],
)
def test_sedimentation_on_non_orthogonal_meshes(tmp_path, env, mesh, degrees, rel, correction):
    """60 discs of 3 mm settling in water in a 2D box, on a non-orthogonal
    mesh against the orthogonal one: the mean fall of the grains over 0.3 s
    agrees within `rel`.  A consistency check of the discretisation across
    meshes (its reference is the same code on the orthogonal mesh); the
    independent reference of the non-orthogonal scheme is pimpleFoam in
    test_closed_tet_box_flow_matches_pimpleFoam.
    - warped: the same box, points moved by a sine warp (warp_box), faces
      non-orthogonal by up to 9.7 and 29.0 deg: measured +0.7 % and +1.7 %
      (with g itself instead of the balanced gravity: +0.7 %, +1.0 %).
    - sheared: the box itself sheared by 10 deg (side walls tilted, so not
      the same container): measured -1.4 %.  Before the non-orthogonal mesh
      took its face pressure gradient from the solved equation and the
      predictor the corrector's forces (pEqn.H, UEqn.H) this box stopped at
      0.014 s (time step collapsed).  At 30 deg the tilted wall meets the
      falling block (its foot moves 7 mm under the block over the fall): a
      different flow, -5 to -12 %, hence the warped mesh there.
    - correction faceForces: the face forces reconstructed by faceReconstruct
      on the warped mesh (faceReconstruct.H; OpenFOAM's fvc::reconstruct
      blew up there): measured +0.2 % at 30 deg (sheared 10 deg: -0.2 %)."""

    def fall(deg):
        case = str(tmp_path / f"{mesh}{deg}")
        grains = small_sedimentation(
            case,
            env,
            end=0.3,
            write=0.3,
            nrow=6,
            shear=math.tan(math.radians(deg)) if mesh == "sheared" else 0.0,
            mesh_hook=(lambda c: warp_box(c, deg, 0.04, 0.06))
            if mesh == "warped" and deg
            else None,
        )
        if correction != "auto":
            fvs = os.path.join(case, "system", "fvSolution")
            txt = (
                open(fvs)
                .read()
                .replace("PIMPLE {", f"PIMPLE {{ velocityCorrection {correction};", 1)
            )
            open(fvs, "w").write(txt)
        log = run("vansFoam", case, env).stdout
        assert ("cellGradient" if deg and correction == "auto" else "faceForces") in log
        y0 = np.mean([y for _, y, _, _ in grains])
        return y0 - np.mean(nscdpost.read_grains(case, "0.3")["x"][:, 1])

    ref, got = fall(0), fall(degrees)
    print(f"mean fall over 0.3 s: {got:.5f} m, {mesh} {degrees} deg; {ref:.5f} m orthogonal")
    assert ref > 0.01
    assert got == pytest.approx(ref, rel=rel)


@pytest.mark.parametrize(
    "word, shear, expect",
    [
        # an unknown word: the message lists the modes
        (
            "reconstruct",
            0.0,
            ["velocityCorrection reconstruct", "cellGradient", "fluxReconstruction"],
        ),
    ],
)
def test_velocity_correction_errors(tmp_path, env, word, shear, expect):
    case = str(tmp_path / "bad")
    make_box_case(
        case,
        (0, 0, 0),
        (0.04, 0.08, 0.004),
        (4, 8, 1),
        (0, -9.81, 0),
        {"glass": {"density": 2500.0, "friction": 0.4}},
        grains=[(0.02, 0.04, 0.002, 0.004)],
        end_time=0.001,
        dt=1e-3,
    )
    if shear:
        shear_box(case, shear)
    add_fluid(case, 1000.0, 1e-6)
    fvs = os.path.join(case, "system", "fvSolution")
    txt = open(fvs).read().replace("PIMPLE {", f"PIMPLE {{ velocityCorrection {word};", 1)
    open(fvs, "w").write(txt)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    out = run_fatal_io("vansFoam", case, env)
    for w in expect:
        assert w in out, w
