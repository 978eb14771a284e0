# SPDX-License-Identifier: GPL-3.0-or-later
"""Physics of dry grains run through grainDeposit + grainFoam (NSCD, thesis ch. 2).

References (rigid-body mechanics, e.g. Goldstein, Classical Mechanics):
  a disc (I = m r^2/2) on an incline of angle theta rolls without slipping
  (contact point sticks) with a = (2/3) g sin(theta) when tan(theta) < 3 mu, and
  slides with a = g (sin(theta) - mu cos(theta)) when tan(theta) > 3 mu; for a
  sphere (I = 2/5 m r^2) the limits are 5/7 g sin(theta) and tan(theta) < 7/2 mu.
  A hard grain without restitution stops on impact (normal velocity 0).
"""

import math
import os
import shutil

import nscdpost
import numpy as np
import pytest
from foamcase import make_box_case, run, set_contact_tolerance

G = 9.81


def incline_case(tmp_path, env, theta_deg, mu, two_d):
    th = math.radians(theta_deg)
    r = 0.005
    case = str(tmp_path / f"incline_{theta_deg}_{mu}_{'2d' if two_d else '3d'}")
    make_box_case(
        case,
        (0, 0, 0),
        (1.0, 0.05, 0.05 if not two_d else 0.01),
        (20, 2, 2),
        (G * math.sin(th), -G * math.cos(th), 0),
        {"steel": {"density": 7800, "friction": mu}},
        grains=[(0.05, r, 0.025 if not two_d else 0.0, 2 * r)],
        end_time=0.3,
        dt=1e-3,
        write_interval=0.1,
        two_d=two_d,
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    t, name = nscdpost.time_dirs(case)[-1]
    g = nscdpost.read_grains(case, name)
    return g["U"][0][0] / t, g["x"][0][1] - r


@pytest.mark.fast
@pytest.mark.parametrize("two_d", [True, False], ids=["disc", "sphere"])
@pytest.mark.parametrize("theta,mu", [(30, 0.1), (30, 0.5), (20, 0.05)])
def test_incline(tmp_path, env, two_d, theta, mu):
    th = math.radians(theta)
    k = 3.0 if two_d else 3.5  # rolling limit tan(theta) < k mu
    if math.tan(th) < k * mu:
        expected = (2.0 / 3.0 if two_d else 5.0 / 7.0) * G * math.sin(th)
    else:
        expected = G * (math.sin(th) - mu * math.cos(th))
    a, lift = incline_case(tmp_path, env, theta, mu, two_d)
    assert a == pytest.approx(expected, rel=0.01)
    assert abs(lift) < 1e-3 * 0.005  # stays on the plane, no overlap


@pytest.mark.fast
def test_drop_no_rebound_no_overlap(tmp_path, env):
    """A disc dropped from 5 cm stops on the floor: zero normal velocity after
    impact (no restitution, eq. 2.33) and no overlap beyond 1e-3 r."""
    r = 0.005
    case = str(tmp_path / "drop")
    make_box_case(
        case,
        (0, 0, 0),
        (0.1, 0.1, 0.01),
        (4, 4, 1),
        (0, -G, 0),
        {"glass": {"density": 2500, "friction": 0.4}},
        grains=[(0.05, 0.055, 0, 2 * r)],
        end_time=0.25,
        dt=1e-3,
        write_interval=0.01,
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    landed = 0
    for t, name in nscdpost.time_dirs(case):
        g = nscdpost.read_grains(case, name)
        y, vy = g["x"][0][1], g["U"][0][1]
        assert y - r > -1e-3 * r, f"overlap with the floor at t={t}: {y - r}"
        if t > math.sqrt(2 * 0.05 / G) + 0.01:
            landed += 1
            assert abs(vy) < 1e-9, f"rebound/normal velocity at t={t}: {vy}"
            assert abs(y - r) < 1e-3 * r
    assert landed >= 10


def _deposit_dict(lo, hi, n, dmin=2e-3, lam=1.2):
    return (
        f"material glass;\nmethod box;\nbox {{ min ({lo[0]} {lo[1]} {lo[2]}); max ({hi[0]} {hi[1]} {hi[2]}); }}\n"
        f"number {n};\ndMin {dmin};\nsizeRatio {lam};\nseed 3;\n"
        "settle { maxTime 2; deltaT 5e-4; speedTolerance 2e-3; }\n"
    )


@pytest.mark.slow
@pytest.mark.parametrize("two_d", [True, False], ids=["discs", "spheres"])
def test_dense_pile_stays_at_rest(tmp_path, env, two_d):
    """A settled pile stays at rest: after 0.2 s of grainFoam (the deposit is
    handed over at rest when its grains move slower than 2 mm/s), no grain
    creeps by more than 1 % of d_min over the next 0.2 s, and the largest
    overlap stays below 1e-3 d_min (hard contacts).  Poured at tolerance
    1e-6, held at 1e-8; measured (2026-11-27): creep 4.8e-5 (discs) and
    2.6e-4 (spheres) d_min, largest overlap 3e-5 and 3.8e-5 d_min."""
    case = str(tmp_path / ("pile2d" if two_d else "pile3d"))
    hi = (0.04, 0.06, 0.004 if two_d else 0.02)
    n = 300 if two_d else 250
    make_box_case(
        case,
        (0, 0, 0),
        hi,
        (4, 6, 2),
        (0, -G, 0),
        {"glass": {"density": 2500, "friction": 0.4}},
        grains=[],
        end_time=0.4,
        dt=5e-4,
        write_interval=0.2,
        two_d=two_d,
        deposit=_deposit_dict((0, 0, 0), hi, n),
        contact_tolerance=1e-6,
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    # poured at the library's default tolerance 1e-6 (a hard pour at 1e-8
    # needs ~1,000 sweeps a step), held at 1e-8: the creep bound is the run's
    set_contact_tolerance(case, 1e-8)
    run("grainFoam", case, env)
    times = nscdpost.time_dirs(case)
    g0 = nscdpost.read_grains(case, times[-2][1])
    g1 = nscdpost.read_grains(case, times[-1][1])
    drift = np.max(np.linalg.norm(g1["x"] - g0["x"], axis=1))
    assert drift < 0.01 * 2e-3, f"creep {drift} m"
    overlaps = nscdpost.read_step_data(case, "grainStatistics")["maxOverlap"]
    assert len(overlaps) and max(overlaps) < 1e-3


@pytest.mark.slow
def test_restart_is_bit_identical(tmp_path, env):
    """A collapsing pile run to 0.1 s in one go equals 0.05 s + restart from the
    written state + 0.05 s, to the last digit written (17 significant digits)."""
    case = str(tmp_path / "full")
    hi = (0.08, 0.06, 0.004)
    make_box_case(
        case,
        (0, 0, 0),
        hi,
        (8, 6, 1),
        (0, -G, 0),
        {"glass": {"density": 2500, "friction": 0.4}},
        grains=[],
        end_time=0.1,
        dt=5e-4,
        write_interval=0.05,
        deposit=_deposit_dict((0, 0, 0), (0.02, 0.06, 0.004), 150).replace(
            "settle {", "settle { temporaryWalls ( { point (0.02 0 0); normal (-1 0 0); } );"
        ),
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    restart = str(tmp_path / "restart")
    shutil.copytree(case, restart)
    shutil.rmtree(os.path.join(restart, "0.1"))
    run("grainFoam", restart, env)  # startFrom latestTime = 0.05
    a = open(os.path.join(case, "0.1", "lagrangian", "grains", "positions")).read()
    b = open(os.path.join(restart, "0.1", "lagrangian", "grains", "positions")).read()
    ga = nscdpost.read_grains(case, "0.1")
    assert np.max(np.linalg.norm(ga["U"], axis=1)) > 0.05, "the pile should be moving"
    assert a == b
