# SPDX-License-Identifier: GPL-3.0-or-later
"""Force-chain pictures (src/python/nscdrender.py --chains): the grains as
discs and one segment per grain-grain contact carrying a normal force,
drawn from the grain state <time>/grainState.h5.

Independent reference: nscd's datasets of the same file (src/nscd/src/IO.cpp
layout) read with h5py directly, not through nscdpost: the grain-grain rows
of /contactBodies (second body below the grain count) whose normal impulse
(/contactData column 6) is positive.  Case: the 2 x 3 stack of discs of the
fault tests on the floor of a 4 x 4 box, grainDeposit then grainFoam to
0.02 s (well under a second); its vertical contacts carry the stack's
weight, its horizontal ones none."""

import os
import subprocess
import sys

import h5py
import matplotlib.image as mpimg
import nscdrender
import numpy as np
import pytest
from faultcase import stack
from foamcase import run

pytestmark = pytest.mark.fast


@pytest.fixture(scope="module")
def settled(tmp_path_factory, env):
    case = stack(tmp_path_factory.mktemp("chains"), "stack")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    return case


def _force_carrying(h5):
    """(pairs, normal impulses) of the grain-grain contacts with rn > 0."""
    with h5py.File(h5, "r") as f:
        n = len(f["radii"])
        ij, cd = f["contactBodies"][()], f["contactData"][()]
    keep = (ij[:, 1] < n) & (cd[:, 6] > 0)
    return ij[keep], cd[keep, 6], len(ij)


def test_segments_are_the_force_carrying_contacts(settled, tmp_path):
    h5 = os.path.join(settled, "0.02", "grainState.h5")
    pairs, rn, n_all = _force_carrying(h5)
    # the stack: 2 columns of 3 discs, 2 loaded contacts per column; the
    # unloaded side-by-side and the wall contacts are not drawn
    assert len(pairs) == 4 and n_all > len(pairs)
    png = str(tmp_path / "chains.png")
    drawn = nscdrender.draw_force_chains(h5, png, "stack")
    assert drawn == len(pairs)
    px = mpimg.imread(png)
    assert px.shape[1] == 1200 and px.shape[0] > 400
    # the read used for the picture: same pairs, forces rn / dt
    s = nscdrender.read_force_chains(h5)
    np.testing.assert_array_equal(s["pairs"], pairs)
    with h5py.File(h5, "r") as f:
        dt = f["time"][1]
    np.testing.assert_allclose(s["fn"], rn / dt, rtol=1e-15)


def test_command_line_renders_the_stepped_times(settled, tmp_path, env):
    """`python3 -m nscdrender --chains`: one PNG per stepped time (0 is the
    deposit, no contacts), named after the case and the time."""
    p = subprocess.run(
        [sys.executable, "-m", "nscdrender", "--chains", "-n", "5", "-o", str(tmp_path), settled],
        capture_output=True,
        text=True,
        env=env,
    )
    assert p.returncode == 0, p.stderr
    assert sorted(os.listdir(tmp_path)) == [
        "stack_forceChains_t0.01.png",
        "stack_forceChains_t0.02.png",
    ]


def test_chains_without_a_stepped_state_say_what_to_run(tmp_path, env):
    p = subprocess.run(
        [sys.executable, "-m", "nscdrender", "--chains", str(tmp_path)],
        capture_output=True,
        text=True,
        env=env,
    )
    assert p.returncode == 1
    assert "grainState.h5" in p.stderr and str(tmp_path) in p.stderr, p.stderr
