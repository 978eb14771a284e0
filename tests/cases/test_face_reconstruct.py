# SPDX-License-Identifier: GPL-3.0-or-later
"""Regression test of the solvers' face-field reconstruction
(src/vansCoupling/solverTools/faceReconstruct.H) against OpenFOAM v1912's
fvc::reconstruct, whose product inv(T) & b on a temporary b GCC 12 -O3
miscompiles (docs/validation/unstructuredMeshes.md, section 1).

tests/foam/faceReconstructCheck (built by Allwmake with the solvers'
flags) reconstructs the face fluxes U0 . S_f of a uniform vector U0 with
faceReconstruct and with reconstructFaceField (the solvers' choice on the
mesh).  Reference, independent of the field algebra: the formula
(sum n S)^-1 . sum n (S . U0) gives U0 exactly on any mesh, so the error is
round-off; a linear field's fluxes against the same formula evaluated one
cell at a time with single tensors.  Meshes: the 2D box sheared by 2 and
30 deg (test_vansFoam.shear_box) and a gmsh tetrahedral box.  The
aliased fvc::reconstruct's error is recorded (it is what the solvers
avoid), not bounded: another compiler may build it right."""

import math

import pytest
from foamcase import gmsh_box, make_box_case, run, run_check
from test_vansFoam import shear_box

pytestmark = pytest.mark.fast


def check(case, env):
    """Run faceReconstructCheck on the case; its results."""
    return run_check("faceReconstructCheck", case, env)


@pytest.mark.parametrize("mesh", ["sheared2", "sheared30", "tet"])
def test_face_reconstruct_of_a_uniform_field_is_exact(tmp_path, env, mesh):
    """faceReconstruct and reconstructFaceField give U0 back to 1e-12 (relative)
    on every mesh, the linear field's reconstruction matches the cell-by-cell
    formula to 1e-12; on these non-orthogonal meshes fvc::reconstruct of this
    build is off by O(1) (2 deg: measured in the log of this test)."""
    case = str(tmp_path / mesh)
    two_d = mesh != "tet"
    make_box_case(
        case,
        (0, 0, 0),
        (0.02, 0.04, 0.02 if not two_d else 0.002),
        (8, 16, 1) if two_d else (4, 8, 4),
        (0, -9.81, 0),
        {"glass": {"density": 2500, "friction": 0.3}},
        two_d=two_d,
    )
    if mesh == "tet":
        gmsh_box(case, env, (0, 0, 0), (0.02, 0.04, 0.02), 0.004)
    else:
        shear_box(case, math.tan(math.radians(2 if mesh == "sheared2" else 30)))
        run("blockMesh", case, env)
    r = check(case, env)
    print(f"{mesh}: {r}")
    assert r["nonOrthogonality"] > 1.9
    assert r["uniformError"] < 1e-12
    assert r["solverError"] < 1e-12
    assert r["linearError"] < 1e-12
