# SPDX-License-Identifier: GPL-3.0-or-later
"""Grain-only gate (grainProperties `gates`, src/grainCloud) and the
granularCollapse tutorial (tutorials/vansInterFoam/granularCollapse, thesis
section 5.2).

References:
- Gate kinematics: the gate wall moves with its prescribed velocity over
  [startTime, endTime]: displacement = velocity (min(t, endTime) -
  startTime) exactly (to round-off, 1e-12 m), also when startTime is not on
  a time step (the velocity is weighted by the part of the step inside the
  window).
- Gate holding a column (static check): no grain crosses the gate plane
  beyond the contact overlap tolerance (1e-6 d) while the gate is closed and
  the grains come to rest; after the lift the column collapses through the
  opening (grains beyond the gate).
- Regimes: Sarlin et al. (2021, JFM 919 R6), quoted in thesis section 5.2:
  Fr_f < 0.35 nonlinear transition, 0.35-0.87 solitary, > 0.87 bore; the
  three tutorial configurations (reduced: 20 mm cells, 0.5 m basin) must
  land in their regimes, with Fr_f = v_f / sqrt(g h0) from the granularFront
  function object.
"""

import math
import os

import nscdpost
import numpy as np
import pytest
from foamcase import copy_tutorial, make_box_case, run, run_allrun, tutorial_modules

pytestmark = pytest.mark.slow

G = 9.81
D = 0.009
GATE = 0.05


def gate_case(tmp_path, gates):
    grains = [
        (0.0055 + 0.0097 * i + (0.0024 if j % 2 else 0), 0.0047 + 0.0095 * j, 0, D)
        for j in range(6)
        for i in range(5 if j % 2 == 0 else 4)
    ]
    case = str(tmp_path / "gate")
    make_box_case(
        case,
        (0, 0, 0),
        (0.2, 0.1, 0.01),
        (8, 4, 1),
        (0, -G, 0),
        {"glass": {"density": 2500, "friction": 0.5}},
        grains=grains,
        end_time=0.4,
        dt=1e-3,
        write_interval=0.05,
        extra_props="gates {\n" + gates + "\n}\n",
    )
    return case


def test_gate_holds_then_lifts_exactly(tmp_path, env):
    t0, t1, v = 0.2005, 0.2705, 1.0  # start not on a step (dt = 1e-3)
    case = gate_case(
        tmp_path,
        f"gate {{ start ({GATE} 0 0); end ({GATE} 0.1 0); "
        f"velocity (0 {v} 0); startTime {t0}; endTime {t1}; }}",
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    p = run("grainFoam", case, env)
    assert "1 gates" in p.stdout
    # held: nothing beyond the gate, at rest before the lift
    for t in ("0.05", "0.1", "0.15", "0.2"):
        g = nscdpost.read_grains(case, t)
        assert np.max(g["x"][:, 0] + g["d"] / 2) < GATE + 1e-6 * D, t
    # the column behind the gate is static (a free disc may still roll on
    # top of the pile: rolling discs without rolling resistance never stop)
    g = nscdpost.read_grains(case, "0.2")
    speed = np.linalg.norm(g["U"], axis=1)
    assert np.mean(speed < 1e-4) > 0.9 and speed.max() < 0.1, speed
    # kinematics: displacement after every step (gates.dat)
    gd = nscdpost.read_step_data(case, "gates")
    assert len(gd["Time"]) == 400
    for t, dx, dy, dz in zip(gd["Time"], gd["gate_x"], gd["gate_y"], gd["gate_z"]):
        expected = v * min(max(t - t0, 0.0), t1 - t0)
        assert abs(dy - expected) < 1e-12 and dx == 0 and dz == 0, t
    # released: the column collapses through the opening
    g = nscdpost.read_grains(case, "0.4")
    assert np.max(g["x"][:, 0]) > GATE + 2 * D


def test_gate_state_restart(tmp_path, env):
    """The gate's displacement is part of the state: a restart from a time
    after the lift continues from the moved gate (no second gate added)."""
    case = gate_case(
        tmp_path,
        f"gate {{ start ({GATE} 0 0); end ({GATE} 0.1 0); "
        "velocity (0 1 0); startTime 0.05; endTime 0.1; }",
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read()
    open(cd, "w").write(txt.replace("endTime 0.4;", "endTime 0.1;"))
    run("grainFoam", case, env)
    open(cd, "w").write(txt.replace("endTime 0.4;", "endTime 0.12;"))
    run("grainFoam", case, env)
    # the restarted run's rows (read_step_data joins them after the first's)
    assert nscdpost.read_step_data(case, "gates")["gate_y"][-1] == pytest.approx(0.05, abs=1e-12)


@pytest.mark.parametrize(
    "gates,key",
    [
        ("gate { start (0.05 0 0); end (0.05 0.1 0); velocity (0 1 0); startTme 0; }", "startTme"),
        ("gate { start (0.05 0 0); end (0.05 0 0); velocity (0 1 0); }", "coincide"),
        ("gate { start (0.05 0 0); end (0.05 0.1 0); velocity (0 1 1); }", "z component"),
        ("gate { start (0.05 0 0); end (0.05 0.1 0); velocity (0 1 0); friction -1; }", "friction"),
    ],
)
def test_gate_keyword_checks(tmp_path, env, gates, key):
    case = gate_case(tmp_path, gates)
    run("blockMesh", case, env)
    p = run("grainDeposit", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0 and key in out and "grainProperties" in out, out[-1500:]


@pytest.mark.parametrize("gate_friction", [None, 0.0], ids=["material", "smooth"])
def test_gate_friction_spins_a_disc(tmp_path, env, gate_friction):
    """A disc pressed against a rising gate by g_x = 2 m/s^2 on a
    frictionless floor: the gate's friction mu m g_x on the disc's side
    spins it (I = m r^2/2: the contact point accelerates at 2 mu g_x) until
    its contact point moves with the gate, then it rolls: omega = v/r for
    t >= v/(2 mu g_x) = 0.01 s (rigid-body mechanics; material friction 0.5,
    v = 0.02 m/s: the gate's lower end, 2 mm up at 0.1 s, stays below the
    contact point).  A smooth gate (friction 0) leaves it without spin.  The
    centre stays on the floor (the friction, m g_x mu = 0.1 m g, is below
    the weight)."""
    r, v = 0.005, 0.02
    mu = 0.5 if gate_friction is None else gate_friction
    extra = "" if gate_friction is None else f" friction {gate_friction};"
    case = str(tmp_path / "gateFriction")
    make_box_case(
        case,
        (0, 0, 0),
        (0.2, 0.1, 0.01),
        (8, 4, 1),
        (2.0, -G, 0),
        {"glass": {"density": 2500, "friction": 0.5}},
        grains=[(GATE - r, r, 0, 2 * r)],
        end_time=0.1,
        dt=1e-3,
        write_interval=0.1,
        extra_props="wallFriction { walls 0; }\n"
        f"gates {{ gate {{ start ({GATE} 0 0); end ({GATE} 0.1 0); velocity (0 {v} 0);"
        f" startTime 0; endTime 1;{extra} }} }}\n",
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    path = os.path.join(case, "0.1", "grainState.h5")
    omega = nscdpost.read_h5(path, "angularVelocities", 3)[0]
    x = nscdpost.read_h5(path, "positions", 3)[0]
    expected = v / r if mu > 0 else 0.0
    assert omega[2] == pytest.approx(expected, abs=1e-3 * v / r), omega
    assert abs(x[1] - r) < 1e-6 * r and abs(x[0] - (GATE - r)) < 1e-6 * r, x


def test_regime_classification():
    """Bounds of Sarlin et al. (2021) as quoted in thesis section 5.2, and
    thesis Table 5.1's Fr_f of the three PFEM-DEM runs in their regimes."""
    _, post = tutorial_modules("vansInterFoam", "granularCollapse")
    assert post.regime(0.0) == post.regime(0.3499) == "nonlinear_transition"
    assert post.regime(0.35) == post.regime(0.87) == "solitary"
    assert post.regime(0.8701) == post.regime(5) == "bore"
    for config, row in post.TABLE_5_1.items():
        assert post.regime(row["thesis"]) == post.EXPECTED_REGIME[config]
        assert post.regime(row["sarlin"]) == post.EXPECTED_REGIME[config]
    with pytest.raises(ValueError):
        post.regime(float("nan"))
    # piston bore: weak limit A -> h0 Fr for Fr -> 0 (linear long wave)
    a = post.piston_bore_amplitude(0.01 * math.sqrt(G * 0.1), 0.1)
    assert a == pytest.approx(0.1 * 0.01, rel=0.02)


def test_three_regimes(tmp_path, env):
    """Reduced tutorial (20 mm cells = 4 d, 0.5 m basin, 0.25 s), run by its
    own `./Allrun 0.02 0.5 0.25` (blockMesh, setFields, grainDeposit,
    vansInterFoam, foamToVTK, postProcess.py, snapshot PNGs; the checks of
    test_tutorialAllruns.py through foamcase.run_allrun): the three
    configurations give Fr_f in their three regimes (Sarlin et al. 2021)
    and a wave (positive elevation at the first gauge)."""
    _, post = tutorial_modules("vansInterFoam", "granularCollapse")
    work = copy_tutorial("vansInterFoam", "granularCollapse", str(tmp_path / "granularCollapse"))
    res = run_allrun(work, env, ["0.02", "0.5", "0.25"], "results.json", "*/*_alpha.water_t*.png")
    for config, expected in post.EXPECTED_REGIME.items():
        r = res[config]
        assert r["regime"] == expected, (config, r["front_froude_number"])
        assert r["max_wave_amplitude"] > 0, config
        assert os.path.isfile(os.path.join(work, f"{config}.png"))
    # the water volume sum(eps alpha V) may only change through the
    # atmosphere (no overflow here): conserved to 1e-6 relative
    for config in post.EXPECTED_REGIME:
        vol = nscdpost.read_step_data(os.path.join(work, config), "waterVolume")["waterVolume"]
        assert len(vol) > 10
        assert max(abs(v - vol[0]) for v in vol) < 1e-6 * vol[0], config


def test_gate_3d_rectangle(tmp_path, env):
    """3D: the gate is the vertical rectangle start-end swept over the mesh
    depth; a sphere pushed against it by g_x stays behind it (no overlap
    beyond 1e-6 d) until the lift, then rolls past (x beyond the gate)."""
    case = str(tmp_path / "gate3d")
    r = 0.005
    make_box_case(
        case,
        (0, 0, 0),
        (0.1, 0.05, 0.04),
        (4, 2, 2),
        (2.0, -G, 0),
        {"glass": {"density": 2500, "friction": 0.5}},
        grains=[(0.04, r, 0.02, 2 * r)],
        end_time=0.3,
        dt=1e-3,
        write_interval=0.1,
        two_d=False,
        extra_props="gates { gate { start (0.05 0 0); end (0.05 0.05 0);"
        " velocity (0 1 0); startTime 0.1; endTime 0.2; } }\n",
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    g = nscdpost.read_grains(case, "0.1")
    assert g["x"][0, 0] + r < 0.05 + 1e-6 * 2 * r
    assert g["x"][0, 0] + r > 0.05 - 1e-6  # it reached the gate
    assert nscdpost.read_step_data(case, "gates")["gate_y"][-1] == pytest.approx(0.1, abs=1e-12)
    g = nscdpost.read_grains(case, "0.3")
    assert g["x"][0, 0] > 0.05 + r
