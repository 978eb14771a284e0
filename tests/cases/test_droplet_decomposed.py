# SPDX-License-Identifier: GPL-3.0-or-later
"""The immersed vaporising droplet (vapourDropletSource) with the grains
decomposed over the ranks (grainDecomposition decomposed, the default of a
parallel run): each rank sums the droplet's grain terms (absorbed volume
V_p, the linear-force sums C, W, Bv, the grain force F_p, the grains
inside) over the grains it owns and the sums are reduced, so that the
droplet is the same on every rank; every copy of a grain (owner and
ghosts) gets the same force, its predictor history travelling with it as
grain columns.

References, independent of the decomposition:
  - the serial run of the same case (undecomposed grains and mesh): a hot,
    blowing droplet released downwards across the processor boundary
    x = w/2 with free grains inside and around it, the droplet.dat columns
    on 2 ranks against serial;
  - Newton's third law across the ranks: F_p (sum over every grain once)
    equals minus the sum of the forces on the grains (the reconstructed
    state's fluid forces are not that sum: the droplet's force is checked
    through droplet.dat's Fg column, computed on the grains' owners);
  - no grain lost or duplicated (the reconstructed cloud holds every id
    once).
"""

import os
import shutil

import nscdpost
import numpy as np
import pytest
from dropletcase import DEPTH, T_D, D, droplet_case, read_droplet
from foamcase import replace_in, run, run_parallel

DT, N_STEPS = 5e-4, 12


def _grains():
    """Free grains of 0.1-0.2 mm, no two within contact reach: nine inside
    the droplet (centre (2D, 2D), radius D/2) on both sides of x = 2D, two
    straddling its surface and two outside, below it (it moves onto them)."""
    c, R0 = 2 * D, D / 2
    at = [
        (c + fx * R0, c + fy * R0)
        for fx, fy in (
            (-0.6, 0.1),
            (-0.3, -0.4),
            (-0.05, 0.3),
            (0.04, -0.1),
            (0.2, 0.5),
            (0.35, -0.3),
            (0.6, 0.05),
            (-0.2, -0.75),
            (0.15, 0.8),
            (1.0, 0.0),
            (-0.98, -0.1),
            (0.1, -1.4),
            (-0.3, -1.6),
        )
    ]
    dgs = [1e-4, 1.5e-4, 2e-4]
    return [(x, y, DEPTH / 2, dgs[k % 3]) for k, (x, y) in enumerate(at)]


def _case(path, env, extra="", grains=None):
    """A droplet (water, 2.5 mm) released at u_d = (1, -3) cm/s into a
    box of walls at 500 C (blowing, uniform release, gravity on), free hot
    grains (T_D + 300 K), 12 cells per D, to DT * N_STEPS = 6 ms (~140
    steps: the blowing's Courant number limits dt below DT)."""
    droplet_case(
        path,
        env,
        12,
        end_time=DT * N_STEPS,
        dt=DT,
        blowing=True,
        rho_l=958.0,
        gravity=9.81,
        grains=_grains() if grains is None else grains,
        T_grains=T_D + 300,
        fixed_grains=False,
        write_interval=DT * N_STEPS / 2,
        moving=True,
        extra="velocity (0.01 -0.03 0);\nliquidViscosity 2.82e-4;\n" + extra,
    )


@pytest.fixture(scope="module")
def runs(tmp_path_factory, env):
    base = tmp_path_factory.mktemp("dropletDecomposed")
    serial = str(base / "serial")
    _case(serial, env)
    par = str(base / "np2")
    shutil.copytree(serial, par)
    run("vansFoam", serial, env)
    p = run_parallel("vansFoam", par, env, n=2)
    assert "grains decomposed over 2 ranks" in p.stdout
    run("reconstructPar", par, env)
    return serial, par


@pytest.mark.fast
@pytest.mark.mpi
def test_droplet_on_decomposed_grains_matches_serial(runs):
    """droplet.dat on 2 ranks with decomposed grains against the serial run:
    state, heat and vapour (time to V_p, 13 columns) to 1e-8 relative, the
    grains inside identical, F_p and the grain-force sum Fg to 1e-6 of their
    largest value (the penalisation force F_pen is a sum of the end-of-step
    U, equal to the U solver's tolerance, as with replicated grains), and
    F_p = -Fg on the ranks' owned grains to 1e-12 (Newton's third law).
    Measured 2026-11-28: 1.7e-10 (Q_p), forces 5.7e-12; 11 grains inside,
    6 and 7 owned by the ranks; a ghost counted in the sums would change
    the grains inside and V_p."""
    serial, par = runs
    a, b = read_droplet(serial), read_droplet(par)
    assert a.shape == b.shape and len(a) >= N_STEPS
    # the droplet overlaps grains on both ranks all along
    assert np.all(a[:, 17] >= 9), a[:, 17]
    assert np.array_equal(a[:, 17], b[:, 17])
    assert np.all(a[:, 12] > 0) and np.all(a[1:, 11] > 0)  # V_p, Vdot (none before the first heat)
    assert np.allclose(a[:, :13], b[:, :13], rtol=1e-8, atol=1e-18)
    F = np.abs(a[:, 13:17]).max()
    assert np.allclose(a[:, 13:17], b[:, 13:17], rtol=1e-6, atol=1e-6 * F)
    fs, fp = nscdpost.read_step_data(serial, "droplet"), nscdpost.read_step_data(par, "droplet")
    for k in ("Fg_x", "Fg_y"):
        scale = np.abs(fs[k]).max()
        assert scale > 0
        assert np.allclose(fs[k], fp[k], rtol=0, atol=1e-6 * scale)
    Fp = b[:, 13:15]
    Fg = np.column_stack([fp["Fg_x"], fp["Fg_y"]])
    assert np.allclose(Fp, -Fg, rtol=0, atol=1e-12 * np.abs(Fp).max())


@pytest.mark.fast
@pytest.mark.mpi
def test_grains_follow_the_serial_run(runs):
    """The grains (reconstructed, by id) at the last write are where the
    serial run puts them to 1e-6 of a diameter and none is lost or
    duplicated (measured 2026-11-28: 4.9e-14 m, the grains moving up to
    0.29 mm); their temperatures agree to 1e-6 K."""
    serial, par = runs
    t = nscdpost.time_dirs(serial)[-1][1]
    gs, gp = nscdpost.read_grains(serial, t), nscdpost.read_grains(par, t)
    n = len(_grains())
    assert sorted(gp["grainId"]) == list(range(n))
    os_, op = np.argsort(gs["grainId"]), np.argsort(gp["grainId"])
    dx = np.max(np.abs(gs["x"][os_] - gp["x"][op]))
    moved = np.max(np.abs(gs["x"][os_] - np.array(_grains())[:, :3]))
    print(f"max |x - x_serial| = {dx:.2e} m; largest displacement {moved:.2e} m")
    assert moved > 1e-3 * 1e-4
    assert dx < 1e-6 * 1e-4
    if "T" in gs:
        assert np.allclose(gs["T"][os_], gp["T"][op], rtol=0, atol=1e-6)


@pytest.mark.fast
@pytest.mark.mpi
def test_serial_restart_from_the_decomposed_run(runs, env, tmp_path):
    """A serial run restarted from the 2-rank run's middle write
    (reconstructed: the droplet's uniform/droplet and the grains' state with
    the predictor's history columns gathered from the ranks) continues the
    uninterrupted serial run: its droplet.dat rows equal the serial run's to
    1e-8 relative (reference: the serial run; the history is per grain id,
    so a grain's columns must have followed it across the ranks)."""
    serial, par = runs
    times = nscdpost.time_dirs(par)
    assert len(times) == 3
    mid, last = times[1][1], times[2][1]
    half = str(tmp_path / "half")
    shutil.copytree(par, half, ignore=shutil.ignore_patterns("processor*", "postProcessing"))
    shutil.rmtree(os.path.join(half, last))
    with open(os.path.join(half, mid, "uniform", "droplet")) as f:
        assert "grainHistory" in f.read()
    run("vansFoam", half, env)
    a = read_droplet(serial)
    b = np.loadtxt(os.path.join(half, "postProcessing", "droplet", mid, "droplet.dat"), ndmin=2)
    a = a[a[:, 0] > float(mid) + 1e-12]
    assert a.shape == b.shape and len(b) > 2
    assert np.allclose(a[:, :13], b[:, :13], rtol=1e-8, atol=1e-18)
    F = np.abs(a[:, 13:17]).max()
    assert np.allclose(a[:, 13:17], b[:, 13:17], rtol=1e-6, atol=1e-6 * F)


def _row_under():
    """Eleven hot discs of 0.15 mm in a row 20 um under the droplet's lowest
    point, across x = 2D (the droplet moves onto them)."""
    c, R0, dg = 2 * D, D / 2, 1.5e-4
    return [(c + k * 1.6 * dg, c - R0 - dg / 2 - 2e-5, DEPTH / 2, dg) for k in range(-5, 6)]


#: the droplet settings with per-grain lists beyond the default model:
#: dropletProperties lines, the grains (None: _grains()) and the contact
#: solver's tolerance (the barrier's contacts: the 2-rank solve differs from
#: the serial one by the tolerance, 1e-8 gives 2.6e-6 in F_c, 1e-12 2.7e-9)
SETTINGS = {
    "vapourReleaseGrains": ("vapourRelease grains;\n", None, None),
    "liquidConductivity": ("liquidConductivity 0.679;\n", None, None),
    "barrierAndFilm": ("surfaceTension 0.05891;\nfilmConduction yes;\n", _row_under, "1e-12"),
}


@pytest.mark.slow
@pytest.mark.mpi
@pytest.mark.parametrize("setting", list(SETTINGS))
def test_settings_on_decomposed_grains_match_serial(tmp_path, env, setting):
    """The droplet's settings that keep per-grain lists (each grain's vapour
    heat, the liquid's extra conductance, the capillary barrier with the
    Leidenfrost film: an nscd droplet whose contacts each grain's owner
    solves, its film heat computed there) on 2 ranks with decomposed grains
    against the serial run: droplet.dat's state, heat and vapour (time to
    V_p) to 1e-8 relative, the capillary force F_c and the film heat Q_film
    to 1e-7 of their largest value.  Measured 2026-11-28: 1.0e-10 (grains'
    release), 8.3e-10 (liquid conductivity), 2.6e-11, F_c 2.7e-9, Q_film
    3.7e-10 (barrier and film, contact tolerance 1e-12)."""
    extra, grains, tolerance = SETTINGS[setting]
    serial, par = str(tmp_path / "serial"), str(tmp_path / "np2")
    _case(serial, env, extra=extra, grains=grains() if grains else None)
    if tolerance:
        gp = os.path.join(serial, "constant", "grainProperties")
        replace_in(gp, ("tolerance 1e-08", f"tolerance {tolerance}"))
    shutil.copytree(serial, par)
    run("vansFoam", serial, env)
    p = run_parallel("vansFoam", par, env, n=2)
    assert "grains decomposed over 2 ranks" in p.stdout
    a, b = read_droplet(serial), read_droplet(par)
    assert a.shape == b.shape
    assert np.allclose(a[:, :13], b[:, :13], rtol=1e-8, atol=1e-18)
    # F_c (22, 23) and Q_film (24): nonzero with the barrier and the film
    for k in (22, 23, 24):
        scale = np.abs(a[:, k]).max()
        assert np.abs(a[:, k] - b[:, k]).max() <= 1e-7 * scale
    if tolerance:
        assert np.abs(a[:, 23]).max() > 0 and np.abs(a[:, 24]).max() > 0
