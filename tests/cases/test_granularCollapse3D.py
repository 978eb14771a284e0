# SPDX-License-Identifier: GPL-3.0-or-later
"""The 3D granular collapse into water on MPI ranks
(tutorials/vansInterFoam/granularCollapse3D), reduced: the tutorial's own
`./Allrun 0.02 2 2 0.02 0.4` (a slice 0.02 m wide settled for 0.4 s, two
copies across a 0.04 m channel, 0.02 s on 2 ranks with the grains decomposed).

References (conservation laws and geometry, no fitted numbers):
- the copies: copy k of the slice is the slice shifted by k W_s across the
  channel, every other one mirrored about the plane it shares with its
  neighbour (z -> (k + 1) W_s - z_s), so the spheres of two copies meet at
  most at that plane and the state starts with no new overlap;
- the sphere count is conserved (no outlet; a sphere leaving the mesh
  stops the run);
- the water volume sum(eps alpha V) changes only by the water that left
  through the atmosphere: conserved to 1e-6 relative (vansInterFoam's
  waterVolume.dat).
"""

import json
import os

import nscdpost
import numpy as np
import pytest
from foamcase import copy_tutorial, run_allrun

pytestmark = [pytest.mark.slow, pytest.mark.mpi]


def test_reduced_allrun_on_two_ranks(tmp_path, env):
    work = copy_tutorial(
        "vansInterFoam", "granularCollapse3D", str(tmp_path / "granularCollapse3D")
    )
    # its postProcess.py uses the 2D tutorial's regime and piston-bore functions
    copy_tutorial("vansInterFoam", "granularCollapse", str(tmp_path / "granularCollapse"))
    res = run_allrun(
        work,
        env,
        ["0.02", "2", "2", "0.02", "0.4"],
        "case/results.json",
        "case/case_alpha.water_t*.png",
    )
    slab = os.path.join(work, "slab")
    case = os.path.join(work, "case")
    ws = json.load(open(os.path.join(slab, "slab.json")))["width"]
    xs = nscdpost.read_h5(os.path.join(slab, "0", "grainState.h5"), "positions", 3)
    x = nscdpost.read_h5(os.path.join(case, "0", "grainState.h5"), "positions", 3)
    n = len(xs)
    assert len(x) == 2 * n and res["grains_initial"] == 2 * n
    # copy 0 as settled, copy 1 mirrored about z = W_s
    assert np.allclose(x[:n, :2], xs[:, :2], rtol=0, atol=1e-9)  # the list: 10 digits
    assert np.allclose(x[:n, 2], xs[:, 2], rtol=0, atol=1e-9)
    assert np.allclose(x[n:, 2], 2 * ws - xs[:, 2], rtol=0, atol=1e-9)
    # conservation over the run
    assert res["grains_final"] == res["grains_initial"]
    assert res["water_volume_max_relative_change"] < 1e-6
    assert res["end_time"] == pytest.approx(0.02, abs=1e-6)
    log = open(os.path.join(case, "log.vansInterFoam")).read()
    assert "grains decomposed over 2 ranks" in log
