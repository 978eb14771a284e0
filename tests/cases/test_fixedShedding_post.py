# SPDX-License-Identifier: GPL-3.0-or-later
"""fixedShedding.py post (tutorials/vansFoam/cylinderSedimentation) on a case
without the grains' fluid force at its write times: a clear exit naming the
missing file and the fix (reconstructPar for a decomposed run), not a
traceback.  An input check, no physics; the shedding analysis itself is
measured in tests/bench/results/cylinderFixedWalls12.json."""

import os
import subprocess
import sys

import pytest

pytestmark = pytest.mark.fast

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPT = os.path.join(ROOT, "tutorials", "vansFoam", "cylinderSedimentation", "fixedShedding.py")


def _post(case):
    return subprocess.run(
        [sys.executable, SCRIPT, "post", str(case)],
        capture_output=True,
        text=True,
        cwd=str(case.parent),
        timeout=120,
    )


@pytest.mark.parametrize("decomposed", [False, True])
def test_post_without_grain_forces_names_the_fix(tmp_path, decomposed):
    case = tmp_path / "case"
    (case / "0.05").mkdir(parents=True)
    if decomposed:
        (case / "processor0").mkdir()
    r = _post(case)
    assert r.returncode != 0
    assert "Traceback" not in r.stderr
    assert "lagrangian/grains/Ffluid" in r.stderr
    if decomposed:
        assert "reconstructPar" in r.stderr
    else:
        assert "reconstructPar" not in r.stderr
    assert not (tmp_path / "shedding.json").exists()
