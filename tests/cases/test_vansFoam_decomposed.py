# SPDX-License-Identifier: GPL-3.0-or-later
"""vansFoam with the grains decomposed over the ranks (grainDecomposition
decomposed, the default of a parallel run without the sub-models that still
need every grain on every rank): each rank owns the grains whose centre lies
in its cells, maps them and the ghosts of its neighbours' grains onto its
own cells, and completes each grain's overlap sums (mapped volume, gathered
fluid velocity, void fraction, pressure gradient) over the grain's copies.

References, independent of the decomposition:
  - the serial run of the same case (undecomposed grains and mesh): a
    sedimentation of 60 discs through water in a 2D box, on 2 (x slabs) and
    4 (2 x 2) ranks, the grains crossing the processor boundaries as they
    fall and collide;
  - the mixture volume: sum(eps V) = box volume - grain volume to 1e-9 on
    every rank count (exact overlaps: a grain straddling a processor
    boundary is counted once, its parts on each rank);
  - no grain lost or duplicated: the reconstructed cloud holds every id once;
  - restart: a run stopped on 2 ranks continues on 4 from the gathered
    state, with the coupling's per-grain restart columns.
"""

import math
import os
import re
import shutil

import h5py
import nscdpost
import numpy as np
import pytest
from foamcase import read_internal, run, run_parallel
from test_vansFoam import small_sedimentation

pytestmark = pytest.mark.fast

NROW, NCOL = 6, 10
N_GRAINS = NROW * NCOL
D = 3e-3


def _case(path, env, end):
    small_sedimentation(path, env, end=end, write=0.05, nrow=NROW, ncol=NCOL)


def _grains(case, time_name):
    """Positions and velocities of every grain in id order (reconstructed)."""
    g = nscdpost.read_grains(case, time_name)
    ids = g["grainId"]
    assert sorted(ids) == list(range(N_GRAINS)), "a grain was lost or duplicated"
    order = np.argsort(ids)
    return g["x"][order], g["U"][order]


def _volume_error(case, time_name):
    eps = read_internal(os.path.join(case, time_name, "voidFraction"))
    V = 0.04 * 0.06 * 0.003 / (9 * 13)
    expected = 0.04 * 0.06 * 0.003 - N_GRAINS * math.pi * (D / 2) ** 2 * 0.003
    return abs(np.sum(eps) * V - expected) / expected


@pytest.fixture(scope="module")
def runs(tmp_path_factory, env):
    """The serial run and the 2- and 4-rank runs to 0.15 s (reconstructed)."""
    base = tmp_path_factory.mktemp("vansDecomposed")
    serial = str(base / "serial")
    _case(serial, env, 0.15)
    out = {"serial": serial}
    for n, split in ((2, (2, 1, 1)), (4, (2, 2, 1))):
        par = str(base / f"np{n}")
        shutil.copytree(serial, par)
        p = run_parallel("vansFoam", par, env, n=n, split=split)
        assert f"grains decomposed over {n} ranks" in p.stdout
        # no rank held the whole state (nscd::System::readHDF5 with a region)
        assert "each rank read its part of the start state" in p.stdout
        run("reconstructPar", par, env)
        out[n] = par
    run("vansFoam", serial, env)
    return out


@pytest.mark.mpi
@pytest.mark.parametrize("n", [2, 4])
def test_sedimentation_matches_serial(runs, n):
    """The grains fall as in the serial run: after 0.05, 0.1 and 0.15 s
    (50-150 steps, the rows colliding as they fall) every grain is within
    1e-4 d of its serial position (measured 2026-11-24: 1.1e-5 d, the
    solver tolerances' differences) and the mean fall velocity agrees to
    1e-3; the mixture volume is exact on every rank count."""
    serial, par = runs["serial"], runs[n]
    for t in ("0.05", "0.1", "0.15"):
        xs, us = _grains(serial, t)
        xp, up = _grains(par, t)
        dx = np.max(np.abs(xs - xp))
        print(
            f"[ np{n} t={t} ] max |x - x_serial| = {dx:.3e} m = {dx / D:.2e} d, "
            f"mean v_y {np.mean(up[:, 1]):.6f} (serial {np.mean(us[:, 1]):.6f}) m/s"
        )
        assert dx < 1e-4 * D
        assert np.mean(up[:, 1]) == pytest.approx(np.mean(us[:, 1]), rel=1e-3)
        assert np.min(us[:, 1]) < -1e-2, "grains should be falling"
        assert _volume_error(par, t) < 1e-9


def _restart_columns(case, time_name):
    """The coupling's restart columns of the state, in id order."""
    with h5py.File(os.path.join(case, time_name, "grainState.h5"), "r") as f:
        order = np.argsort(f["grainIds"][()])
        names = ("grainHeldFraction", "grainContactImpulse", "grainDragImpulseDefect")
        return {c: f[c][()][order] for c in names}


@pytest.mark.mpi
@pytest.mark.parametrize("n", [2, 4])
def test_restart_columns_match_serial(runs, n):
    """The coupling's restart columns (grainState.h5 datasets gathered from
    the ranks, each grain's values migrating with it) equal the serial
    run's grain by grain to 1e-2 of their largest serial value, at 0.05,
    0.1 and 0.15 s (measured 2026-11-26 on 2 and 4 ranks: held fraction
    7.5e-4, contact impulse 5.7e-4, drag impulse defect 1.6e-3 relative,
    the grains being 1e-5 d apart; values on the wrong grains differ by
    O(1))."""
    serial, par = runs["serial"], runs[n]
    for t in ("0.05", "0.1", "0.15"):
        a, b = _restart_columns(serial, t), _restart_columns(par, t)
        for c in a:
            scale = max(np.max(np.abs(a[c])), 1e-300)
            diff = np.max(np.abs(a[c] - b[c]))
            print(f"[ np{n} t={t} {c} ] max |diff| = {diff:.2e}, max |serial| = {scale:.2e}")
            assert a[c].shape == b[c].shape == (N_GRAINS,) + a[c].shape[1:]
            assert diff < 1e-2 * scale
        assert np.max(np.abs(a["grainContactImpulse"])) > 0


@pytest.mark.mpi
def test_restart_on_4_ranks_continues_a_2_rank_run(runs, env, tmp_path):
    """The 2-rank run's state at 0.1 s (grainState.h5 with the coupling's
    restart columns, written whole into the case), reconstructed and
    decomposed again over 4 ranks, continues to 0.15 s as the uninterrupted
    2-rank run does: every grain within 1e-4 d (measured 2026-11-24:
    1.3e-6 d; 2.1e-3 d when the restart lists are removed, so they are read
    and placed on the right grains)."""
    restart = str(tmp_path / "restart")
    shutil.copytree(runs[2], restart, ignore=shutil.ignore_patterns("processor*", "0.15"))
    with h5py.File(os.path.join(restart, "0.1", "grainState.h5"), "r") as f:
        for name in ("grainContactImpulse", "grainDragImpulseDefect", "grainHeldFraction"):
            assert f[name].shape[0] == N_GRAINS, name
            assert not os.path.exists(os.path.join(restart, "0.1", "uniform", name)), name
    shutil.rmtree(os.path.join(restart, "0.05"))
    p = run_parallel("vansFoam", restart, env, n=4, split=(2, 2, 1))
    assert "grains decomposed over 4 ranks" in p.stdout
    run("reconstructPar", restart, env, args=("-latestTime",))
    xa, _ = _grains(runs[2], "0.15")
    xb, _ = _grains(restart, "0.15")
    dx = np.max(np.abs(xa - xb))
    print(f"[ restart 2 -> 4 ranks ] max |x - x_uninterrupted| = {dx / D:.2e} d")
    assert dx < 1e-4 * D


@pytest.mark.mpi
def test_bed_at_rest_across_ranks_matches_serial(tmp_path, env):
    """A bed of 40 discs settled by grainFoam (its contacts carry the
    weight) then immersed: vansFoam from that state on 2 ranks split across
    the bed's height (the weight crosses the processor boundary) follows
    the serial run, every grain within 1e-4 d after 20 steps (measured
    2026-11-24: 3.1e-7 d), and the bed stays nearly at rest (|v| < 1e-2
    m/s, as in the serial run to 1e-3). The fluid's prediction starts from
    the held fractions of the state's contacts: a grain held by contacts
    solved on another rank is held on every rank that holds a copy."""
    r = 1.5e-3
    grains = [
        (0.005 + (2 * i + 1 + (j % 2) * 0.5) * r * 1.05, (2 * j + 1) * r * 1.02, 0, 2 * r)
        for j in range(4)
        for i in range(10)
    ]
    serial = str(tmp_path / "serial")
    from foamcase import add_fluid, make_box_case
    from foamlib import FoamFile

    make_box_case(
        serial,
        (0, 0, 0),
        (0.04, 0.06, 0.003),
        (9, 13, 1),
        (0, -9.81, 0),
        {"grains": {"density": 1500, "friction": 0.3}},
        grains=grains,
        end_time=0.2,
        dt=1e-3,
        write_interval=0.2,
    )
    run("blockMesh", serial, env)
    run("grainDeposit", serial, env)
    run("grainFoam", serial, env)
    add_fluid(serial, 1000.0, 1e-6, max_dt=1e-3)
    for f in ("U", "p"):  # the fluid at rest from the settled state on
        shutil.move(os.path.join(serial, "0", f), os.path.join(serial, "0.2", f))
    with FoamFile(os.path.join(serial, "system", "controlDict")) as f:
        f["endTime"] = 0.22
        f["writeInterval"] = 0.02
    par = str(tmp_path / "par")
    shutil.copytree(serial, par)
    run("vansFoam", serial, env)
    run_parallel("vansFoam", par, env, n=2, split=(1, 2, 1))
    run("reconstructPar", par, env, args=("-latestTime",))
    t = nscdpost.time_dirs(serial)[-1][1]
    gs = nscdpost.read_grains(serial, t)
    gp = nscdpost.read_grains(par, t)
    xs = gs["x"][np.argsort(gs["grainId"])]
    xp = gp["x"][np.argsort(gp["grainId"])]
    dx = np.max(np.abs(xs - xp))
    vmax = np.max(np.linalg.norm(gp["U"], axis=1))
    vmax_serial = np.max(np.linalg.norm(gs["U"], axis=1))
    print(
        f"[ bed at rest, 2 ranks ] max |x - x_serial| = {dx / D:.2e} d, |v| max {vmax:.2e} m/s"
        f" (serial {vmax_serial:.2e})"
    )
    assert sorted(gp["grainId"]) == list(range(40))
    assert dx < 1e-4 * D
    assert vmax == pytest.approx(vmax_serial, rel=1e-3)
    assert vmax < 1e-2  # (the pressure's start from 0 stirs the bed a little)


@pytest.mark.mpi
@pytest.mark.parametrize("n,split", [(2, (1, 2, 1)), (4, (2, 2, 1))])
def test_heat_exchange_decomposed_matches_serial(tmp_path, env, n, split):
    """Fluid-grain heat exchange (heatTransferModel, thesis eq. 4.4-4.13)
    with the grains decomposed: 16 hot discs (350 K) settling in water at
    300 K with Boussinesq buoyancy in a closed box (test_vansFoam_heat.py),
    the rows crossing the processor boundaries. References: the energy of
    fluid + grains of the log conserved to 1e-6 on every rank count, up to
    its logged continuity defect (each grain's exchanged heat counted once
    over its copies), and the serial
    run: grain temperatures within 1e-8 K, the gathered fluid temperature
    (Tfluid) within 1e-8 K, positions within 1e-4 d; the upper row changes
    ranks on the y splits. The fluid and contact solvers are converged
    to round-off (tolerance 1e-13, relTol 0; contact tolerance 1e-12), as
    the partition changes the linear solvers' iterates: with the test
    cases' usual p relTol 0.01 and contact tolerance 1e-8 the temperatures
    differ by 2e-6 K at 0.03 s (measured 2026-11-24), 1.8e-11 K here."""
    from foamlib import FoamFile
    from test_vansFoam_heat import check_energy, closed_box_case

    serial = str(tmp_path / "serial")
    E0 = closed_box_case(serial, env, end_time=0.06, top=0.035)
    with FoamFile(os.path.join(serial, "system", "fvSolution")) as f:
        for k in list(f["solvers"].keys()):
            f["solvers", k, "tolerance"] = 1e-13
            f["solvers", k, "relTol"] = 0
    gp = os.path.join(serial, "constant", "grainProperties")
    text, count = re.subn(
        r"contactSolver \{ tolerance \S+;", "contactSolver { tolerance 1e-12;", open(gp).read()
    )
    assert count == 1
    open(gp, "w").write(text)
    par = str(tmp_path / f"np{n}")
    shutil.copytree(serial, par)
    p = run_parallel("vansFoam", par, env, n=n, split=split)
    assert f"grains decomposed over {n} ranks" in p.stdout
    check_energy(par, E0)
    run("vansFoam", serial, env)
    run("reconstructPar", par, env, args=("-latestTime",))
    fields = {}
    for name, case in (("serial", serial), ("par", par)):
        g = nscdpost.read_grains(case, "0.06")
        order = np.argsort(g["grainId"])
        d = os.path.join(case, "0.06", "lagrangian", "grains")
        fields[name] = (
            g["x"][order],
            nscdpost.read_scalar_field(os.path.join(d, "T"))[order],
            nscdpost.read_scalar_field(os.path.join(d, "Tfluid"))[order],
        )
        assert sorted(g["grainId"]) == list(range(16))
    (xs, Ts, Tfs), (xp, Tp, Tfp) = fields["serial"], fields["par"]
    dx, dT, dTf = (np.max(np.abs(a - b)) for a, b in ((xs, xp), (Ts, Tp), (Tfs, Tfp)))
    print(
        f"[ heat np{n} ] max |x - x_serial| = {dx / D:.2e} d, |T - T_serial| {dT:.2e} K,"
        f" |Tfluid - serial| {dTf:.2e} K, grain T {Ts.min():.3f}-{Ts.max():.3f} K"
    )
    assert np.max(Ts) < 350 - 1  # the grains cooled
    assert dx < 1e-4 * D
    assert dT < 1e-8
    assert dTf < 1e-8
