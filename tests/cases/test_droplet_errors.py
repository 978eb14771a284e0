# SPDX-License-Identifier: GPL-3.0-or-later
"""Immersed vaporising droplet: bad input - constant/dropletProperties
and couplingProperties grainPorosity are keyword-checked (FatalIOErrors naming
the file, the keyword and the fix).  Case set-up in dropletcase.py."""

import os
import re

import pytest
from dropletcase import droplet_case
from foamcase import run

pytestmark = pytest.mark.fast


@pytest.mark.parametrize(
    "edit, words",
    [
        (lambda s: s.replace("latentHeat", "latentHeet"), ["latentHeet", "dropletProperties"]),
        (lambda s: re.sub(r"latentHeat \S+;\n", "", s), ["latentHeat", "Missing keyword"]),
        (lambda s: s.replace("diameter", "radius 1e-3;\ndiameter"), ["radius", "diameter"]),
        (
            lambda s: s.replace("liquidDensity 1000.0", "liquidDensity -1"),
            ["liquidDensity", "positive"],
        ),
        (lambda s: s + "liquidViscosity -2e-4;\n", ["liquidViscosity", "positive"]),
        (lambda s: s + "vapourRelease bottom;\n", ["vapourRelease", "heatFlux", "grains"]),
        (lambda s: s + "absorbedGrains rigid;\n", ["absorbedGrains", "carried"]),
    ],
)
def test_keyword_errors(tmp_path, env, edit, words):
    """constant/dropletProperties is keyword-checked: unknown, missing,
    contradictory or non-positive entries are FatalIOErrors naming the file
    and the keyword."""
    case = str(tmp_path / "err")
    droplet_case(case, env, 2, end_time=0.01, dt=0.01, blowing=False, rho_l=1000.0)
    dp = os.path.join(case, "constant", "dropletProperties")
    txt = edit(open(dp).read())
    open(dp, "w").write(txt)
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "FOAM FATAL IO ERROR" in out
    for w in words:
        assert w in out, out[-1500:]


@pytest.mark.parametrize(
    "extra, words",
    [
        ("filmConduction yes;\n", ["filmConduction", "surfaceTension"]),
        (
            "surfaceTension 0.05891;\nfilmConduction yes;\nvapourViscosity -1;\n",
            ["vapourViscosity", "positive"],
        ),
    ],
)
def test_film_keyword_errors(tmp_path, env, extra, words):
    """filmConduction without the capillary barrier (no load for the film)
    and a non-positive vapourViscosity are FatalIOErrors naming the file,
    the keyword and the fix."""
    case = str(tmp_path / "err")
    droplet_case(case, env, 2, end_time=0.01, dt=0.01, blowing=False, rho_l=1000.0, extra=extra)
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "FOAM FATAL IO ERROR" in out and "dropletProperties" in out
    for w in words:
        assert w in out, out[-1500:]


@pytest.mark.parametrize("value", ["1", "-0.1"])
def test_grain_porosity_keyword_error(tmp_path, env, value):
    """couplingProperties grainPorosity must be in [0, 1): FatalIOError naming
    the keyword and the file."""
    case = str(tmp_path / "err")
    droplet_case(
        case,
        env,
        2,
        end_time=0.01,
        dt=0.01,
        blowing=False,
        rho_l=1000.0,
        coupling=f"grainPorosity {value};\n",
    )
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0 and "FOAM FATAL IO ERROR" in out
    assert "grainPorosity" in out and "couplingProperties" in out
