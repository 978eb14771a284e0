# SPDX-License-Identifier: GPL-3.0-or-later
"""Immersed vaporising droplet: a run stopped at a write time and
restarted, and a run on two ranks, reproduce the uninterrupted serial run
(droplet state in <time>/uniform/droplet, global sums over the ranks).
Case set-up in dropletcase.py."""

import os
import re

import nscdpost
import numpy as np
import pytest
from dropletcase import D, W, blowing_droplet_case, held_suspension_case, read_droplet
from foamcase import run

pytestmark = pytest.mark.fast


@pytest.mark.parametrize("release", ["uniform", "heatFlux"])
def test_restart_continues_exactly(tmp_path, env, release):
    """A run stopped at a write time and restarted (state from
    <time>/uniform/droplet: centre, velocity, mass, pending vapour; with
    vapourRelease heatFlux also the last heat sink) ends as the
    uninterrupted run, to 1e-9 relative on every droplet.dat column
    (reference: the uninterrupted run; fields are written with 17 digits).
    The droplet moves (moving yes, initial velocity) and blows, so the
    position, velocity, mass and lagged vapour all have to be restored."""
    import shutil

    dt = 0.01
    case = str(tmp_path / "full")
    blowing_droplet_case(
        case,
        env,
        6,
        dt,
        10,
        extra=f"velocity (0.004 -0.01 0);\nvapourRelease {release};\n",
        moving=True,
    )
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace(f"writeInterval {10 * dt};", f"writeInterval {5 * dt};")
    txt = txt.replace("adjustTimeStep yes;", "adjustTimeStep no;")  # same dt after restart
    open(cd, "w").write(txt)
    run("vansFoam", case, env)
    full = read_droplet(case)
    assert len(full) == 10
    assert abs(full[-1, 2] - W / 2) > 1e-4  # it did move (m)
    half = str(tmp_path / "half")
    shutil.copytree(case, half)
    shutil.rmtree(os.path.join(half, "0.1"))
    shutil.rmtree(os.path.join(half, "postProcessing"))
    assert os.path.isfile(os.path.join(half, "0.05", "uniform", "droplet"))
    run("vansFoam", half, env)
    rest = np.loadtxt(
        os.path.join(half, "postProcessing", "droplet", "0.05", "droplet.dat"), ndmin=2
    )
    assert len(rest) == 5
    assert np.allclose(rest, full[5:], rtol=1e-9, atol=1e-15)


def test_restart_with_grains_continues_exactly(tmp_path, env):
    """The grains' contact predictor of the droplet (vapourDroplet.H, "Gas
    drag of the grains inside") has a history (v^{n-1}, v^{n-2}, F^{n-1},
    dG^{n-1}, dt^{n-1}); it is written to <time>/uniform/droplet
    (grainHistory, the grains within 2 R + r_i of the centre).  A dense
    suspension of free 50 um grains in a held droplet (the case of
    test_dense_suspension_settles_steadily, inner quarter of the radius, gas
    nu = 2e-5), stopped at step 20 of 40 and restarted, ends as the
    uninterrupted run: every droplet.dat column and every grain velocity
    within 1e-9 relative (reference: the uninterrupted run; 17 digits
    written).  Without grainHistory the restart is NOT exact (asserted:
    grain velocities off by > 1e-6 relative; measured 1.3e-4, and 0 with
    it: bit-identical; the first step after the restart then runs without
    the predictor), so the test fails if the history is lost.  A history
    that does not fit the case's grains (a label out of range) is a
    FatalIOError naming grainHistory and the fix."""
    import shutil

    n = 40
    case = str(tmp_path / "full")
    grains, dt = held_suspension_case(case, env, 0.25, n, n // 2, 2e-5)
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace("adjustTimeStep yes;", "adjustTimeStep no;")
    open(cd, "w").write(txt)
    run("vansFoam", case, env)
    full = read_droplet(case)
    assert len(full) == n and np.all(full[:, 17] == len(grains))
    times = nscdpost.time_dirs(case)
    (t1, mid), (t2, last) = times[-2], times[-1]
    assert abs(t1 - dt * n / 2) < 1e-12 and abs(t2 - dt * n) < 1e-12
    u_full = nscdpost.read_grains(case, last)["U"]
    hist = open(os.path.join(case, mid, "uniform", "droplet")).read()
    assert "grainHistory" in hist

    def restart(name, edit_history=None, check=True):
        half = str(tmp_path / name)
        shutil.copytree(case, half)
        shutil.rmtree(os.path.join(half, last))
        shutil.rmtree(os.path.join(half, "postProcessing"))
        if edit_history:
            f = os.path.join(half, mid, "uniform", "droplet")
            txt = edit_history(open(f).read())
            open(f, "w").write(txt)
        p = run("vansFoam", half, env, check=check)
        if not check:
            return p
        rest = np.loadtxt(
            os.path.join(half, "postProcessing", "droplet", mid, "droplet.dat"), ndmin=2
        )
        return rest, nscdpost.read_grains(half, last)["U"]

    rest, u_rest = restart("half")
    scale = np.abs(u_full[:, :2]).max()
    err = np.abs(u_rest[:, :2] - u_full[:, :2]).max() / scale
    print(
        f"{len(grains)} grains, restart with history: max grain velocity error {err:.2e} "
        f"(relative to {scale:.3e} m/s)"
    )
    assert len(rest) == n // 2
    assert np.allclose(rest, full[n // 2 :], rtol=1e-9, atol=1e-15)
    assert err < 1e-9
    _, u_lost = restart("lost", lambda txt: txt[: txt.index("grainHistory")] + "\n")
    err_lost = np.abs(u_lost[:, :2] - u_full[:, :2]).max() / scale
    print(f"restart without grainHistory: max grain velocity error {err_lost:.2e}")
    assert err_lost > 1e-6
    # a history that does not fit the grains of the case: a clear error
    p = restart(
        "bad", lambda txt: re.sub(r"\bgrains\b[^;]*;", "grains (99999);", txt, count=1), check=False
    )
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "grainHistory" in out and "Fix" in out and "FOAM FATAL IO ERROR" in out, out[-2000:]


@pytest.mark.mpi
@pytest.mark.parametrize("release", ["uniform", "heatFlux"])
def test_parallel_matches_serial(tmp_path, env, release):
    """Two ranks (the droplet straddles the processor boundary x = w/2): the
    droplet.dat columns equal the serial run's to 1e-8 relative (reference:
    the serial run; the overlaps are exact on every rank and Q_f, F, the
    ring weights are global sums; with vapourRelease heatFlux the heat sink
    is gathered onto all ranks and the droplet sits low, 0.8 D above the
    hot bottom wall, so that the release is not symmetric)."""
    import shutil

    dt, n_steps = 0.01, 5
    case = str(tmp_path / "serial")
    centre = None if release == "uniform" else (2 * D, 0.8 * D)
    blowing_droplet_case(
        case, env, 6, dt, n_steps, centre=centre, extra=f"vapourRelease {release};\n"
    )
    par = str(tmp_path / "par")
    shutil.copytree(case, par)
    # the droplet needs every grain on every rank (vansFoam README, Parallel)
    with open(os.path.join(par, "constant", "grainProperties"), "a") as f:
        f.write("grainDecomposition replicated;\n")
    run("vansFoam", case, env)
    from foamcase import run_parallel

    run_parallel("vansFoam", par, env, n=2)
    a, b = read_droplet(case), read_droplet(par)
    assert a.shape == b.shape
    assert np.allclose(a[:, :13], b[:, :13], rtol=1e-8, atol=1e-18)
    # forces F_p, F_pen (grain-droplet force): the penalisation force is a sum
    # of the end-of-step U, equal to the U solver tolerance (1e-6 relative)
    F = np.abs(a[:, 13:17]).max()
    assert np.allclose(a[:, 13:17], b[:, 13:17], rtol=1e-6, atol=1e-6 * F)
    assert np.array_equal(a[:, 17], b[:, 17])
