# SPDX-License-Identifier: GPL-3.0-or-later
"""Reduced dry 2D column collapse (tutorials/grainFoam/columnCollapse) against
the runout scaling of 2D columns.

Reference: Lube, Huppert, Sparks & Freundt (2005), Phys. Rev. E 72, 041301,
"Collapses of two-dimensional granular columns": (L_f - L_i)/L_i = 1.2 a for
a < 1.8 and 1.9 a^(2/3) for a > 2.8 (we join the two at a = 2.3).  Staron &
Hinch (2005, J. Fluid Mech. 545, 1-27) reproduce the experiments with contact
dynamics discs on a rough floor; the prefactor depends on the grains' friction
and on the column width in grains (finite-size effects, Man et al. 2021), so
the reduced cases (500 discs, a = 0.5 and 2) are checked for the scaling
with a (ratio of the two runouts 0.9-1.7 x the law's: the measured spread
under solver-tolerance perturbations, 1.24-1.52, with its margin) and for the
prefactor within a band [0.7, 1.8] x the law.
"""

import json
import os
import shutil
import subprocess
import sys

import pytest
from foamcase import run

pytestmark = pytest.mark.slow

TUT = os.path.join(
    os.path.dirname(__file__), "..", "..", "tutorials", "grainFoam", "columnCollapse"
)


def _run(work, env, a, n):
    case = str(work / f"a{a}")
    subprocess.run(
        [sys.executable, str(work / "setupCase.py"), case, str(a), str(n)], check=True, env=env
    )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    return case


def test_column_collapse_runout(tmp_path, env):
    work = tmp_path / "cc"
    shutil.copytree(
        TUT, work, ignore=shutil.ignore_patterns("a[0-9]*", "results.json", "*.png", "log.*")
    )
    cases = [_run(work, env, a, 500) for a in (0.5, 2)]
    subprocess.run(
        [sys.executable, str(work / "postProcess.py"), *cases], check=True, env=env, cwd=work
    )
    res = json.load(open(work / "results.json"))["cases"]
    for r in res:
        for key in ("aspect_ratio", "initial_width", "initial_height", "runout", "final_height"):
            assert key in r
        # the front has stopped (grains may still roll down the free surface)
        assert abs(r["runout_change_last_interval"]) < 0.5 * r["mean_diameter"]
        assert r["final_height"] < r["initial_height"] * 1.001
        # prefactor band: free-rolling 2D discs (no rolling resistance) run out
        # further than the quasi-2D experiments; the full tutorial (1500 discs)
        # measures 1.5-1.6 x the law for a = 0.5, 2 and 6.
        ratio = r["normalised_runout"] / r["reference_normalised_runout"]
        assert 0.7 < ratio < 1.8, ratio
    # the scaling with a: runout(a~2)/runout(a~0.5) against the law's.  The
    # narrow reduced columns (~15 grains wide) run out relatively further at
    # a = 2 (finite-size effect; the tutorial's 1500 discs: 1.14 x the law's
    # scaling).  Measured with 500 discs, the same set-up perturbed at the
    # solver-tolerance level (2026-11-23): 1.27 (as is), 1.29 (reorderInterval
    # 0), 1.24 / 1.41 (contact tolerance 5e-6 / 2e-5 instead of 1e-5), 1.52
    # (before the relax stage of nscd, which no longer turns overlap
    # corrections into velocity): the band is that spread plus its margin.
    lo, hi = res
    measured = hi["normalised_runout"] / lo["normalised_runout"]
    law = hi["reference_normalised_runout"] / lo["reference_normalised_runout"]
    assert 0.9 * law < measured < 1.7 * law, (measured, law)
    # short columns barely lose height (Lube et al.: H_f = H_i for a < 1.15)
    assert lo["final_height"] == pytest.approx(lo["initial_height"], rel=0.1)
