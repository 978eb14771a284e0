# SPDX-License-Identifier: GPL-3.0-or-later
"""grainDeposit method rain (2D, applications/utilities/grainDeposit/
rainDeposit.H): discs laid one by one and rolled to rest on the discs below
(the rain model of Visscher & Bolsterli, Nature 239, 504-507, 1972), the
settle started from the top-down static contact forces (nscd/StaticLoad.H,
`staticLoad yes`; the default `no` settles from zero impulses).
Checked against the model's definition and against statics, not against
the code:
  - geometry (the model): no two discs overlap, every disc lies in the
    box, and every disc rests on the floor or on two bodies laid before it
    (discs or a side wall) with its centre between them;
  - statics: after the settle the floor and the side walls hold the bed's
    weight (vertical force balance from the written contact impulses).
"""

import os

import nscdpost
import numpy as np
import pytest
from foamcase import log_message, run, run_fatal_io, write
from test_grainDeposit_replicate import WIDTH, D, box_case, wall_lift, weight

pytestmark = pytest.mark.fast

NUMBER = 300
TOUCH = 1e-9 * D  # touching (positions written with 15 digits)


def rain_case(tmp_path, env, name, settle=True, number=NUMBER, height=0.06):
    case = str(tmp_path / name)
    box_case(
        case,
        WIDTH,
        height,
        "wallPatches (walls);\n",
        f"method rain;\nbox {{ min (0 0 0); max ({WIDTH} {height} 1); }}\nnumber {number};\n"
        f"dMin {0.9 * D};\nsizeRatio {1 / 0.9:.6g};\nseed 3;\nwriteContactImpulses yes;\nstaticLoad yes;\n"
        + ("settle { maxTime 0.05; deltaT 5e-4; speedTolerance 2e-3; }\n" if settle else ""),
        tolerance=1e-6,
    )
    write(
        os.path.join(case, "system", "controlDict"),
        "dictionary",
        "controlDict",
        "application grainDeposit; startFrom startTime; startTime 0; stopAt endTime;\n"
        "endTime 1; deltaT 1e-3; writeControl timeStep; writeInterval 1;\n"
        "writePrecision 15;\n",
    )
    run("blockMesh", case, env)
    return case


@pytest.fixture(scope="module")
def laid(tmp_path_factory, env):
    case = rain_case(tmp_path_factory.mktemp("rain"), env, "laid", settle=False)
    run("grainDeposit", case, env)
    return case


def test_rain_deposit_is_the_rain_model(laid):
    """Every disc of the deposit as written (laying order, no settle) rests
    on the floor or on two earlier bodies (discs, side walls) with its
    centre between them, inside the box, and overlaps nothing."""
    g = nscdpost.read_grains(laid, "0")
    x, y, r = g["x"][:, 0], g["x"][:, 1], 0.5 * g["d"]
    n = len(r)
    assert n == NUMBER
    assert np.all(x - r >= -TOUCH) and np.all(x + r <= WIDTH + TOUCH) and np.all(y - r >= -TOUCH)
    gap = np.hypot(x[:, None] - x[None, :], y[:, None] - y[None, :]) - (r[:, None] + r[None, :])
    np.fill_diagonal(gap, np.inf)
    assert gap.min() > -TOUCH
    for i in range(n):
        if y[i] - r[i] < TOUCH:
            continue  # on the floor
        below = [x[j] for j in range(i) if gap[i, j] < TOUCH]
        if x[i] - r[i] < TOUCH:
            below.append(0.0)  # the left wall
        if WIDTH - x[i] - r[i] < TOUCH:
            below.append(WIDTH)
        assert len(below) >= 2, f"disc {i} at ({x[i]:.6g}, {y[i]:.6g}) rests on {len(below)} bodies"
        assert min(below) - TOUCH <= x[i] <= max(below) + TOUCH, (
            f"disc {i} is not between its supports"
        )


def test_rain_deposit_settles_on_its_walls(tmp_path, env):
    """After the settle (tolerance 1e-6 d_min) the walls hold the bed's
    weight: vertical force balance of the written contact impulses.  The
    log reports the seeded static load."""
    case = rain_case(tmp_path, env, "settled")
    log = run("grainDeposit", case, env).stdout
    m = log_message(log, r"Static load: (\d+) contacts seeded, (\d+) grains not balanced")
    assert int(m.group(1)) >= NUMBER
    assert wall_lift(case) == pytest.approx(weight(case), rel=5e-3)


def test_compliant_rain_deposit_is_written_loaded(tmp_path, env):
    """A compliant bed (relativeCompliance 5e-2) carries its weight by
    overlaps of up to ~8 overlapTolerance r_min at its bottom: grainDeposit
    writes it with its contact impulses by default (without `writeContactImpulses`) and
    the written state passes the initial-overlap check (each overlap is its
    contact's law under its load, nscd System::checkInitialOverlaps); the
    walls hold the bed's weight (statics, as the hard bed above)."""
    case = rain_case(tmp_path, env, "compliant")
    for name, old, new in (
        ("constant/grainProperties", "friction", "relativeCompliance 5e-2; friction"),
        ("system/grainDepositDict", "writeContactImpulses yes;", ""),
        ("system/grainDepositDict", "staticLoad yes;", ""),
        # at rest to 2e-5 m/s: the compliant bed's slow mode (its weight
        # loading the springs) outlasts the 2e-3 m/s of the hard bed
        ("system/grainDepositDict", "maxTime 0.05;", "maxTime 0.5;"),
        ("system/grainDepositDict", "speedTolerance 2e-3;", "speedTolerance 2e-5;"),
    ):
        path = os.path.join(case, name)
        text = open(path).read()
        assert old in text, (name, old)
        open(path, "w").write(text.replace(old, new, 1))
    run("grainDeposit", case, env)
    g = nscdpost.read_grains(case, "0")
    y, r = g["x"][:, 1], 0.5 * g["d"]
    assert np.max(r - y) > 2e-3 * r.min()  # floor overlaps beyond overlapTolerance (1e-3 r_min)
    assert wall_lift(case) == pytest.approx(weight(case), rel=5e-3)


def test_rain_deposit_above_the_box_is_an_error(tmp_path, env):
    case = rain_case(tmp_path, env, "tall", settle=False, number=2000, height=0.02)
    out = run_fatal_io("grainDeposit", case, env)
    assert "rises to y" in out and "fewer grains" in out
    assert not os.path.exists(os.path.join(case, "0", "grainState.h5"))
