# SPDX-License-Identifier: GPL-3.0-or-later
"""grainDeposit's `initialVelocity` (system/grainDepositDict): the movable
grains of the written state start with a given velocity (a launched slide,
tutorials/vansInterFoam/lituyaBay's SLIDE_SPEED); fixed grains stay at rest.

Reference, independent of the code: the ballistic trajectory of a free body
under constant gravity, x(t) = x0 + v0 t + g t^2/2, v(t) = v0 + g t.  The
grain's velocity is exact at every step (constant force); its position
lags the parabola by at most |g| t dt / 2 (the step's explicit position
update), which the test allows.
"""

import os

import nscdpost
import numpy as np
import pytest
from foamcase import make_box_case, run, run_fatal_io

pytestmark = pytest.mark.fast

G = np.array([0.0, -9.81, 0.0])
V0 = np.array([0.3, 0.4, 0.0])  # [m/s]
X0 = np.array([0.2, 0.3, 0.005])  # [m]
D = 0.01  # [m]
T = 0.1  # [s]
DT = 1e-3  # [s]


def launched_case(case, deposit_extra, fixed=False):
    make_box_case(
        case,
        (0, 0, 0),
        (0.4, 0.4, 0.01),
        (8, 8, 1),
        G,
        {"glass": {"density": 2500, "friction": 0.3}},
        grains=[(*X0, D)],
        end_time=T,
        dt=DT,
        write_interval=T,
    )
    path = os.path.join(case, "system", "grainDepositDict")
    with open(path, "a") as fh:
        fh.write(deposit_extra + ("fixed yes;\n" if fixed else ""))


def test_launched_grain_follows_the_parabola(tmp_path, env):
    """A disc written with initialVelocity (0.3 0.4 0) m/s by grainDeposit,
    then run by grainFoam for 0.1 s in free flight: velocity v0 + g t
    within 1e-9 m/s, position on the parabola within |g| t dt / 2."""
    case = str(tmp_path / "launched")
    launched_case(case, "initialVelocity (0.3 0.4 0);\n")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    g0 = nscdpost.read_grains(case, "0")
    assert np.allclose(g0["U"][0], V0, atol=1e-12, rtol=0)
    run("grainFoam", case, env)
    g = nscdpost.read_grains(case, f"{T:g}")
    assert np.allclose(g["U"][0], V0 + G * T, atol=1e-9, rtol=0)
    x_exact = X0 + V0 * T + 0.5 * G * T**2
    assert np.linalg.norm(g["x"][0][:2] - x_exact[:2]) <= 0.5 * 9.81 * T * DT * (1 + 1e-6)


def test_fixed_grains_stay_at_rest(tmp_path, env):
    """With method list and `fixed yes`, initialVelocity leaves the fixed
    grains at rest (it launches the movable ones only)."""
    case = str(tmp_path / "fixed")
    launched_case(case, "initialVelocity (0.3 0.4 0);\n", fixed=True)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    g0 = nscdpost.read_grains(case, "0")
    assert g0["fixed"][0] and np.all(g0["U"][0] == 0)


def test_out_of_plane_velocity_in_2d_is_an_input_error(tmp_path, env):
    """A 2D case with a z component in initialVelocity stops on a
    FatalIOError naming the keyword and the fix."""
    case = str(tmp_path / "outOfPlane")
    launched_case(case, "initialVelocity (0 0 1);\n")
    run("blockMesh", case, env)
    out = run_fatal_io("grainDeposit", case, env)
    assert "initialVelocity" in out and "z component to 0" in out
