# SPDX-License-Identifier: GPL-3.0-or-later
"""Immersed vaporising droplet, vapourRelease grains (src/dropletCoupling/
README.md "The model", Blowing): the vapour of the heat Q_i each grain gives
the droplet is released in the cells of that grain by its exact overlaps,
the gas's share Q_f over the ring as in uniform.  One hot fixed grain
(diameter 0.8 cell, T_d + 300 K) straddles the lower surface of a held,
blowing droplet (16 cells per D, walls and gas at T_d, open top), so the
droplet's heat is mostly the grain's.  Case set-up in dropletcase.py."""

import os
import shutil

import h5py
import nscdpost
import numpy as np
import pytest
from dropletcase import (
    DEPTH,
    T_D,
    D,
    blowing_droplet_case,
    read_droplet,
    replicated_copy,
    rerun_from,
)
from foamcase import fails_with, run, run_parallel

pytestmark = pytest.mark.fast

N_PER_D, DT, N_STEPS = 16, 0.005, 6
W_BOX = 4 * D
H = D / N_PER_D
CENTRE = (W_BOX / 2, W_BOX / 2)
# a grain smaller than the cells, as in the tutorial's bed (cells of 1.7 d):
# its cells keep their gas (void fraction >= 0.7), where the vapour goes
DG = 0.8 * H
# centred on the droplet's lower surface (R = 0.5 D): half of it inside;
# it straddles the cell faces x = w/2 (the ranks' boundary of the MPI test)
GRAIN = (W_BOX / 2 + 0.1 * H, W_BOX / 2 - 0.49 * D, DEPTH / 2, DG)


def hot_grain_case(case, env, release, n_steps=N_STEPS, write_every=1, grain=GRAIN):
    blowing_droplet_case(
        case,
        env,
        N_PER_D,
        DT,
        n_steps,
        rho_l=1e6,  # constant radius over the run
        centre=CENTRE,
        T_w=T_D,
        grains=[grain],
        fixed_grains=True,
        T_grains=T_D + 300,
        write_interval=DT * write_every,
        extra=f"vapourRelease {release};\n",
    )
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace("adjustTimeStep yes;", "adjustTimeStep no;")
    open(cd, "w").write(txt)


def grain_cells():
    """Mask of the cells (blockMesh order) whose square meets the grain
    disc with a positive area: the nearest point of the square is inside
    the disc (geometry, independent of the overlap library)."""
    n = 4 * N_PER_D
    xs = (np.arange(n) + 0.5) * H
    xc, yc = np.tile(xs, n), np.repeat(xs, n)
    gx, gy, r = GRAIN[0], GRAIN[1], DG / 2
    px = np.clip(gx, xc - H / 2, xc + H / 2)
    py = np.clip(gy, yc - H / 2, yc + H / 2)
    return (px - gx) ** 2 + (py - gy) ** 2 < r * r * (1 - 1e-9)


def volume_source(case, time_name):
    return nscdpost.read_internal_field(os.path.join(case, time_name, "dropletVolumeSource"))


def test_grain_release_conserves_and_locates(tmp_path, env):
    """Conservation of the vapour volume (mass balance of eq. 4.16, rho_v
    Vdot = mass vaporised in the previous step): at every step sum_c q_c V_c
    = Vdot of droplet.dat to 1e-9, and at the first step with vapour (step
    2: both runs identical up to then) the total equals the uniform mode's
    to 1e-12 relative, whatever the distribution.  Location (reference: the
    grain's cells from geometry and the uniform run's ring): at step 2,
    with p = Q_p/(Q_p + Q_f) of step 1, the vapour outside the grain's cells
    is (1 - p) times the uniform run's there, cell by cell (1e-9: the gas's
    share over the ring, none of the grain's vapour outside its cells), and
    the share in the grain's cells is p + (1 - p) u (u: the ring's share in
    them) to 1e-9; at later steps at least p of the previous step.  The
    configuration discriminates: > 70 % of the vapour in the grain's cells
    against < 5 % with uniform release."""
    runs = {}
    for release in ("uniform", "grains"):
        case = str(tmp_path / release)
        hot_grain_case(case, env, release)
        run("vansFoam", case, env)
        runs[release] = case
    vol = H * H * DEPTH
    mask = grain_cells()
    times = [name for t, name in nscdpost.numeric_dirs(runs["grains"]) if t > 0]
    assert len(times) == N_STEPS
    d = read_droplet(runs["grains"])
    Qf, Qp, Vdot = d[:, 7], d[:, 8], d[:, 11]
    p = Qp / (Qp + np.maximum(Qf, 0))
    q_u, q_g = volume_source(runs["uniform"], times[1]), volume_source(runs["grains"], times[1])
    total_u, total_g = q_u.sum() * vol, q_g.sum() * vol
    print(f"step 2: sum q V uniform {total_u:.17e}, grains {total_g:.17e}")
    assert total_g > 0 and abs(total_g - total_u) < 1e-12 * total_u
    out = ~mask
    assert np.allclose(q_g[out], (1 - p[0]) * q_u[out], rtol=1e-9, atol=1e-12 * q_u.max())
    u = q_u[mask].sum() / q_u.sum()
    s2 = q_g[mask].sum() / q_g.sum()
    print(f"step 2: share in the grain's cells {s2:.9f} (uniform {u:.6f}), p {p[0]:.9f}")
    assert abs(s2 - (p[0] + (1 - p[0]) * u)) < 1e-9
    assert s2 > 0.7 and u < 0.05
    for k in range(1, N_STEPS):
        q = volume_source(runs["grains"], times[k])
        s = q[mask].sum() / q.sum()
        print(f"step {k + 1}: vapour in the grain's cells {s:.6f}, Q_p share {p[k - 1]:.6f}")
        assert q.min() >= 0
        assert abs(q.sum() * vol - Vdot[k]) < 1e-9 * Vdot[k]
        assert s >= p[k - 1] - 1e-9


def test_grain_release_restart_continues_exactly(tmp_path, env):
    """A run stopped at step 3 of 6 and restarted ends as the uninterrupted
    run (reference: the uninterrupted run): every droplet.dat column to 1e-9
    relative and the last dropletVolumeSource to 1e-9 of its maximum; the
    grains' heats (column dropletVapourHeat of grainState.h5) and Q_f
    (gasHeat of uniform/droplet) carry the release over the restart.  A
    restart whose grain state lacks the column releases the first step's
    vapour in the ring only (asserted: the volume source then differs)."""
    case = str(tmp_path / "full")
    hot_grain_case(case, env, "grains", write_every=3)
    run("vansFoam", case, env)
    full = read_droplet(case)
    times = [name for t, name in nscdpost.numeric_dirs(case) if t > 0]
    assert len(full) == N_STEPS and len(times) == 2
    mid, last = times
    q_full = volume_source(case, last)
    with h5py.File(os.path.join(case, mid, "grainState.h5")) as h:
        assert np.abs(h["dropletVapourHeat"][()]).max() > 0
    assert "gasHeat" in open(os.path.join(case, mid, "uniform", "droplet")).read()

    def restart(name, edit=None):
        half = str(tmp_path / name)
        rest, _ = rerun_from(case, half, mid, last, env, edit)
        return rest, volume_source(half, last)

    rest, q = restart("half")
    assert len(rest) == N_STEPS // 2
    assert np.allclose(rest, full[N_STEPS // 2 :], rtol=1e-9, atol=1e-15)
    assert np.abs(q - q_full).max() <= 1e-9 * q_full.max()

    def drop_column(half):
        with h5py.File(os.path.join(half, mid, "grainState.h5"), "a") as h:
            del h["dropletVapourHeat"]

    _, q_lost = restart("lost", drop_column)
    err = np.abs(q_lost - q_full).max() / q_full.max()
    print(f"restart without the grains' heats: volume source off by {err:.2e}")
    assert err > 1e-3


@pytest.mark.mpi
@pytest.mark.parametrize("grains", ["replicated", "decomposed"])
def test_grain_release_parallel_matches_serial(tmp_path, env, grains):
    """Two ranks, the grains replicated (grainDecomposition replicated: the
    grains' heats summed over the ranks) or decomposed (the default: summed
    over each grain's copies, the column copied to the ghosts); the release
    weights use each rank's overlaps, so the droplet.dat columns of the heat
    and vapour (time to Vdot) equal the serial run's to 1e-8 relative
    (reference: the serial run)."""
    case = str(tmp_path / "serial")
    hot_grain_case(case, env, "grains")
    par = str(tmp_path / "par")
    if grains == "replicated":
        replicated_copy(case, par)
    else:
        shutil.copytree(case, par)
    run("vansFoam", case, env)
    p = run_parallel("vansFoam", par, env, n=2)
    assert ("grains decomposed over 2 ranks" in p.stdout) == (grains == "decomposed")
    a, b = read_droplet(case), read_droplet(par)
    assert a.shape == b.shape and np.all(a[1:, 11] > 0)
    assert np.allclose(a[:, :12], b[:, :12], rtol=1e-8, atol=1e-18)


def test_grain_release_refuses_a_grain_wider_than_two_cells(tmp_path, env):
    """A hot grain of 6 cells on the droplet's surface: the cells it covers
    have no gas for its vapour (the fluid blew up without the check), so
    vapourRelease grains stops with a FatalIOError naming the grain, the
    size ratio and the fix, before the first release."""
    case = str(tmp_path / "wide")
    hot_grain_case(case, env, "grains", n_steps=2, grain=GRAIN[:3] + (6 * H,))
    p = run("vansFoam", case, env, check=False)
    fails_with(p, "vapourRelease grains", "times the size", "Fix:", banner="FOAM FATAL IO ERROR")
