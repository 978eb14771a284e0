# SPDX-License-Identifier: GPL-3.0-or-later
"""grainCloud's cell search (src/grainCloud/grainMeshExits.H) against
OpenFOAM's polyMesh::findCell.

On a one-cell-thick 2D mesh polyMesh's cell octree stops refining (every
cell spans the thickness and falls in both halves of each split), so a
search there tests hundreds of cells; grainMeshExits searches its own
octree of the cells on a box as deep as it is wide.  The grains' start
check, their inside-mesh check and the lagrangian write all use it.
tests/foam/cellSearchCheck (built by Allwmake) compares both searches at
random points of the mesh's widened bounding box (2D: in the grains'
plane).  Reference: polyMesh::findCell, an independent search with the same
point-in-cell test (CELL_TETS), so the cells must agree exactly; the CPU
times are recorded, and the 2D search must be faster."""

import math

import pytest
from foamcase import gmsh_box, make_box_case, run, run_check
from test_vansFoam import shear_box

pytestmark = pytest.mark.fast


def check(case, env, two_d):
    """Run cellSearchCheck on the case; its results."""
    return run_check("cellSearchCheck", case, env, ["-twoD"] if two_d else [])


@pytest.mark.parametrize("mesh", ["box2D", "sheared2D", "tet3D"])
def test_cell_search_names_polyMesh_cells(tmp_path, env, mesh):
    """The same cell (or none) as polyMesh::findCell at 20,000 random points,
    from no hint and from a random hint; in 2D (a 120 x 150 cell box, about
    the rayleighTaylor tutorial's 122 x 148) at least 5 times faster."""
    case = str(tmp_path / mesh)
    two_d = mesh != "tet3D"
    make_box_case(
        case,
        (0, 0, 0),
        (0.056, 0.068, 0.002) if two_d else (0.02, 0.04, 0.02),
        (120, 150, 1) if two_d else (4, 8, 4),
        (0, -9.81, 0),
        {"glass": {"density": 2500, "friction": 0.3}},
        two_d=two_d,
    )
    if mesh == "tet3D":
        gmsh_box(case, env, (0, 0, 0), (0.02, 0.04, 0.02), 0.003)
    else:
        if mesh == "sheared2D":
            shear_box(case, math.tan(math.radians(30)))
        run("blockMesh", case, env)
    r = check(case, env, two_d)
    print(f"{mesh}: {r}")
    assert r["points"] == 20000
    assert 0.3 * r["points"] < r["inside"] < r["points"]
    assert r["findCellMismatches"] == 0
    assert r["findCellFromMismatches"] == 0
    if two_d:
        assert r["searchSeconds"] < r["referenceSeconds"] / 5
