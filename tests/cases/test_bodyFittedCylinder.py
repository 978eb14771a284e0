# SPDX-License-Identifier: GPL-3.0-or-later
"""tests/bench/cylinderFreeMotion/bodyFitted.py, the body-fitted OpenFOAM
reference of the falling cylinder (pimpleFoam, sixDoFRigidBodyMotion): on a
coarse O-grid the modes mesh, run a few steps and post-process.  A
consistency check of the bench script, no physics: the reference values
(fixed C_D 1.326 and St 0.185 against Henderson 1995 and Williamson 1996;
the free cylinder's 2.51 cm/s against Namkoong et al. 2008) are measured in
tests/bench/results/cylinderFreeMotionBodyFitted.json."""

import json
import math
import os
import subprocess
import sys

import pytest

pytestmark = pytest.mark.fast

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCRIPT = os.path.join(ROOT, "tests", "bench", "cylinderFreeMotion", "bodyFitted.py")


def _run(args, cwd, env):
    r = subprocess.run(args, cwd=str(cwd), env=env, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, (args, r.stdout[-2000:], r.stderr[-2000:])
    return r.stdout


@pytest.mark.parametrize("mode", ["fixed", "free", "forced"])
def test_body_fitted_cylinder_runs(tmp_path, env, mode):
    case = tmp_path / mode
    # 40 cells around, 20 radially, 0.05 s
    _run([sys.executable, SCRIPT, "setup", mode, str(case), "40", "0.05"], tmp_path, env)
    _run(["blockMesh"], case, env)
    assert "Mesh OK" in _run(["checkMesh"], case, env)
    if mode == "fixed":
        _run(["setFields"], case, env)
    _run(["pimpleFoam"], case, env)
    out = tmp_path / "out.json"
    _run([sys.executable, SCRIPT, "post", str(out), "%s:%s" % (mode, case)], tmp_path, env)
    rows = json.load(open(out))["modes"][mode]["per_half_second"]
    assert rows and all(math.isfinite(x) for x in rows[0])
    if mode == "free":
        assert rows[0][2] > 0  # it falls
    if mode == "forced":
        # the sway written is the one asked for: the free light cylinder's
        lift = json.load(open(out))["modes"][mode]["forced_lift"]
        assert lift["amplitude_over_D"] == pytest.approx(0.092)
        assert lift["strouhal_forced"] == pytest.approx(0.167)
        assert all(math.isfinite(v) for v in lift.values())
