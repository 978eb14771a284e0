# SPDX-License-Identifier: GPL-3.0-or-later
"""The coupling's per-grain restart state as columns of the grain system
(vansCloud::declareGrainColumns: grainHeldFraction, grainContactImpulse,
grainDragImpulseDefect, nscd::ColumnRestart | ColumnMigrate |
ColumnOptional): datasets of <time>/grainState.h5 that follow their grains
through the removal of grains at an outlet and a restart.  Serial =
parallel for these columns: test_vansFoam_decomposed.py; a case written
before they were columns (uniform/ lists): test_vansFoam.py."""

import os

import h5py
import numpy as np
import pytest
from faultcase import MAT, G, open_bottom_cube
from foamcase import log_message, run

pytestmark = pytest.mark.fast

COLUMNS = ("grainHeldFraction", "grainContactImpulse", "grainDragImpulseDefect")
#: glass spheres (x, y, z, d) sinking through water in a 4 cm box whose
#: bottom (inlet) is an outlet for the grains: grain 0 leaves in ~0.045 s,
#: grains 1 and 2 (other sizes, so other velocities) sink freely
GRAINS = [
    (0.01, 0.006, 0.02, 0.01),
    (0.03, 0.033, 0.02, 0.008),
    (0.02, 0.03, 0.03, 0.006),
]


def state(case, t):
    """Grain ids and the restart columns of <t>/grainState.h5, by id."""
    with h5py.File(os.path.join(case, t, "grainState.h5"), "r") as f:
        ids = f["grainIds"][()]
        order = np.argsort(ids)
        return ids[order], {c: f[c][()][order] for c in COLUMNS}


def test_restart_columns_follow_their_grains_through_removal_and_restart(tmp_path, env):
    """After grain 0 leaves through the outlet (grains 1, 2 renumbered 0,
    1), the state holds one row per remaining grain of each restart column,
    and the values are those of the grains: a freely sinking grain has no
    contact impulse (|p^n| = |m (v - v^n) - dt (F + m g) - J_drag| < 1e-9
    m g dt; a row of another grain, with another v^n, would be ~m g dt) and
    is not held (theta < 1e-9).  A restart from the write after the removal ends as the
    uninterrupted run: fields, grains and the columns bit for bit."""
    case = str(tmp_path / "full")
    open_bottom_cube(case, env, GRAINS, end=0.09, write_interval=0.03, outlet=True)
    out = run("vansFoam", case, env).stdout
    left = log_message(
        out,
        r"grainOutlets: 1 grains \(mass \S+ kg\) left through inlet at time (\S+), ids 0;",
        every=True,
    )
    assert len(left) == 1 and 0.03 < float(left[0]) < 0.06, out[-3000:]
    ids, cols = state(case, "0.03")
    assert list(ids) == [0, 1, 2]
    for t in ("0.06", "0.09"):
        ids, cols = state(case, t)
        assert list(ids) == [1, 2], t
        assert cols["grainHeldFraction"].shape == (2,)
        assert cols["grainContactImpulse"].shape == cols["grainDragImpulseDefect"].shape == (2, 3)
        for k, (_, _, _, d) in enumerate(GRAINS[1:]):
            m = MAT["glass"]["density"] * np.pi / 6 * d**3
            impulse = np.linalg.norm(cols["grainContactImpulse"][k])
            print(f"[ t={t} grain {k + 1} ] |p^n| / (m g dt) = {impulse / (m * G * 1e-3):.2e}")
            assert impulse < 1e-9 * m * G * 1e-3, (t, k)
            assert 0 <= cols["grainHeldFraction"][k] < 1e-9, (t, k)
        assert not os.path.exists(os.path.join(case, t, "uniform", "grainHeldFraction"))

    restart = str(tmp_path / "restart")
    import shutil

    shutil.copytree(case, restart)
    shutil.rmtree(os.path.join(restart, "0.09"))
    run("vansFoam", restart, env)
    for f in ("U", "p", os.path.join("lagrangian", "grains", "positions")):
        a = open(os.path.join(case, "0.09", f)).read()
        assert a == open(os.path.join(restart, "0.09", f)).read(), f
    ida, a = state(case, "0.09")
    idb, b = state(restart, "0.09")
    assert list(ida) == list(idb)
    for c in COLUMNS:
        assert np.array_equal(a[c], b[c]), c
