# SPDX-License-Identifier: GPL-3.0-or-later
"""Grains leaving through outletPatches with the grains decomposed over the
ranks (grainDecomposition decomposed; src/grainCloud, grainCloudOutlets.C):
a grain whose centre crosses an outlet is removed by the rank that owns it
(nscd::mpi::DecomposedSystem::removeOwned drops its ghost copies on the
other ranks), the counts of grainOutlets.dat are summed over the ranks,
ids are never reused, and a restart on another number of ranks continues
the totals.

References, independent of the decomposition:
  - conservation: removed + remaining = initial grains, by id;
  - the serial run of the same case (the undecomposed NSCD to the same
    contact tolerance): the same ids removed in the same steps, the same
    totals, and the remaining grains at the serial positions;
  - nextGrainId of the state: the initial count (the ids of removed grains
    are not given again).
"""

import os
import shutil

import h5py
import numpy as np
import pytest
from faultcase import open_bottom_cube, set_control
from foamcase import log_message, run, run_parallel
from test_faults_boundaries import outlet_rows
from test_outlet_orifice import small_silo

pytestmark = [pytest.mark.slow, pytest.mark.mpi]

#: silo discharge to END s: 14 discs leave through the orifice (the first
#: at 0.0245 s).  Later the discharge's arches amplify the contact solve's
#: differences (serial and 2 ranks: 5e-7 d apart at 0.05 s, 0.29 d at 0.1 s,
#: one disc leaving a step apart at 0.08 s; measured 2026-11-26), so the
#: comparison stops here, as a serial run at another tolerance would
END = 0.05
D_SILO = 3e-3


def _state(case, time_name):
    """{id: (position, angular velocity)} and nextGrainId of the written
    (whole, gathered) grain state."""
    with h5py.File(os.path.join(case, time_name, "grainState.h5"), "r") as f:
        ids = f["grainIds"][()].astype(int)
        x = f["positions"][()]
        w = f["angularVelocities"][()]
        nxt = int(np.ravel(f["nextGrainId"][()])[0])
    return {int(i): (x[k], w[k]) for k, i in enumerate(ids)}, nxt


def _same_rows(a, b):
    """The same steps, patch and counts in grainOutlets.dat rows a and b;
    the masses to round-off (summed over the ranks in another order)."""
    assert [(r[0], r[1], r[2], r[4]) for r in a] == [(r[0], r[1], r[2], r[4]) for r in b]
    for ra, rb in zip(a, b):
        assert rb[3] == pytest.approx(ra[3], rel=1e-12)
        assert rb[5] == pytest.approx(ra[5], rel=1e-12)


def _compare(serial, par, t, n_initial, label):
    """Same totals and removed ids as serial at time t, removed + remaining
    = initial, and the remaining discs at the serial positions (returns the
    largest distance [m])."""
    a, b = outlet_rows(serial, "0"), outlet_rows(par, "0")
    sa, nxt_a = _state(serial, t)
    sb, nxt_b = _state(par, t)
    total_a = [r for r in a if r[0] <= float(t) + 1e-9][-1][4]
    total_b = [r for r in b if r[0] <= float(t) + 1e-9][-1][4]
    assert total_b == total_a > 0, (total_a, total_b)
    assert len(sb) + total_b == n_initial
    assert set(sb) == set(sa), sorted(set(sa) ^ set(sb))
    assert nxt_a == nxt_b == n_initial
    dx = max(np.linalg.norm(sa[i][0] - sb[i][0]) for i in sa)
    print(
        f"[ {label} t={t} ] removed {total_b} of {n_initial}; max |x - x_serial| {dx / D_SILO:.2e} d"
    )
    return dx


@pytest.fixture(scope="module")
def silo_runs(tmp_path_factory, env):
    """The silo discharged serially, on 2 ranks (x slabs cut through the
    orifice), and on 4 ranks (2 x 2) stopped at END/2 and continued on 2."""
    base = tmp_path_factory.mktemp("siloDecomposed")
    serial = str(base / "serial")
    grains = small_silo(serial, env, END, write_interval=END / 2)
    out = {"n": len(grains), "serial": serial}
    np2 = str(base / "np2")
    shutil.copytree(serial, np2)
    np4 = str(base / "np4")
    shutil.copytree(serial, np4)
    run("grainFoam", serial, env)
    p = run_parallel("grainFoam", np2, env, n=2, split=(2, 1, 1))
    log_message(p.stdout, r"grains decomposed over 2 ranks.*each rank read its part")
    out["np2"] = np2
    set_control(np4, endTime=END / 2)
    p = run_parallel("grainFoam", np4, env, n=4, split=(2, 2, 1))
    log_message(p.stdout, r"grains decomposed over 4 ranks")
    # restart on 2 ranks from the gathered state and the counts of END/2,
    # as a user does it (test_grainFoam_decomposed.py)
    run("reconstructPar", np4, env, args=("-latestTime",))
    for d in os.listdir(np4):
        if d.startswith("processor"):
            shutil.rmtree(os.path.join(np4, d))
    set_control(np4, endTime=END)
    p = run_parallel("grainFoam", np4, env, n=2, split=(1, 2, 1))
    assert "outlet counts continued" in p.stdout
    out["restart"] = np4
    return out


@pytest.mark.parametrize("t", [str(END / 2), str(END)])
def test_silo_discharge_on_2_ranks_matches_serial(silo_runs, t):
    """grainFoam, the silo on 2 x slabs whose boundary crosses the orifice
    (both ranks remove discs): as many discs leave in the same steps as in
    the serial run (grainOutlets.dat), the same discs are left at every
    write (so the same ids were removed), the totals equal, and every remaining disc is within
    1e-3 d of its serial position (measured 2026-11-26: 0 at 0.025 s,
    5.2e-7 d at 0.05 s; the decomposed solve differs from the serial one by
    the contact tolerance; a disc placed on another side of a neighbour
    would be ~0.1-1 d away)."""
    s = silo_runs
    dx = _compare(s["serial"], s["np2"], t, s["n"], "np2")
    assert dx < 1e-3 * D_SILO
    _same_rows(outlet_rows(s["serial"], "0"), outlet_rows(s["np2"], "0"))


def test_silo_restarted_on_2_ranks_from_4_continues_the_totals(silo_runs):
    """The silo on 4 ranks (2 x 2: discs cross the horizontal boundary as
    they flow) to END/2, then continued on 2 ranks from the gathered state:
    grainOutlets.dat of the restart continues the totals of the 4-rank run
    (its first row's total = the serial total of END/2 + the discs of that
    step) and at END the totals, the remaining ids and the positions are
    the serial run's (1e-3 d, as above; measured 9.7e-8 d)."""
    s = silo_runs
    _compare(s["serial"], s["restart"], str(END / 2), s["n"], "np4")
    rows = outlet_rows(s["restart"], str(END / 2))
    serial = [r for r in outlet_rows(s["serial"], "0") if r[0] > END / 2 + 1e-9]
    _same_rows(serial, rows)
    dx = _compare_final(s)
    assert dx < 1e-3 * D_SILO


def _compare_final(s):
    a, nxt_a = _state(s["serial"], str(END))
    b, nxt_b = _state(s["restart"], str(END))
    assert set(a) == set(b) and nxt_a == nxt_b == s["n"]
    counts = open(os.path.join(s["restart"], str(END), "uniform", "grainOutlets")).read()
    assert f"grains {s['n'] - len(b)};" in counts
    dx = max(np.linalg.norm(a[i][0] - b[i][0]) for i in a)
    print(f"[ restart 4 -> 2 ranks t={END} ] max |x - x_serial| {dx / D_SILO:.2e} d")
    return dx


#: spheres (x, y, z, d) sinking in the open-bottom water cube: they cross
#: its open bottom `inlet` at 0.066 s (two, on different ranks), 0.114 and
#: 0.117 s; the run goes on without grains to END_CUBE
CUBE_GRAINS = [
    (0.01, 0.012, 0.02, 0.01),
    (0.03, 0.033, 0.02, 0.01),
    (0.03, 0.012, 0.01, 0.008),
    (0.012, 0.03, 0.032, 0.008),
]
END_CUBE = 0.12


@pytest.mark.parametrize("n,split", [(2, (2, 1, 1)), (4, (2, 2, 1))])
def test_vansFoam_outlet_decomposed_matches_serial(tmp_path, env, n, split):
    """vansFoam, 3D: spheres sinking through the open bottom of a water cube
    (outletPatches (inlet)) with the grains decomposed: the rank owning a
    sphere removes it, the counts and removed ids are the serial run's, the
    remaining spheres at 0.09 s are within 1e-3 d of their serial positions
    (measured 2026-11-26: 3.5e-8 d on 2 ranks, 1.0e-7 d on 4; the
    decomposition's own scatter in this cube reaches 3.5e-5 d,
    test_coupling_decomposed.py), and the run goes on once every sphere
    has left (no grain on any rank: the decomposed step's tolerance scale
    d_min is then 0, as an empty system's)."""
    serial = str(tmp_path / "serial")
    open_bottom_cube(serial, env, CUBE_GRAINS, end=END_CUBE, write_interval=0.03, outlet=True)
    par = str(tmp_path / f"np{n}")
    shutil.copytree(serial, par)
    run("vansFoam", serial, env)
    p = run_parallel("vansFoam", par, env, n=n, split=split)
    log_message(p.stdout, rf"grains decomposed over {n} ranks")
    a, b = outlet_rows(serial, "0"), outlet_rows(par, "0")
    _same_rows(a, b)
    assert [r[4] for r in a] == [2, 3, 4], a
    for t, left in (("0.09", 2), ("0.12", 0)):
        sa, nxt_a = _state(serial, t)
        sb, nxt_b = _state(par, t)
        assert set(sa) == set(sb) and len(sb) == left
        assert nxt_a == nxt_b == len(CUBE_GRAINS)
        dx = max((np.linalg.norm(sa[i][0] - sb[i][0]) for i in sa), default=0.0)
        print(f"[ vansFoam np{n} t={t} ] {left} left; max |x - x_serial| {dx / 0.008:.2e} d")
        assert dx < 1e-3 * 0.008
