"""Reduced dry 2D column collapse (tutorials/grainFoam/columnCollapse) against
the runout scaling of 2D columns.

Reference: Lube, Huppert, Sparks & Freundt (2005), Phys. Rev. E 72, 041301,
"Collapses of two-dimensional granular columns": (L_f - L_i)/L_i = 1.2 a for
a < 1.8 and 1.9 a^(2/3) for a > 2.8 (we join the two at a = 2.3).  Staron &
Hinch (2005, J. Fluid Mech. 545, 1-27) reproduce the experiments with contact
dynamics discs on a rough floor; the prefactor depends on the grains' friction
and on the column width in grains (finite-size effects, Man et al. 2021), so
the reduced case (500 discs, a column ~15 grains wide) is checked within 40 %.
"""
import json
import os
import shutil
import subprocess
import sys

import pytest

from foamcase import run

TUT = os.path.join(os.path.dirname(__file__), "..", "..", "tutorials", "grainFoam", "columnCollapse")


def test_column_collapse_runout(tmp_path, env):
    work = tmp_path / "cc"
    shutil.copytree(TUT, work, ignore=shutil.ignore_patterns("a[0-9]*", "results.json", "*.png", "log.*"))
    case = str(work / "a2")
    subprocess.run([sys.executable, str(work / "setupCase.py"), case, "2", "500"], check=True, env=env)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    subprocess.run([sys.executable, str(work / "postProcess.py"), case], check=True, env=env, cwd=work)
    res = json.load(open(work / "results.json"))["cases"][0]
    for key in ("aspect_ratio", "initial_width", "initial_height", "runout", "final_height"):
        assert key in res
    assert 1.7 < res["aspect_ratio"] < 2.7
    assert res["final_max_speed"] < 0.01, "deposit not at rest at the end"
    assert res["final_height"] < res["initial_height"]
    assert res["normalised_runout"] == pytest.approx(res["reference_normalised_runout"], rel=0.4)
