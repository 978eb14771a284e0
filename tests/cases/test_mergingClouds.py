# SPDX-License-Identifier: GPL-3.0-or-later
"""tutorials/vansFoam/mergingClouds (M. Henry, PhD thesis, UCLouvain,
section 3.3, Figures 3.10-3.11): two clouds of radius R = 3.3 mm made of
glass discs at solid fraction 0.2, centres 10 mm apart, falling in a fluid
of 1030 kg/m^3 and 0.6 Pa s.

The set-up (fast) is checked on the grain list setupCase.py writes against
the geometry the thesis gives (independent reference: the disc areas, N pi
r^2 / pi R^2 = 0.2, every disc inside its cloud's circle, no two discs
overlapping, the clouds' centres 10 mm apart on the box's axis), also at the
thesis' grain size; the pure-fluid reference's drop against pi R^2.  The
short coarse run (slow) against the single cloud's fall and the physics of a
falling pair (Stimson & Jeffery 1926 for two spheres one above the other:
the pair falls faster than one alone; a trailing drop catches a leading one
only through their deformation and the fluid's inertia, here Re ~ 0.17).
"""

import json
import os
import re
import subprocess
import sys

import nscdpost
import numpy as np
import pytest
from foamcase import run

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
TUT = os.path.join(ROOT, "tutorials", "vansFoam", "mergingClouds")
R = 3.3e-3


def setup_case(case, env, *args):
    """Run setupCase.py CASE *args; returns (centres (n, 2), diameters (n,),
    setup.json)."""
    subprocess.run(
        [sys.executable, os.path.join(TUT, "setupCase.py"), case, *args],
        env=env,
        check=True,
        capture_output=True,
    )
    with open(os.path.join(case, "setup.json")) as f:
        setup = json.load(f)
    path = os.path.join(case, "system", "grainDepositDict")
    if not os.path.isfile(path):
        return None, None, setup
    text = open(path).read()
    g = np.array([[float(v) for v in m.split()] for m in re.findall(r"^\(([^()]*)\)$", text, re.M)])
    return g[:, :2], g[:, 3], setup


def check_cloud(xy, d, centre):
    """Solid fraction, extent and overlaps of one cloud's discs."""
    r = 0.5 * d
    dist = np.hypot(*(xy - centre).T)
    assert np.all(dist + r <= R * (1 + 1e-9)), "a disc pokes out of the cloud"
    assert dist.max() + r.max() > 0.97 * R, "the cloud is smaller than R"
    assert np.sum(r**2) / R**2 == pytest.approx(0.2, rel=0.02)
    # no overlaps: pairs k apart in the order of x, until none is closer
    # than d in x
    p = xy[np.argsort(xy[:, 0])]
    nearest = np.inf
    for k in range(1, len(p)):
        dx = p[k:, 0] - p[:-k, 0]
        if dx.min() >= d.max():
            break
        nearest = min(nearest, np.hypot(dx, p[k:, 1] - p[:-k, 1]).min())
    assert nearest >= d.max()


@pytest.mark.fast
def test_two_clouds_set_up(tmp_path, env):
    xy, d, setup = setup_case(str(tmp_path / "merge"), env)
    n = setup["grains_per_cloud"]
    assert len(xy) == 2 * n == 2 * 218
    assert np.allclose(d, 200e-6, rtol=1e-8)
    (x0, y0), (x1, y1) = setup["centres"]
    assert x0 == x1 == pytest.approx(0.5 * setup["width"])
    assert y1 - y0 == pytest.approx(10e-3, rel=1e-9)  # the trailing cloud above
    for k, c in enumerate(setup["centres"]):
        check_cloud(xy[k * n : (k + 1) * n], d[k * n : (k + 1) * n], np.array(c))
    gap = xy[n:, 1].min() - xy[:n, 1].max() - d.max()
    assert 10e-3 - 2 * R <= gap < 10e-3 - 2 * R + 1e-3


@pytest.mark.fast
def test_thesis_grain_size(tmp_path, env):
    """The thesis' 25 um grains: 13,939 discs per cloud."""
    xy, d, setup = setup_case(
        str(tmp_path / "fine"), env, "--clouds", "1", "--grain-diameter", "25e-6"
    )
    assert len(xy) == setup["grains_per_cloud"] == 13939
    check_cloud(xy, d, np.array(setup["centres"][0]))


@pytest.mark.fast
def test_drop_reference(tmp_path, env):
    """The pure-fluid reference's drop: its alpha.water sums to pi R^2
    within 1 %, at the cloud's mean density."""
    _, _, drop = setup_case(str(tmp_path / "drop"), env, "--drop", "--clouds", "1")
    assert drop["drop_area_ratio"] == pytest.approx(1, abs=0.01)
    assert drop["drop_density"] == pytest.approx(1030 + 0.2 * (2450 - 1030))


@pytest.mark.slow
def test_trailing_cloud_closes_the_gap(tmp_path, env):
    """Two clouds, R/h = 2, to 0.5 s (~4 s CPU): both fall, every grain kept
    in its cloud's count, each faster than one cloud alone on the same mesh
    (the pair's drag reduction), the trailing one faster than the leading
    one, so the gap between their grain sets closes."""
    pp = nscdpost.load_module("mergingPost", os.path.join(TUT, "postProcess.py"))
    hist = {}
    for name, clouds in (("pair", "2"), ("single", "1")):
        case = str(tmp_path / name)
        _, _, setup = setup_case(
            case,
            env,
            "--clouds",
            clouds,
            "--cells-per-radius",
            "2",
            "--height",
            str(30 * R),
            "--end",
            "0.5",
        )
        run("blockMesh", case, env)
        run("grainDeposit", case, env)
        run("vansFoam", case, env)
        hist[name] = pp.cloud_history(case)
    pair, single = hist["pair"], hist["single"]
    assert pair[-1]["time"] == pytest.approx(0.5)
    for row in pair:
        assert [c["grains"] for c in row["clouds"]] == [218, 218]
    fall = [pair[0]["clouds"][k]["centroid"] - pair[-1]["clouds"][k]["centroid"] for k in (0, 1)]
    alone = single[0]["clouds"][0]["centroid"] - single[-1]["clouds"][0]["centroid"]
    assert alone > 3e-3  # ~14 mm/s
    assert min(fall) > alone
    assert fall[1] > fall[0] + 0.25e-3  # the trailing cloud gains on the leading one (0.47 mm)
    gap = [r["clouds"][1]["lowest"] - r["clouds"][0]["highest"] for r in pair]
    assert gap[-1] < gap[0] - 0.5e-3
