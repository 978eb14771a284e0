# SPDX-License-Identifier: GPL-3.0-or-later
"""The packings of tutorials/vansFoam/sedimentation (setupCase.py,
packing.py): the thesis mode's hexagonal packing (M. Henry, PhD thesis,
UCLouvain, section 3.2.2, Figure 3.9) and the default square lattice, checked
on the grain list setupCase.py writes against the definition of the two
lattices (independent reference: the geometry of touching discs, nearest
neighbours d apart, 6 of them in the interior of a hexagonal packing, 4 in a
square lattice), and the default kept as before (6,650 discs, 50 rows of
133, the grid CI's sedimentation tests and MigFlow's grid deposit use).
"""

import os
import re
import subprocess
import sys

import nscdpost
import numpy as np
import pytest
from foamcase import run

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
TUT = os.path.join(ROOT, "tutorials", "vansFoam", "sedimentation")
D = 3e-3  # grain diameter [m]
BOX = (0.4, 0.6)


def grain_list(case, env, *args, end="2"):
    """(centres (n, 2), diameters (n,)) of the grainDepositDict written by
    `setupCase.py case overlap END *args`."""
    subprocess.run(
        [sys.executable, os.path.join(TUT, "setupCase.py"), case, "overlap", end, *args],
        env=env,
        check=True,
        capture_output=True,
    )
    text = open(os.path.join(case, "system", "grainDepositDict")).read()
    g = np.array([[float(v) for v in m.split()] for m in re.findall(r"^\(([^()]*)\)$", text, re.M)])
    return g[:, :2], g[:, 3]


def neighbour_counts(xy, d, chunk=400):
    """(distance of each disc's nearest neighbour, number of discs within
    1.01 d) over all pairs less than 2 d apart in height (discs sorted by
    height, each chunk against the discs of its height band)."""
    order = np.argsort(xy[:, 1])
    p = xy[order]
    nearest, count = np.empty(len(p)), np.empty(len(p), dtype=int)
    for s in range(0, len(p), chunk):
        a = p[s : s + chunk]
        lo, hi = np.searchsorted(p[:, 1], [a[:, 1].min() - 2 * d, a[:, 1].max() + 2 * d])
        r = np.hypot(*(a[:, None, :] - p[None, lo:hi, :]).transpose(2, 0, 1))
        r[np.arange(len(a)), np.arange(s, s + len(a)) - lo] = np.inf  # itself
        nearest[order[s : s + chunk]] = r.min(axis=1)
        count[order[s : s + chunk]] = (r < 1.01 * d).sum(axis=1)
    return nearest, count


def interior(xy, margin):
    lo, hi = xy.min(axis=0) + margin, xy.max(axis=0) - margin
    return np.all((xy > lo) & (xy < hi), axis=1)


@pytest.mark.fast
@pytest.mark.parametrize(
    "packing, grains, neighbours", [("hexagonal", 7553, 6), ("square", 6650, 4)]
)
def test_packing_geometry(tmp_path, env, packing, grains, neighbours):
    xy, d = grain_list(str(tmp_path / packing), env, "--packing", packing)
    assert len(xy) == grains
    assert np.allclose(d, D, rtol=1e-8)
    nearest, count = neighbour_counts(xy, D)
    # touching discs: every nearest neighbour d apart (no overlap, no gap)
    assert np.allclose(nearest, D, rtol=1e-8), (nearest.min(), nearest.max())
    inner = interior(xy, 1.5 * D)
    assert inner.sum() > 0.8 * grains
    assert np.all(count[inner] == neighbours), np.unique(count[inner])
    # the layer: inside the box, top 2 mm below the lid, at most 0.150 m thick
    top, bottom = xy[:, 1].max() + D / 2, xy[:, 1].min() - D / 2
    assert top == pytest.approx(BOX[1] - 2e-3, abs=1e-9)
    assert 0.1485 - 1e-4 < top - bottom <= 0.150 + 1e-9
    assert xy[:, 0].min() - D / 2 > 0 and xy[:, 0].max() + D / 2 < BOX[0]


@pytest.mark.fast
def test_default_is_the_square_grid(tmp_path, env):
    """No --packing: the square grid (the default the CI tests and the bench
    results use), the same list as before the thesis mode existed:
    133 columns x 50 rows of spacing d from x0 = 0.5 mm, top centres at
    0.6 - 2e-3 - r."""
    xy, _ = grain_list(str(tmp_path / "default"), env)
    i, j = np.meshgrid(np.arange(133), np.arange(50))
    ref = np.column_stack(
        [0.5e-3 + (2 * i.ravel() + 1) * D / 2, 0.598 - (2 * j.ravel() + 1) * D / 2]
    )
    assert np.allclose(xy, ref, atol=1e-9)


@pytest.mark.fast
def test_perturbed_lattice_has_no_overlap(tmp_path, env):
    """--perturb A moves centres by up to A d and shrinks the discs to
    (1 - 2 A) d: no pair overlaps."""
    xy, d = grain_list(str(tmp_path / "p"), env, "--perturb", "0.05", "--seed", "3")
    assert np.allclose(d, 0.9 * D, rtol=1e-8)
    nearest, _ = neighbour_counts(xy, D)
    assert nearest.min() >= 0.9 * D * (1 - 1e-8)
    assert nearest.min() < 0.95 * D  # the offsets did move the discs


@pytest.mark.slow
def test_thesis_mode_short_run(tmp_path, env):
    """The thesis mode's overlap case (./Allrun thesis: hexagonal packing,
    effectiveDiameterFactor 0.88, jiggled mesh) to 0.5 s.  Independent
    checks: the mixture stays incompressible -- every grain is kept with its
    diameter, the final corrector's continuity error stays at solver
    tolerance and the fluid volume sum(eps V) (V from writeCellVolumes on the
    jiggled mesh) equals the box volume minus the fluid-side grain volume
    k^2 sum(pi d^2 / 4) x depth, computed here from the diameters, to 1e-9;
    and the leading edge at 0.5 s lies in the band of MigFlow 1.4 on the
    same packing (tests/bench/migflowSedimentation.py --packing hexagonal,
    fall 0.0511 m with the true discs, 0.0750 m with the fluid seeing
    0.88 d; docs/validation/sedimentation.md): between them, widened by
    5 mm (the two jiggled-mesh runs there fall 0.0755 and 0.0740 m)."""
    case = str(tmp_path / "thesis")
    k = 0.88
    xy0, _ = grain_list(
        case, env, "--packing", "hexagonal", "--effective-diameter-factor", str(k), end="0.5"
    )
    run("blockMesh", case, env)
    subprocess.run(
        [sys.executable, os.path.join(TUT, "jiggleMesh.py"), case, "0.2"], env=env, check=True
    )
    run("grainDeposit", case, env)
    run("vansFoam", case, env)
    run("postProcess", case, env, args=["-func", "writeCellVolumes", "-time", "0.5"])
    g = nscdpost.read_grains(case, "0.5")
    assert len(g["d"]) == len(xy0) == 7553
    assert np.allclose(g["d"], D * (1 - 1e-9), rtol=1e-12)
    errs = nscdpost.read_step_data(case, "continuityErrors")["sumLocal"]
    assert len(errs) and max(errs) < 1e-7
    eps = nscdpost.read_internal_field(os.path.join(case, "0.5", "voidFraction"))
    V = nscdpost.read_internal_field(os.path.join(case, "0.5", "V"))
    depth = 3e-3
    assert np.sum(V) == pytest.approx(BOX[0] * BOX[1] * depth, rel=1e-12)
    grains = k**2 * np.sum(np.pi * g["d"] ** 2 / 4) * depth
    assert np.sum(eps * V) == pytest.approx(BOX[0] * BOX[1] * depth - grains, rel=1e-9)
    front = np.percentile(g["x"][:, 1], 0.5) - D / 2
    start = np.percentile(xy0[:, 1], 0.5) - D / 2
    assert 0.0511 - 0.005 < start - front < 0.0750 + 0.005, start - front
