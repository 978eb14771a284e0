# SPDX-License-Identifier: GPL-3.0-or-later
"""Immersed vaporising droplet: a run stopped at a write time and
restarted, and a run on two ranks, reproduce the uninterrupted serial run
(droplet state in <time>/uniform/droplet, the grains' predictor history in
<time>/grainState.h5, global sums over the ranks).
Case set-up in dropletcase.py."""

import os
import re

import h5py
import nscdpost
import numpy as np
import pytest
from dropletcase import (
    D,
    W,
    blowing_droplet_case,
    held_suspension_case,
    read_droplet,
    replicated_copy,
    rerun_from,
)
from foamcase import fails_with, run

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


def _set_end_time(case, end):
    cd = os.path.join(case, "system", "controlDict")
    txt = re.sub(r"endTime\s+[^;]+;", f"endTime {end};", open(cd).read())
    open(cd, "w").write(txt.replace("adjustTimeStep yes;", "adjustTimeStep no;"))


def test_restart_from_an_unscheduled_write(tmp_path, env):
    """The droplet's state is written with the fields at every write, not only
    at the scheduled ones: a run that ends off the write grid (endTime 0.07,
    writeInterval 0.1: the last step is written by runTime.writeNow(), the
    same path as a SIGTERM/SIGUSR1 stop, grainRunControl::writeStep) has
    0.07/uniform/droplet, and continued to 0.1 it ends as the uninterrupted
    run, to 1e-9 relative on every droplet.dat column (reference: the
    uninterrupted run).  Before, the file was written only at scheduled
    write times, so such a restart silently started a fresh droplet."""
    import shutil

    dt = 0.01
    case = str(tmp_path / "full")
    extra = "velocity (0.004 -0.01 0);\n"
    blowing_droplet_case(case, env, 6, dt, 10, extra=extra, moving=True)
    _set_end_time(case, 10 * dt)
    stopped = str(tmp_path / "stopped")
    shutil.copytree(case, stopped)
    run("vansFoam", case, env)
    full = read_droplet(case)
    assert len(full) == 10
    _set_end_time(stopped, 0.07)
    run("vansFoam", stopped, env)
    assert os.path.isfile(os.path.join(stopped, "0.07", "uniform", "droplet"))
    _set_end_time(stopped, 10 * dt)
    run("vansFoam", stopped, env)
    rest = np.loadtxt(
        os.path.join(stopped, "postProcessing", "droplet", "0.07", "droplet.dat"), ndmin=2
    )
    assert len(rest) == 3
    assert np.allclose(rest, full[7:], rtol=1e-9, atol=1e-15)


HISTORY = (
    "dropletPrevVelocity",
    "dropletPrevForce",
    "dropletPrevVelocity2",
    "dropletGasForceChange",
)


def _h5(case, t):
    """Every dataset of <t>/grainState.h5 (name -> array)."""
    with h5py.File(os.path.join(case, t, "grainState.h5"), "r") as f:
        return {k: f[k][()] for k in f if isinstance(f[k], h5py.Dataset)}


def _old_format(case, t):
    """Rewrite <t>/uniform/droplet and <t>/grainState.h5 as written before
    the predictor history was a restart column: per-grain lists in
    grainHistory (every grain, labels in the state's order, shortest
    round-trip decimals) and no history datasets in the state."""
    f = os.path.join(case, t, "uniform", "droplet")
    txt = open(f).read()
    dt = re.search(r"grainHistory\s*\{[^}]*\bdt\s+(\S+);", txt).group(1)
    with h5py.File(os.path.join(case, t, "grainState.h5"), "a") as h:
        cols = [h[c][()] for c in HISTORY]
        for c in HISTORY:
            del h[c]

    def vectors(a):
        return "(" + " ".join(f"({x!r} {y!r} {z!r})" for x, y, z in a.tolist()) + ")"

    names = ("velocity", "force", "velocity2", "gasForceChange")
    lists = "".join(f"{k} {vectors(c)};\n" for k, c in zip(names, cols))
    n = len(cols[0])
    old = f"grainHistory\n{{\ndt {dt};\ngrains {n}({' '.join(map(str, range(n)))});\n{lists}}}"
    open(f, "w").write(re.sub(r"grainHistory\s*\{[^}]*\}", lambda _: old, txt))


def test_restart_with_grains_continues_exactly(tmp_path, env):
    """The grains' contact predictor of the droplet (vapourDroplet.H, "Gas
    drag of the grains inside") has a history (v^{n-1}, v^{n-2}, F^{n-1},
    dG^{n-1} per grain: restart columns of grainState.h5; dt^{n-1}:
    grainHistory of <time>/uniform/droplet).  A dense suspension of free
    50 um grains in a held droplet (the case of
    test_dense_suspension_settles_steadily, inner quarter of the radius, gas
    nu = 2e-5), stopped at step 20 of 40 and restarted, ends as the
    uninterrupted run (reference: the uninterrupted run): every dataset of
    the last grainState.h5, the history columns included, bit for bit, and
    every droplet.dat column to 1e-9 relative (the droplet's state is read
    back from ascii).  Without grainHistory the restart is NOT
    exact (asserted: grain velocities off by > 1e-6 relative; measured
    8.2e-4; the first step after the restart then runs without the
    predictor), so the test fails if the history is lost.  A restart file
    written before the history was a column (per-grain lists in
    grainHistory, no datasets) still reads, bit for bit.  A list history
    that does not fit the case's grains (a label out of range), or a
    grainHistory whose state lacks the columns, is a FatalIOError naming
    grainHistory and the fix."""

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
    assert "grainHistory" in hist and "velocity2" not in hist
    state_full = _h5(case, last)
    assert all(state_full[c].shape == (len(grains), 3) for c in HISTORY)
    assert np.abs(state_full["dropletPrevForce"]).max() > 0

    def restart(name, edit=None, check=True):
        half = str(tmp_path / name)
        rest, p = rerun_from(case, half, mid, last, env, edit, check)
        if not check:
            return p
        return rest, nscdpost.read_grains(half, last)["U"], _h5(half, last)

    def edit_droplet(f):
        def edit(half):
            path = os.path.join(half, mid, "uniform", "droplet")
            txt = open(path).read()  # (read before open(path, "w") truncates it)
            open(path, "w").write(f(txt))

        return edit

    for name, edit in (("half", None), ("oldFormat", lambda h: _old_format(h, mid))):
        rest, _, state = restart(name, edit)
        assert len(rest) == n // 2
        # the droplet's own state passes through ascii uniform/droplet
        assert np.allclose(rest, full[n // 2 :], rtol=1e-9, atol=1e-15), name
        assert state.keys() == state_full.keys(), name
        for k, a in state_full.items():
            nan = a.dtype.kind == "f"  # (adiabatic walls: NaN temperature)
            assert np.array_equal(a, state[k], equal_nan=nan), (name, k)
        print(f"{len(grains)} grains, restart ({name}): grainState.h5 bit-identical")
    scale = np.abs(u_full[:, :2]).max()
    no_history = edit_droplet(lambda txt: txt[: txt.index("grainHistory")] + "\n")
    _, u_lost, _ = restart("lost", no_history)
    err_lost = np.abs(u_lost[:, :2] - u_full[:, :2]).max() / scale
    print(f"restart without grainHistory: max grain velocity error {err_lost:.2e}")
    assert err_lost > 1e-6

    # a history that does not fit the grains of the case, or a state
    # without the history columns: a clear error
    def bad_label(half):
        _old_format(half, mid)
        edit_droplet(lambda t: re.sub(r"\bgrains\b[^;]*;", "grains (99999);", t, count=1))(half)

    def no_columns(half):
        with h5py.File(os.path.join(half, mid, "grainState.h5"), "a") as h:
            del h[HISTORY[0]]

    for edit, why in ((bad_label, "does not match"), (no_columns, "lacks them")):
        p = restart(edit.__name__, edit, check=False)
        fails_with(p, "grainHistory", why, "Fix:", banner="FOAM FATAL IO ERROR")


@pytest.mark.mpi
@pytest.mark.parametrize("release", ["uniform", "heatFlux"])
def test_parallel_matches_serial(tmp_path, env, release):
    """Two ranks (the droplet straddles the processor boundary x = w/2): the
    droplet.dat columns equal the serial run's to 1e-8 relative (reference:
    the serial run; the overlaps are exact on every rank and Q_f, F, the
    ring weights are global sums; with vapourRelease heatFlux the heat sink
    is gathered onto all ranks and the droplet sits low, 0.8 D above the
    hot bottom wall, so that the release is not symmetric)."""

    dt, n_steps = 0.01, 5
    case = str(tmp_path / "serial")
    centre = None if release == "uniform" else (2 * D, 0.8 * D)
    blowing_droplet_case(
        case, env, 6, dt, n_steps, centre=centre, extra=f"vapourRelease {release};\n"
    )
    par = str(tmp_path / "par")
    replicated_copy(case, par)
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
