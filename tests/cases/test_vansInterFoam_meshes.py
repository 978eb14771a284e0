# SPDX-License-Identifier: GPL-3.0-or-later
"""vansInterFoam on non-orthogonal, tetrahedral and polyhedral meshes.

Still water under air in the closed basin of test_vansInterFoam (40 x 60 mm,
water below 30 mm) on a mesh sheared by 10, 30 and 60 deg (side walls
tilted), and in a gmsh tetrahedral box and its polyhedral dual; the reference is hydrostatics (U = 0, the water
volume constant).  Grains settling into the sheared basin against the same
run on the orthogonal mesh, and spheres settling through the surface on
tets and polyhedra against hexahedra.  Before faceReconstruct
(src/vansCoupling/solverTools/faceReconstruct.H) the runs blew up at the
second step already at 2 deg: fvc::reconstruct's aliased product gave a
force of 3.6e6 instead of -201 in every other cell.  Measurements:
docs/validation/unstructuredMeshes.md.
"""

import math
import os

import foamcase
import nscdpost
import numpy as np
import pytest
from correlations import cd_brown_lawler, terminal_velocity
from foamcase import gmsh_box, make_box_case, read_internal, run
from interfoamcase import G, add_two_phase, basin
from test_vansFoam import shear_box
from test_vansInterFoam import ode_fall


@pytest.mark.fast
@pytest.mark.parametrize(
    "degrees",
    [
        10,
        30,
        pytest.param(
            60,
            marks=pytest.mark.xfail(
                strict=True,
                reason="60 deg: water |U| 0.33 m/s at 0.1 s (0.28-0.45 from 0.02 s, not"
                " growing), the surface current of the corrected schemes and surface"
                " tension; uncorrected schemes and sigma 0: 1.4e-5 m/s",
            ),
        ),
    ],
)
def test_still_basin_on_a_sheared_mesh(tmp_path, env, monkeypatch, degrees):
    """Shear of 10, 30 and 60 deg, no grains, 0.1 s at adjustable time
    step: the run ends, the water volume sum(eps alpha V) of waterVolume.dat
    stays constant to 1e-12 (measured 1e-16), alpha in [0, 1] to 1e-6, and
    the water stays nearly at rest: |U| < 0.1 m/s where alpha > 0.99
    (measured 0.06 m/s at 10 deg, air 1.25 m/s; 30 deg: 0.082, air 2.7; 60
    deg: 0.33, air 3.3, the strict xfail).  The light air above the surface carries a spurious current of
    ~1 m/s next to the surface (the explicit non-orthogonal correction of
    ghf snGrad(rho) in the interface rows is not balanced by p_rgh's; README,
    not bounded here: with uncorrected snGrad and laplacian schemes and
    sigma 0 the basin stays at rest to 4e-8 m/s, water, and 3e-6, air)."""
    case = str(tmp_path / "sheared")

    def sheared(case, env, *a, **kw):
        shear_box(case, math.tan(math.radians(degrees)))
        return add_two_phase(case, env, *a, **kw)

    monkeypatch.setattr("interfoamcase.add_two_phase", sheared)
    basin(case, env, [], fixed=False, end=0.1)
    log = run("vansInterFoam", case, env).stdout
    assert "reconstruction faceReconstruct" in log
    d = nscdpost.read_step_data(case, "waterVolume")
    vol = d["waterVolume"]
    assert len(vol) > 50
    assert np.max(np.abs(vol - vol[0])) < 1e-12 * vol[0]
    assert d["alphaMin"].min() > -1e-6 and d["alphaMax"].max() < 1 + 1e-6
    U = np.linalg.norm(np.asarray(read_internal(os.path.join(case, "0.1", "U"))), axis=1)
    a = np.asarray(read_internal(os.path.join(case, "0.1", "alpha.water")))
    print(
        f"basin sheared by {degrees} deg at 0.1 s: water |U| max {U[a > 0.99].max():.3g},"
        f" air {U[a < 0.01].max():.3g}"
    )
    assert U[a > 0.99].max() < 0.1


BOX_LO, BOX_HI = (0, 0, 0), (0.02, 0.04, 0.02)


def gmsh_instead_of_blockMesh(monkeypatch, mesh):
    """interfoamcase meshes the 20 x 40 x 20 mm box with gmsh (4 mm tets, or
    their polyhedral dual for mesh 'polyhedral') where it would run
    blockMesh."""

    def unstructured(app, c, e, *a, **kw):
        if app == "blockMesh":
            return gmsh_box(c, e, BOX_LO, BOX_HI, 0.004, polyhedral=mesh == "polyhedral")
        return foamcase.run(app, c, e, *a, **kw)

    monkeypatch.setattr("interfoamcase.run", unstructured)


def box_case(case, grains, end, write_interval):
    """The 3D box with 2 mm glass grains from a list, 4 mm cells (blockMesh,
    or gmsh after gmsh_instead_of_blockMesh), dt 1e-3 s."""
    make_box_case(
        case,
        BOX_LO,
        BOX_HI,
        (5, 10, 5),
        (0, -G, 0),
        {"glass": {"density": 2500, "friction": 0.3}},
        grains=grains,
        end_time=end,
        dt=1e-3,
        write_interval=write_interval,
        two_d=False,
    )


def tet_basin(case, env, level, monkeypatch, polyhedral=False):
    """A closed 20 x 40 x 20 mm box meshed by gmsh in tetrahedra (1,385
    tets, faces up to 55 deg off orthogonal), water below y = level, air
    above, no grains, 0.1 s at adjustable time step."""
    gmsh_instead_of_blockMesh(monkeypatch, "polyhedral" if polyhedral else "tet")
    box_case(case, [], 0.1, 0.1)
    add_two_phase(case, env, level)
    log = run("vansInterFoam", case, env).stdout
    assert "reconstruction faceReconstruct" in log
    U = np.linalg.norm(np.asarray(read_internal(os.path.join(case, "0.1", "U"))), axis=1)
    a = np.asarray(read_internal(os.path.join(case, "0.1", "alpha.water")))
    return U, a, nscdpost.read_step_data(case, "waterVolume")


@pytest.mark.fast
def test_still_water_on_tets(tmp_path, env, monkeypatch):
    """Hydrostatics on tetrahedra (U = 0).  Water alone filling the box: the
    p_rgh form is exact there, |U| < 1e-10 m/s at 0.1 s (measured 1.1e-14).
    Water below air (surface at 20 mm): the run ends, the water volume
    sum(eps alpha V) stays constant to 1e-12 (measured 3e-15), alpha in
    [0, 1] to 1e-6, and |U| < 0.2 m/s where alpha > 0.99 (measured 0.12-0.13
    m/s from 0.05 to 0.2 s, not growing; air up to 2 m/s).  The current
    comes from the interface: on tets the faces that cross the staircase
    surface of a setFields start lie at different heights, so no p_rgh
    balances gh_f snGrad(rho) on all of them, and the non-orthogonal
    correction adds the mismatch of the sheared basin (README; surface
    tension 0: water 0.08, air 1.9 m/s).  OpenFOAM's interFoam, as built
    here, blows up on this case at the first step (fvc::reconstruct)."""
    U, _, _ = tet_basin(str(tmp_path / "full"), env, 1.0, monkeypatch)
    print(f"water alone on tets at 0.1 s: |U| max {U.max():.3g}")
    assert U.max() < 1e-10
    U, a, d = tet_basin(str(tmp_path / "surface"), env, 0.02, monkeypatch)
    vol = d["waterVolume"]
    assert np.max(np.abs(vol - vol[0])) < 1e-12 * vol[0]
    assert d["alphaMin"].min() > -1e-6 and d["alphaMax"].max() < 1 + 1e-6
    print(f"tet basin at 0.1 s: water |U| max {U[a > 0.99].max():.3g}, air {U[a < 0.01].max():.3g}")
    assert U[a > 0.99].max() < 0.2


def settle(case, env, degrees, monkeypatch):
    """Five 2 mm glass discs released at rest 6 mm below the surface of the
    basin, sheared by `degrees`, settling for 0.25 s; returns the times and
    the discs' heights (n_times, 5) and the water volume history."""
    s = math.tan(math.radians(degrees))
    y0 = 0.024
    grains = [(0.008 + 0.006 * i + s * y0, y0, 0, 2e-3) for i in range(5)]

    def sheared(c, e, *a, **kw):
        shear_box(c, s)
        return add_two_phase(c, e, *a, **kw)

    monkeypatch.setattr("interfoamcase.add_two_phase", sheared)
    basin(case, env, grains, fixed=False, end=0.25, write_interval=0.05)
    run("vansInterFoam", case, env)
    series = [
        (t, nscdpost.read_grains(case, name)["x"][:, 1]) for t, name in nscdpost.time_dirs(case)
    ]
    t = np.array([s[0] for s in series])
    return t, np.array([s[1] for s in series]), nscdpost.read_step_data(case, "waterVolume")


@pytest.mark.fast
def test_grains_settle_on_a_sheared_mesh_as_on_the_orthogonal_one(tmp_path, env, monkeypatch):
    """Five discs settle through the water of the basin sheared by 10 deg
    as in the orthogonal basin (the reference; same code), and both agree
    with two estimates: the discs end at rest on the floor, y = r to 1 um
    (contact, hydrostatic rest), and their mean fall speed from 0.05 to
    0.15 s lies below the isolated disc's terminal velocity (Dallavalle/
    Di Felice in unbounded water, eps = 1: 0.255 m/s; measured 0.166 m/s,
    the five discs in 2.5 mm cells see eps < 1 and the walls).  The sheared
    fall speed within 5 % of the orthogonal one (measured -3.0 %), the water
    volume constant to 1e-12 in both (measured 4e-15)."""
    speeds = {}
    for deg in (0, 10):
        t, y, d = settle(str(tmp_path / f"shear{deg}"), env, deg, monkeypatch)
        monkeypatch.undo()
        i, j = np.argmin(np.abs(t - 0.05)), np.argmin(np.abs(t - 0.15))
        speeds[deg] = (y[i].mean() - y[j].mean()) / (t[j] - t[i])
        assert t[-1] == pytest.approx(0.25)
        assert np.all(np.abs(y[-1] - 1e-3) < 1e-6), y[-1]
        vol = d["waterVolume"]
        assert np.max(np.abs(vol - vol[0])) < 1e-12 * vol[0]
    terminal = ode_fall(1.0, 2500.0, 2e-3, 1000.0, 1e-3, 1.0)
    print(f"mean fall speed 0.05-0.15 s: {speeds[0]:.4f} m/s orthogonal, {speeds[10]:.4f} sheared")
    assert 0.3 * terminal < speeds[0] < terminal
    assert speeds[10] == pytest.approx(speeds[0], rel=0.05)


@pytest.mark.fast
def test_still_water_on_polyhedra(tmp_path, env, monkeypatch):
    """Hydrostatics (U = 0) on the tet box's dual mesh (polyDualMesh 70:
    polyhedral cells).  Water alone filling the box, and water below air
    (surface at 20 mm), 0.1 s, bounds as on tets."""
    U, _, _ = tet_basin(str(tmp_path / "full"), env, 1.0, monkeypatch, polyhedral=True)
    print(f"water alone on polyhedra at 0.1 s: |U| max {U.max():.3g}")
    assert U.max() < 1e-10
    U, a, d = tet_basin(str(tmp_path / "surface"), env, 0.02, monkeypatch, polyhedral=True)
    vol = d["waterVolume"]
    print(
        f"polyhedral basin at 0.1 s: water |U| max {U[a > 0.99].max():.3g},"
        f" air {U[a < 0.01].max():.3g}, volume drift {np.max(np.abs(vol - vol[0])) / vol[0]:.3g}"
    )
    assert np.max(np.abs(vol - vol[0])) < 1e-12 * vol[0]
    assert d["alphaMin"].min() > -1e-6 and d["alphaMax"].max() < 1 + 1e-6
    assert U[a > 0.99].max() < 0.2


def settle_3d(case, env, mesh, monkeypatch):
    """Five 2 mm glass spheres released at rest 6 mm below the surface of
    the 20 x 40 x 20 mm box (water below 30 mm, air above), settling for
    0.25 s on 4 mm hexahedra (blockMesh), gmsh tets or their polyhedral
    dual; returns the mean fall speed from 0.05 to 0.15 s, the final
    heights and the water volume history."""
    if mesh != "hex":
        gmsh_instead_of_blockMesh(monkeypatch, mesh)
    y0 = 0.024
    grains = [(0.005 + 0.005 * (i % 3), y0, 0.006 + 0.008 * (i // 3), 2e-3) for i in range(5)]
    box_case(case, grains, 0.25, 0.025)
    add_two_phase(case, env, 0.03)
    run("vansInterFoam", case, env)
    series = [
        (t, nscdpost.read_grains(case, name)["x"][:, 1]) for t, name in nscdpost.time_dirs(case)
    ]
    t = np.array([a[0] for a in series])
    y = np.array([a[1] for a in series])
    i, j = np.argmin(np.abs(t - 0.05)), np.argmin(np.abs(t - 0.15))
    speed = (y[i].mean() - y[j].mean()) / (t[j] - t[i])
    return speed, y[-1], nscdpost.read_step_data(case, "waterVolume")["waterVolume"]


@pytest.mark.slow
def test_spheres_settle_on_tets_and_polyhedra_as_on_hexahedra(tmp_path, env, monkeypatch):
    """Sedimentation through the free surface on unstructured meshes: five
    spheres settle on gmsh tets and on their polyhedral dual as on the
    hexahedral box (the reference; same code): mean fall speed from 0.05 to
    0.15 s within 5 % (measured +1.8 % tets, -0.4 % polyhedra; hexahedra
    0.173 m/s), below Brown & Lawler's terminal velocity of the isolated
    sphere in unbounded water (0.266 m/s; the spheres are 2 mm in 4 mm cells
    beside walls 10 d apart) and above 0.3 of it; every sphere ends at rest
    on the floor, y = r to 1 um; the water volume constant to 1e-12
    (measured 1-3e-15)."""
    terminal = terminal_velocity(cd_brown_lawler, 2e-3, 1e-6, 1000.0, 2500.0)
    speeds = {}
    for mesh in ("hex", "tet", "polyhedral"):
        speed, y, vol = settle_3d(str(tmp_path / mesh), env, mesh, monkeypatch)
        monkeypatch.undo()
        speeds[mesh] = speed
        assert np.all(np.abs(y - 1e-3) < 1e-6), (mesh, y)
        assert np.max(np.abs(vol - vol[0])) < 1e-12 * vol[0], mesh
        assert 0.3 * terminal < speed < terminal, mesh
    print("mean fall speed 0.05-0.15 s [m/s]:", speeds)
    assert speeds["tet"] == pytest.approx(speeds["hex"], rel=0.05)
    assert speeds["polyhedral"] == pytest.approx(speeds["hex"], rel=0.05)
