# SPDX-License-Identifier: GPL-3.0-or-later
"""OpenFOAM adapter of the overlap mapping (src/vansCoupling/overlapMeshAdapter)
through the grainVoidFraction utility (thesis section 3.2.1, eq. 3.43).

Checks, in 2D (discs, volume pi r^2 x mesh depth) and 3D (spheres):
  - conservation: sum_c phi_c V_c == sum_g V_g to 1e-10 relative for grains
    wholly inside the domain, for unresolved (h >> d), semi-resolved (h ~ d)
    and resolved (h << d) meshes;
  - resolved: cells inside a grain have phi = 1 and eps = epsMin;
  - eps in [epsMin, 1];
  - parallel (decomposePar, mpirun -np 2, reconstructPar) == serial to 1e-12,
    with grains straddling the processor boundary.
"""

import math
import os
import shutil

import numpy as np
import pytest
from foamcase import log_message, make_box_case, read_internal, run, run_parallel, write

pytestmark = pytest.mark.fast

MAT = {"glass": {"density": 2500, "friction": 0.4}}


def check_coupling_log(text, tol=1e-12):
    """grainVoidFraction -checkCoupling logs the relative errors of force
    conservation (spread, eq. 3.42), partition of unity (gather of a uniform
    field) and adjointness (sum_g a_g.F_g vs sum_c a_c.f_c V_c)."""
    lines = log_message(
        text, r"checkCoupling: spread (\S+), unity (\S+), adjoint (\S+)", every=True
    )
    assert lines, text[-2000:]
    for errs in lines:
        assert all(float(e) < tol for e in errs), errs


def deposited_box(case, env, hi, cells, grains, two_d=True, lo=(0, 0, 0), mapping_dict=None):
    """Box [lo, hi] (2D: one cell deep), uniform cells, grains (x y z d) by
    grainDeposit method list: blockMesh and grainDeposit run."""
    make_box_case(case, lo, hi, cells, (0, -9.81, 0), MAT, grains=grains, two_d=two_d)
    if mapping_dict is not None:
        write(
            os.path.join(case, "system", "overlapMappingDict"),
            "dictionary",
            "overlapMappingDict",
            mapping_dict,
        )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)


def grain_case(tmp_path, env, name, size, cells, grains, two_d, mapping_dict=None):
    """Box [0, size] (2D: depth size[2]), uniform cells, grains (x y z d) by
    grainDeposit method list, then grainVoidFraction. Returns (case, phi,
    eps, V_cell)."""
    case = str(tmp_path / name)
    deposited_box(case, env, size, cells, grains, two_d, mapping_dict=mapping_dict)
    p = run("grainVoidFraction", case, env, args=["-checkCoupling"])
    check_coupling_log(p.stdout)
    phi = read_internal(os.path.join(case, "0", "solidFraction"))
    eps = read_internal(os.path.join(case, "0", "voidFraction"))
    nz = cells[2] if not two_d else 1
    vcell = size[0] * size[1] * size[2] / (cells[0] * cells[1] * nz)
    return case, phi, eps, vcell


def grain_volume(grains, two_d, depth):
    if two_d:
        return sum(math.pi * (g[3] / 2) ** 2 * depth for g in grains)
    return sum(math.pi / 6 * g[3] ** 3 for g in grains)


def lattice(n_per_side, size, d_of, two_d, jitter=0.37):
    """Grains on a jittered lattice (no overlaps, wholly inside)."""
    out = []
    sp = [size[k] / n_per_side for k in range(3)]
    nz = 1 if two_d else n_per_side
    rng = np.random.default_rng(7)
    for k in range(nz):
        for j in range(n_per_side):
            for i in range(n_per_side):
                d = d_of(i, j, k)
                x = (i + 0.5 + jitter * (rng.random() - 0.5) * (1 - d / sp[0])) * sp[0]
                y = (j + 0.5 + jitter * (rng.random() - 0.5) * (1 - d / sp[1])) * sp[1]
                z = (
                    0.0
                    if two_d
                    else (k + 0.5 + jitter * (rng.random() - 0.5) * (1 - d / sp[2])) * sp[2]
                )
                out.append((x, y, z, d))
    return out


# (name, two_d, size, cells, grains)
L2, D2 = 0.1, 0.01  # 2D box and depth
L3 = 0.05
CASES = [
    (
        "2d_semi",
        True,
        (L2, L2, D2),
        (20, 20, 1),
        lattice(6, (L2, L2, D2), lambda i, j, k: 4e-3 + 1e-3 * ((i + j) % 3), True),
    ),
    (
        "2d_unresolved",
        True,
        (L2, L2, D2),
        (2, 2, 1),
        lattice(8, (L2, L2, D2), lambda i, j, k: 2e-3 + 5e-4 * (i % 2), True),
    ),
    ("2d_resolved", True, (L2, L2, D2), (40, 40, 1), [(0.0512, 0.0493, 0.0, 0.06)]),
    (
        "3d_semi",
        False,
        (L3, L3, L3),
        (8, 8, 8),
        lattice(4, (L3, L3, L3), lambda i, j, k: 5e-3 + 1e-3 * ((i + j + k) % 3), False),
    ),
    (
        "3d_unresolved",
        False,
        (L3, L3, L3),
        (2, 2, 2),
        lattice(3, (L3, L3, L3), lambda i, j, k: 2e-3, False),
    ),
    ("3d_resolved", False, (L3, L3, L3), (12, 12, 12), [(0.0252, 0.0246, 0.0249, 0.036)]),
]


@pytest.mark.parametrize("name,two_d,size,cells,grains", CASES, ids=[c[0] for c in CASES])
def test_conservation_and_bounds(tmp_path, env, name, two_d, size, cells, grains):
    eps_min = 1e-6
    _, phi, eps, vcell = grain_case(
        tmp_path,
        env,
        name,
        size,
        cells,
        grains,
        two_d,
        mapping_dict=f"method overlap;\nepsMin {eps_min};\n",
    )
    vg = grain_volume(grains, two_d, size[2])
    assert abs(phi.sum() * vcell - vg) <= 1e-10 * vg
    assert phi.min() >= 0
    assert eps.min() >= eps_min and eps.max() <= 1.0
    np.testing.assert_allclose(eps, np.maximum(1 - phi, eps_min), rtol=0, atol=1e-15)
    if name.endswith("resolved") and not name.endswith("unresolved"):
        # cells wholly inside the (single) grain: phi == 1, eps == epsMin
        x, y, z, d = grains[0]
        r = d / 2
        nx, ny, nz = cells
        hx, hy, hz = size[0] / nx, size[1] / ny, size[2] / nz
        inside = []
        for c in range(phi.size):
            i, j, k = c % nx, (c // nx) % ny, c // (nx * ny)
            corners = [
                ((i + a) * hx - x) ** 2
                + ((j + b) * hy - y) ** 2
                + (0 if two_d else ((k + e) * hz - z) ** 2)
                for a in (0, 1)
                for b in (0, 1)
                for e in (0, 1)
            ]
            if max(corners) < r * r:
                inside.append(c)
        assert len(inside) > 50
        np.testing.assert_allclose(phi[inside], 1.0, rtol=0, atol=1e-12)
        assert np.all(eps[inside] == eps_min)
        assert phi.max() <= 1 + 1e-12


def test_centroid_method_and_keyword_check(tmp_path, env):
    """PCM (method centroid): each grain volume lands in one cell; an unknown
    keyword is a fatal error naming it."""
    grains = CASES[0][4]
    _, phi, _, vcell = grain_case(
        tmp_path,
        env,
        "pcm",
        (L2, L2, D2),
        (20, 20, 1),
        grains,
        True,
        mapping_dict="method centroid;\n",
    )
    vg = grain_volume(grains, True, D2)
    assert abs(phi.sum() * vcell - vg) <= 1e-10 * vg
    assert np.count_nonzero(phi) <= len(grains)
    case = str(tmp_path / "pcm")
    write(
        os.path.join(case, "system", "overlapMappingDict"),
        "dictionary",
        "overlapMappingDict",
        "method overlap;\nepsMn 1e-6;\n",
    )
    p = run("grainVoidFraction", case, env, check=False)
    assert p.returncode != 0 and "epsMn" in p.stdout + p.stderr


def _mpirun_ok(env):
    if shutil.which("mpirun", path=env.get("PATH")) is None:
        return "mpirun not found"
    return None


@pytest.mark.mpi
@pytest.mark.parametrize("two_d", [True, False], ids=["2d", "3d"])
def test_parallel_matches_serial(tmp_path, env, two_d):
    reason = _mpirun_ok(env)
    if reason:
        pytest.skip(reason)
    if two_d:
        size, cells = (L2, L2, D2), (20, 20, 1)
        # grains straddling the processor boundary x = 0.05 (simple 2 1 1)
        grains = [
            (0.05, 0.03, 0.0, 0.012),
            (0.0513, 0.07, 0.0, 0.02),
            (0.0471, 0.05, 0.0, 0.004),
            (0.02, 0.02, 0.0, 0.005),
            (0.08, 0.081, 0.0, 0.006),
        ]
    else:
        size, cells = (L3, L3, L3), (8, 8, 8)
        grains = [
            (0.025, 0.0125, 0.0251, 0.012),
            (0.0261, 0.035, 0.023, 0.011),
            (0.01, 0.01, 0.01, 0.005),
            (0.04, 0.04, 0.04, 0.006),
        ]
    case, phi_s, eps_s, vcell = grain_case(tmp_path, env, "par", size, cells, grains, two_d)
    for f in ("solidFraction", "voidFraction"):
        os.remove(os.path.join(case, "0", f))
    p = run_parallel("grainVoidFraction", case, env, args=("-checkCoupling",))
    check_coupling_log(p.stdout)
    for k in range(2):
        assert os.path.exists(os.path.join(case, f"processor{k}", "0", "solidFraction"))
    run("reconstructPar", case, env, args=["-withZero", "-fields", "(solidFraction voidFraction)"])
    phi_p = read_internal(os.path.join(case, "0", "solidFraction"))
    eps_p = read_internal(os.path.join(case, "0", "voidFraction"))
    np.testing.assert_allclose(phi_p, phi_s, rtol=0, atol=1e-12)
    np.testing.assert_allclose(eps_p, eps_s, rtol=0, atol=1e-12)
    vg = grain_volume(grains, two_d, size[2])
    assert abs(phi_p.sum() * vcell - vg) <= 1e-10 * vg


def test_2d_mesh_off_origin_in_z(tmp_path, env):
    """2D mesh whose z range does not contain 0 (nscd discs lie at z = 0):
    the adapter maps on the mesh mid-plane; V_g = pi r^2 x depth."""
    case = str(tmp_path / "offz")
    grains = [(0.03, 0.04, 0.0, 0.01), (0.07, 0.05, 0.0, 0.012)]
    deposited_box(case, env, (0.1, 0.1, 0.125), (10, 10, 1), grains, lo=(0, 0, 0.1))
    run("grainVoidFraction", case, env)
    phi = read_internal(os.path.join(case, "0", "solidFraction"))
    vcell = 0.01 * 0.01 * 0.025
    vg = grain_volume(grains, True, 0.025)
    assert abs(phi.sum() * vcell - vg) <= 1e-10 * vg


def test_grain_outside_mesh_is_fatal(tmp_path, env):
    """A grain centre outside the mesh: FatalError naming the grain and the fix
    (here the mesh is shrunk after the grains were made)."""
    case = str(tmp_path / "outside")
    grains = [(0.02, 0.02, 0.0, 0.004), (0.09, 0.05, 0.0, 0.004)]
    deposited_box(case, env, (0.1, 0.1, 0.01), (10, 10, 1), grains)
    make_box_case(case, (0, 0, 0), (0.08, 0.1, 0.01), (10, 10, 1), (0, -9.81, 0), MAT, two_d=True)
    run("blockMesh", case, env)
    p = run("grainVoidFraction", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "Grain 1 at" in out and "outside the mesh" in out and "Fix:" in out
