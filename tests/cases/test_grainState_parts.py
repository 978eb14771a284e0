# SPDX-License-Identifier: GPL-3.0-or-later
"""The grain state of a decomposed run written in parts (issue 57, item 3):
each rank writes its own grains into <time>/grainStateA/rank<N>.h5 and the
master joins them by HDF5 virtual datasets into <time>/grainState.h5
(src/grainCloud/grainCloudStateParts.C, src/nscd/src/IOParts.cpp).

References, independent of the parallel writer:
  - the serial run of the same pile at rest (one whole file, no parts): the
    same grain ids and radii, positions within 1e-3 d_min, the walls
    carrying the weight sum m g to 2e-3 of it, read with h5py through the
    virtual datasets;
  - geometry: every grain-grain contact of a joined state links two grains
    whose centres are r_i + r_j apart (to 5 % of d_min) along its normal, so
    the rows of a contact whose partner another rank wrote are right;
  - a restart from the 2-rank write on 3 ranks and serially carries the
    weight at once, with every grain id once;
  - a run killed (SIGKILL to mpirun) at a random point of its writes leaves
    every grainState.h5 of the case whole (every id once) and a restart
    continues from the latest; the same when one rank alone is killed (the
    master, which joins the parts, or the other), and the case restarts on
    2 ranks as it was left.
"""

import os
import shutil
import signal
import subprocess
import time

import h5py
import nscdpost
import numpy as np
import pytest
from foamcase import decompose, log_message, run, run_in_background, run_parallel
from test_grainFoam_decomposed import _copy, _set_control, deposited_pile
from test_grainFoam_decomposed import _wall_load as _wall_load_of
from test_grainFoam_physics import G

pytestmark = [pytest.mark.slow, pytest.mark.mpi]

N = 300
DMIN = 2e-3
RHO = 2500


@pytest.fixture(scope="module")
def pile(tmp_path_factory, env):
    """300 discs deposited at rest (grainDeposit), once."""
    return deposited_pile(str(tmp_path_factory.mktemp("parts") / "pile"), env, 0.1, 0.05, N)


def _set_end(case, end):
    _set_control(case, endTime=end)


def _state(case, t):
    """Whole-state arrays (through the virtual datasets) sorted by grain id."""
    path = os.path.join(case, t, "grainState.h5")
    ids = nscdpost.read_h5(path, "/grainIds").astype(int)
    o = np.argsort(ids)
    x = nscdpost.read_h5(path, "/positions").astype(float)[o]
    r = nscdpost.read_h5(path, "/radii").astype(float)[o]
    return ids[o], x, r


def _wall_load(case, t):
    return _wall_load_of(case, t, RHO, G)


def _check_contacts_geometry(case, t):
    """Grain-grain contacts in file rows: centres r_i + r_j apart, along the
    normal (from B to A)."""
    path = os.path.join(case, t, "grainState.h5")
    c = nscdpost.read_contacts(case, t)
    x = nscdpost.read_h5(path, "/positions").astype(float)
    r = nscdpost.read_h5(path, "/radii").astype(float)
    p = c["j"] >= 0
    i, j = c["i"][p], c["j"][p]
    d = x[i] - x[j]
    dist = np.linalg.norm(d, axis=1)
    assert np.all(np.abs(dist - r[i] - r[j]) < 0.05 * DMIN), np.max(np.abs(dist - r[i] - r[j]))
    assert np.all(np.einsum("ij,ij->i", d / dist[:, None], c["normal"][p]) > 0.99)
    return int(p.sum())


def _parts(case, t, n):
    """The part files the joined state reads, checked: one per rank that
    holds grains (a rank without maps no rows), none holding every grain."""
    path = os.path.join(case, t, "grainState.h5")
    with h5py.File(path, "r") as f:
        assert f["radii"].is_virtual and f["positions"].is_virtual
        src = sorted({s.file_name for s in f["radii"].virtual_sources()})
    assert set(src) <= {f"grainStateA/rank{k}.h5" for k in range(n)} and len(src) >= 2, src
    for k in range(n):
        assert os.path.isfile(os.path.join(case, t, f"grainStateA/rank{k}.h5"))
    rows = []
    for s in src:
        with h5py.File(os.path.join(case, t, s), "r") as f:
            rows.append(len(f["radii"]))
    assert sum(rows) == N and max(rows) < N, rows
    return rows


def test_parallel_write_equals_serial(pile, tmp_path, env):
    serial = _copy(pile, str(tmp_path / "serial"))
    run("grainFoam", serial, env)
    ids_s, x_s, r_s = _state(serial, "0.1")
    assert list(ids_s) == list(range(N))
    load_s = _wall_load(serial, "0.1")
    for n in (2, 4):
        case = _copy(pile, str(tmp_path / f"np{n}"))
        run_parallel("grainFoam", case, env, n=n, split=(1, n, 1))
        for t in ("0.05", "0.1"):
            rows = _parts(case, t, n)
            ids, x, r = _state(case, t)
            assert list(ids) == list(range(N)), t
            assert np.array_equal(r, r_s)
        moved = np.max(np.linalg.norm(x - x_s, axis=1))
        pairs = _check_contacts_geometry(case, "0.1")
        load = _wall_load(case, "0.1")
        print(
            f"{n} ranks: rows per part {rows}, max |x - x_serial| {moved:.2e} m, {pairs} pair contacts, load {load:.6f} (serial {load_s:.6f})"
        )
        assert moved < 1e-3 * DMIN
        assert load == pytest.approx(1.0, abs=2e-3)
        # ParaView: the XDMF's vertex list runs over the joined rows
        path = os.path.join(case, "0.1", "grainState.h5")
        assert list(nscdpost.read_h5(path, "/xdmfVertices")) == list(range(N))
        assert os.path.isfile(os.path.join(case, "grainState.xmf"))


def test_restart_from_two_ranks_on_three_and_serially(pile, tmp_path, env):
    case = _copy(pile, str(tmp_path / "np2"))
    run_parallel("grainFoam", case, env, n=2, split=(1, 2, 1))
    _parts(case, "0.1", 2)
    serial = _copy(case, str(tmp_path / "serialRestart"))  # (the parts with it)
    _set_end(serial, 0.15)
    run("grainFoam", serial, env)
    _set_end(case, 0.15)
    run("reconstructPar", case, env, args=("-latestTime",))
    for d in os.listdir(case):
        if d.startswith("processor"):
            shutil.rmtree(os.path.join(case, d))
    p = run_parallel("grainFoam", case, env, n=3, split=(1, 3, 1))
    log_message(p.stdout, r"grains decomposed over 3 ranks.*each rank read its part")
    _parts(case, "0.15", 3)
    for c in (case, serial):
        ids, _, _ = _state(c, "0.15")
        assert list(ids) == list(range(N))
        load = _wall_load(c, "0.15")
        print(f"{os.path.basename(c)}: wall load / weight at 0.15 s {load:.6f}")
        assert load == pytest.approx(1.0, abs=2e-3)


def _writing_every_step(pile, case, env):
    """The pile on 2 ranks (y slabs) writing every step, started in its own
    session; returns the mpirun Popen 40 steps in (the log in log.killed)."""
    case = _copy(pile, case)
    _set_control(case, writeInterval="5e-4")
    decompose(case, env, n=2, split=(1, 2, 1))
    logp = os.path.join(case, "log.killed")
    proc = run_in_background(
        ["mpirun", "-np", "2", "grainFoam", "-parallel", "-case", case],
        env,
        logp,
        lambda log: log.count("\nTime = ") >= 40,
        timeout=120,
        poll=0.05,
        start_new_session=True,
    )
    assert proc.poll() is None, open(logp).read()[-2000:]
    return proc


def _wait_for_the_lock_holder(case):
    """Until the killed process holding the case's lock file is gone."""
    holder = int(open(os.path.join(case, ".nscdFoam.lock")).read().split()[0])
    for _ in range(100):
        try:
            os.kill(holder, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)


def _whole_states(case):
    """The times of the case holding a grainState.h5, each checked whole
    (every id once, read through its virtual datasets)."""
    states = [
        t
        for _, t in nscdpost.numeric_dirs(case)
        if os.path.isfile(os.path.join(case, t, "grainState.h5"))
    ]
    assert len(states) > 10, states
    for t in states:
        ids, _, _ = _state(case, t)
        assert list(ids) == list(range(N)), t
    return states


def _rank_pid(mpirun_pid, rank):
    """The pid of the MPI rank `rank` among mpirun's children (its
    OMPI_COMM_WORLD_RANK)."""
    with open(f"/proc/{mpirun_pid}/task/{mpirun_pid}/children") as f:
        children = [int(c) for c in f.read().split()]
    for pid in children:
        with open(f"/proc/{pid}/environ", "rb") as f:
            env = dict(e.split(b"=", 1) for e in f.read().split(b"\0") if b"=" in e)
        if env.get(b"OMPI_COMM_WORLD_RANK") == str(rank).encode():
            return pid
    raise AssertionError(f"rank {rank} not among mpirun's children {children}")


def _restart_on_two_ranks(case, end, env):
    """The case run on to end on 2 ranks as it is (no decomposePar, no
    clean-up); returns its log (log.restart)."""
    _set_end(case, end)
    p = subprocess.run(
        ["mpirun", "-np", "2", "grainFoam", "-parallel", "-case", case],
        env=env,
        capture_output=True,
        text=True,
    )
    log = p.stdout + p.stderr
    open(os.path.join(case, "log.restart"), "w").write(log)
    assert p.returncode == 0, log[-4000:]
    return log


def test_killed_during_writes_leaves_whole_states(pile, tmp_path, env):
    """A write every step; mpirun killed (SIGKILL) 40 steps in, at whatever
    point of a write its ranks are."""
    case = str(tmp_path / "kill")
    proc = _writing_every_step(pile, case, env)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=60)
    _wait_for_the_lock_holder(case)
    states = _whole_states(case)
    # a serial run continues from the latest whole state
    last = states[-1]
    for t in [t for _, t in nscdpost.numeric_dirs(case) if float(t) > float(last)]:
        shutil.rmtree(os.path.join(case, t))
    _set_end(case, round(float(last) + 2e-3, 6))
    run("grainFoam", case, env)
    ids, _, _ = _state(case, nscdpost.numeric_dirs(case)[-1][1])
    assert list(ids) == list(range(N))


@pytest.mark.parametrize("rank", [0, 1])
def test_one_rank_killed_during_writes_restarts_on_the_ranks(pile, tmp_path, env, rank):
    """A write every step; one rank (the master, which joins the parts, or
    the other) SIGKILLed alone 40 steps in, mpirun ending the other. Every
    grainState.h5 left is whole, and the same case restarted on 2 ranks
    (startFrom latestTime, nothing cleaned by hand: the solver moves an
    incomplete latest time aside) goes on from the latest whole write with
    every grain."""
    case = str(tmp_path / f"kill{rank}")
    proc = _writing_every_step(pile, case, env)
    os.kill(_rank_pid(proc.pid, rank), signal.SIGKILL)
    try:
        proc.wait(timeout=60)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
    _wait_for_the_lock_holder(case)
    states = _whole_states(case)
    end = round(float(states[-1]) + 2e-3, 6)
    _restart_on_two_ranks(case, end, env)
    print(f"rank {rank} killed: {len(states)} whole writes, the latest {states[-1]}")
    t_end, last = nscdpost.numeric_dirs(case)[-1]
    assert t_end == pytest.approx(end, abs=1e-9), last
    ids, _, _ = _state(case, last)
    assert list(ids) == list(range(N))


def _cut_short(path):
    """Truncate a file to half its size (a write killed half-way)."""
    with open(path, "r+b") as f:
        f.truncate(os.path.getsize(path) // 2)


def _leave_interrupted(case, t, how):
    """Turn the write of time t of a finished 2-rank run into what a kill
    during it leaves (grainCloudStateParts.C's order: the parts into
    grainStateA, or grainStateB for a rewrite of the same time, then the
    joined file into grainState.h5.tmp, renamed into place)."""
    d = os.path.join(case, t)
    if how == "part":  # a rank killed writing its part: no joined file yet
        os.remove(os.path.join(d, "grainState.h5"))
        _cut_short(os.path.join(d, "grainStateA", "rank1.h5"))
    elif how == "join":  # the master killed writing the joined file
        os.rename(os.path.join(d, "grainState.h5"), os.path.join(d, "grainState.h5.tmp"))
        _cut_short(os.path.join(d, "grainState.h5.tmp"))
    else:  # "rewrite": a rewrite of the same time killed in its parts
        shutil.copytree(os.path.join(d, "grainStateA"), os.path.join(d, "grainStateB"))
        _cut_short(os.path.join(d, "grainStateB", "rank0.h5"))


@pytest.mark.parametrize("how", ["part", "join", "rewrite"])
def test_restart_after_a_write_killed_at_each_stage(pile, tmp_path, env, how):
    """Each state a kill during a parts write can leave, made on purpose in
    the latest write (0.1 s) of a 2-rank run: a part cut short with no
    joined file, the joined file cut short as grainState.h5.tmp, a rewrite's
    grainStateB cut short. The case restarted on 2 ranks as it was left
    (startFrom latestTime) goes on from the latest readable write: 0.05 s
    (the 0.1 s directory moved aside), or 0.1 s for the rewrite (its joined
    file still reads grainStateA), with every grain."""
    case = _copy(pile, str(tmp_path / how))
    run_parallel("grainFoam", case, env, n=2, split=(1, 2, 1))
    _leave_interrupted(case, "0.1", how)
    start = "0.1" if how == "rewrite" else "0.05"
    end = float(start) + 2.5e-3
    log = _restart_on_two_ranks(case, end, env)
    log_message(log, rf"Create mesh for time = {start}\b")
    if how != "rewrite":
        log_message(log, r"The latest time directory 0\.1 is\s+incomplete")
    last = [t for v, t in nscdpost.numeric_dirs(os.path.join(case, "processor0")) if v < 1]
    assert float(last[-1]) == pytest.approx(end, abs=1e-9), last
    for t in (start, last[-1]):
        ids, _, _ = _state(case, t)
        assert list(ids) == list(range(N)), t
