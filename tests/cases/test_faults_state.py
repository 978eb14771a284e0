# SPDX-License-Identifier: GPL-3.0-or-later
"""Faults of the grain state and the writes: bad, truncated or
missing state files, restarts, interrupted writes, stop signals, parallel
state, lagrangian output on the case's own mesh (rows 4-7, 12, 14); every
row fails loudly or does what is documented, never crashes on a signal; the
earlier results of the case stay intact.  Small 2D cases (seconds each);
helpers in faultcase.py."""

import os
import re
import shutil
import signal
import subprocess
import time

import nscdpost
import pytest
from faultcase import (
    MAT,
    G,
    box,
    digest,
    fill_disk,
    mount_small_disk,
    set_control,
    stack,
    times,
    umount_small_disk,
)
from foamcase import (
    decompose,
    fails_with,
    log_message,
    make_box_case,
    run,
    run_in_background,
    run_parallel,
)

pytestmark = pytest.mark.fast


# ---- row 4: bad state files -------------------------------------------------


def poke(path, dataset, index, value):
    """Overwrite element `index` (flat, row-major) of a float64 dataset of an
    HDF5 file in place (h5py; the FoamFile user block is left as it is)."""
    import h5py

    with h5py.File(path, "r+") as f:
        ds = f[dataset]
        flat = ds[()].reshape(-1)
        flat[index] = value
        ds[...] = flat.reshape(ds.shape)


def deposited(tmp_path, name, env):
    case = box(tmp_path, name, [(0.05, 0.006, 0, 0.01), (0.07, 0.006, 0, 0.01)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    return case


def test_nan_and_negative_values_in_state(tmp_path, env):
    for dataset, index, value, words in [
        ("/positions", 3 + 1, float("nan"), ("grain 1", "non-finite position")),
        ("/velocities", 0, float("inf"), ("grain 0", "non-finite velocity")),
        ("/radii", 1, -0.005, ("grain 1", "radius", "> 0")),
    ]:
        case = deposited(tmp_path, "bad" + dataset.strip("/"), env)
        poke(os.path.join(case, "0", "grainState.h5"), dataset, index, value)
        fails_with(
            run("grainFoam", case, env, check=False),
            *words,
            "Cannot use the grain state",
            "Fix",
            "grainDeposit",
        )


def test_truncated_state_names_previous_write(tmp_path, env):
    case = deposited(tmp_path, "trunc", env)
    run("grainFoam", case, env)
    path = os.path.join(case, "0.02", "grainState.h5")
    data = open(path, "rb").read()
    open(path, "wb").write(data[: len(data) // 2])
    p = run("grainFoam", case, env, check=False)
    fails_with(p, "damaged or truncated", "previous write 0.01", "startTime 0.01")
    assert os.path.getsize(os.path.join(case, "0.01", "grainState.h5")) > 0


# ---- row 14: lagrangian output on the case's own mesh -----------------------


def positions_cells(case, time_name):
    """Cell index of each grain in lagrangian/grains: from `positions`
    ((x y z) celli) and `coordinates` ((a b c d) celli tetFacei tetPti),
    which must agree."""
    d = os.path.join(case, time_name, "lagrangian", "grains")
    pos = [
        int(c)
        for c in re.findall(r"\)\s+(-?\d+)\s*$", open(os.path.join(d, "positions")).read(), re.M)
    ]
    bary = [
        int(c)
        for c in re.findall(
            r"\)\s+(-?\d+)\s+-?\d+\s+-?\d+\s*$", open(os.path.join(d, "coordinates")).read(), re.M
        )
    ]
    assert pos == bary, (pos, bary)
    return pos


def test_state_from_another_mesh_is_located_on_this_one(tmp_path, env):
    """A deposit settled on a fine mesh (20 x 20) copied with its lagrangian
    output into a case on a coarse mesh (2 x 2): the solver writes the start
    time's grains on its own mesh, so foamToVTK runs (it segfaulted on cell
    indices of the other mesh) and each grain's cell is the coarse cell that
    holds it."""
    fine = str(tmp_path / "fine")
    grains = [(0.013, 0.006, 0, 0.01), (0.087, 0.006, 0, 0.01), (0.06, 0.07, 0, 0.01)]
    make_box_case(
        fine,
        (0, 0, 0),
        (0.1, 0.1, 0.01),
        (20, 20, 1),
        (0, -G, 0),
        MAT,
        grains=grains,
        end_time=0.002,
        dt=1e-3,
        write_interval=0.002,
    )
    run("blockMesh", fine, env)
    run("grainDeposit", fine, env)
    assert max(positions_cells(fine, "0")) > 4
    coarse = str(tmp_path / "coarse")
    make_box_case(
        coarse,
        (0, 0, 0),
        (0.1, 0.1, 0.01),
        (2, 2, 1),
        (0, -G, 0),
        MAT,
        end_time=0.002,
        dt=1e-3,
        write_interval=0.002,
    )
    run("blockMesh", coarse, env)
    os.makedirs(os.path.join(coarse, "0"), exist_ok=True)
    for item in ("grainState.h5", "lagrangian"):
        src, dst = os.path.join(fine, "0", item), os.path.join(coarse, "0", item)
        (shutil.copytree if os.path.isdir(src) else shutil.copy)(src, dst)
    state = open(os.path.join(coarse, "0", "grainState.h5"), "rb").read()
    run("grainFoam", coarse, env)
    assert open(os.path.join(coarse, "0", "grainState.h5"), "rb").read() == state
    for t in ("0", "0.002"):
        cells = positions_cells(coarse, t)
        assert len(cells) == 3 and all(0 <= c < 4 for c in cells), cells
    # cells of the 2 x 2 mesh: i + 2 j; grains at x = 0.013 / 0.087 / 0.06, low / low / high
    assert sorted(positions_cells(coarse, "0")) == [0, 1, 3]
    p = run("foamToVTK", coarse, env, check=False)
    assert p.returncode == 0, (p.stdout + p.stderr)[-2000:]


# ---- row 12: SIGTERM / SIGUSR1 write and stop -------------------------------


def test_sigterm_writes_and_stops(tmp_path, env):
    # endTime far beyond the signal: the 3-grain run steps ~200,000 steps/s
    # on an idle machine, so an end of 100 s could finish before the first poll
    case = stack(tmp_path, "sigterm", end=1000, write_interval=500)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    proc = run_in_background(
        ["grainFoam", "-case", case],
        env,
        os.path.join(case, "log.grainFoam"),
        lambda log: "Time = 0.05" in log,
        poll=0.01,
    )
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=60) == 0
    out = open(os.path.join(case, "log.grainFoam")).read()
    assert "Stop signal 15 (SIGTERM) received: wrote time" in out
    last = times(case)[-1]
    assert float(last) >= 0.05
    assert os.path.isfile(os.path.join(case, last, "grainState.h5"))
    # postProcessing/runEnd says why the run ended, and at which step
    (end,) = nscdpost.read_run_end(case)
    assert end["reason"] == "stopSignal" and end["time"] == float(last), end
    # and the run continues from it
    set_control(case, endTime=float(last) + 0.002)
    out = run("grainFoam", case, env).stdout
    assert "Create time" in out and "End" in out
    assert [e["reason"] for e in nscdpost.read_run_end(case)] == ["stopSignal", "endTime"]


# ---- the write grid kept when a run continues from an off-grid time ----------


def test_continued_run_writes_on_the_write_grid(tmp_path, env):
    """grainFoam with writeInterval 0.01 stopped at 0.025 (the state of the
    last step is always written, as after a stop signal) and continued to
    0.05: the continued run writes at 0.03, 0.04, 0.05, the multiples of
    writeInterval, not at 0.035, 0.045 (writeGridTime)."""
    case = stack(tmp_path, "grid", end=0.025, dt=1e-3, write_interval=0.01)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    assert times(case) == ["0", "0.01", "0.02", "0.025"]
    set_control(case, endTime=0.05)
    out = run("grainFoam", case, env).stdout
    assert "writeGridTime: the start time 0.025 is off the write grid" in out
    assert times(case) == ["0", "0.01", "0.02", "0.025", "0.03", "0.04", "0.05"]


def test_vansFoam_continued_run_writes_on_the_write_grid(tmp_path, env):
    """The same with vansFoam's adjustable time step (maxCo): stopped near
    0.045 (the last step, off the grid of writeInterval 0.02) and continued
    to 0.1: writes at 0.06, 0.08, 0.1 (the time step shortened to land on
    them)."""
    from test_vansFoam import small_sedimentation

    case = str(tmp_path / "grid")
    small_sedimentation(case, env, end=0.045, write=0.02)
    run("vansFoam", case, env)
    first = times(case)
    assert first[:3] == ["0", "0.02", "0.04"] and 0.04 < float(first[-1]) < 0.05
    set_control(case, endTime=0.1)
    out = run("vansFoam", case, env).stdout
    assert "is off the write grid" in out
    assert times(case) == first + ["0.06", "0.08", "0.1"]


# ---- row 5: restart from a write that is not the first ----------------------


def test_vansFoam_restart_from_second_write(tmp_path, env):
    """Writes at 0.03, 0.06, 0.09 s (adjustable time step, maxCo): a restart
    from 0.06 (not the first write) reaches 0.09 with the grains and the
    fluid of the uninterrupted run, to the 17 digits written."""
    from test_vansFoam import small_sedimentation

    case = str(tmp_path / "full")
    small_sedimentation(case, env, end=0.105, write=0.035)
    run("vansFoam", case, env)
    assert times(case) == ["0", "0.035", "0.07", "0.105"]
    restart = str(tmp_path / "restart")
    shutil.copytree(case, restart)
    shutil.rmtree(os.path.join(restart, "0.105"))
    run("vansFoam", restart, env)
    for f in (
        "U",
        "p",
        os.path.join("lagrangian", "grains", "positions"),
        os.path.join("lagrangian", "grains", "U"),
        "uniform/time",
    ):
        a = open(os.path.join(case, "0.105", f)).read()
        b = open(os.path.join(restart, "0.105", f)).read()
        assert a == b, f


# ---- row 7: writes that cannot half-fail -------------------------------------


def test_disk_full_during_write(tmp_path, env):
    """The grain state is written to grainState.h5.tmp and renamed when
    complete; a full disk (the temporary file is a link to /dev/full) gives
    'no space left on device', no partial state and no empty time directory
    that startFrom latestTime would take."""
    case = box(tmp_path, "full", [(0.05, 0.05, 0, 0.01)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    set_control(case, startFrom="startTime")
    os.makedirs(os.path.join(case, "0.01"))
    os.symlink("/dev/full", os.path.join(case, "0.01", "grainState.h5.tmp"))
    p = run("grainFoam", case, env, check=False)
    fails_with(
        p,
        "Writing the grain state",
        "no space left on device",
        "the empty time directory was removed",
    )
    assert times(case) == ["0"]
    # and the run restarts as if nothing happened
    set_control(case, startFrom="latestTime")
    run("grainFoam", case, env)
    assert times(case) == ["0", "0.01", "0.02"]
    assert not any(f.endswith(".tmp") for f in os.listdir(os.path.join(case, "0.02")))


# the messages of the write points, in the order a step reaches them
WRITE_POINTS = {
    "lock file": "Cannot write the lock file",
    ".dat row": '.dat" failed',
    "grainState.h5": "Writing the grain state",
    "time directory": "Writing the time directory 0.02 failed",
}


def test_full_disk_at_every_write_point(tmp_path, env):
    """A real full disk (a small tmpfs filled by a file, leaving 0 to 80 kB):
    each amount stops grainFoam at another write point (the lock file, a
    row of a postProcessing .dat file, grainState.h5, the fields of the time
    directory), each with a FatalError naming the file and "no space left
    on device", no signal or HDF5 loop at exit (HDF5 used to loop closing
    the file it could not write: "infinite loop closing library", then a
    crash), the earlier writes untouched and no incomplete time directory
    left for startFrom latestTime; with the space freed the run continues
    to its end.  Needs root (mount); skipped otherwise."""
    base = box(tmp_path, "base", [(0.05, 0.05, 0, 0.01)], end=0.01)
    run("blockMesh", base, env)
    run("grainDeposit", base, env)
    run("grainFoam", base, env)
    hit = {}
    for free in (0, 8192, 20000, 80000):
        disk = str(tmp_path / f"disk{free}")
        mount_small_disk(disk, "4m")
        try:
            case = os.path.join(disk, "case")
            shutil.copytree(base, case)
            set_control(case, endTime=0.03)
            before = {t: digest(case, t) for t in times(case)}
            filler = fill_disk(disk, free)
            out = fails_with(run("grainFoam", case, env, check=False), "no space left on device")
            assert "infinite loop" not in out and "HDF5-DIAG" not in out
            points = [k for k, m in WRITE_POINTS.items() if m in out]
            assert len(points) == 1, out[-3000:]
            hit[free] = points[0]
            assert times(case) == ["0", "0.01"]
            assert {t: digest(case, t) for t in times(case)} == before
            os.remove(filler)
            run("grainFoam", case, env)
            assert times(case) == ["0", "0.01", "0.02", "0.03"]
        finally:
            umount_small_disk(disk)
    print("write point hit by the free space:", hit)
    assert sorted(hit.values()) == sorted(WRITE_POINTS), hit


@pytest.mark.mpi
def test_full_disk_at_a_parallel_write(tmp_path, env):
    """Two ranks, the disk full during the fields of time 0.02: FatalError
    naming the file and "no space left on device", every processor's 0.02
    and the case's (the grain state) moved to 0.02.incomplete, the earlier
    writes untouched; once the space is freed and the aborted ranks are gone
    (MPI_Abort leaves the lock file, whose process then no longer runs) the
    run takes the lock over and continues to its end."""
    base = box(tmp_path, "base", [(0.02, 0.05, 0, 0.01), (0.07, 0.05, 0, 0.01)], end=0.01)
    run("blockMesh", base, env)
    run("grainDeposit", base, env)
    run_parallel("grainFoam", base, env)
    disk = str(tmp_path / "disk")
    mount_small_disk(disk, "6m")
    try:
        case = os.path.join(disk, "case")
        shutil.copytree(base, case)
        set_control(case, endTime=0.03)
        proc = [os.path.join(case, f"processor{i}") for i in range(2)]
        before = [digest(d, "0.01") for d in proc]
        filler = fill_disk(disk, 80000)

        def mpirun():
            return subprocess.run(
                ["mpirun", "-np", "2", "grainFoam", "-parallel", "-case", case],
                env=env,
                capture_output=True,
                text=True,
            )

        fails_with(mpirun(), WRITE_POINTS["time directory"], "no space left on device")
        for d in [case] + proc:
            assert os.path.isdir(os.path.join(d, "0.02.incomplete")) and times(d)[-1] == "0.01"
        assert [digest(d, "0.01") for d in proc] == before
        os.remove(filler)
        holder = int(open(os.path.join(case, ".nscdFoam.lock")).read().split()[0])
        for _ in range(100):
            try:
                os.kill(holder, 0)
            except ProcessLookupError:
                break
            time.sleep(0.1)
        p = mpirun()
        assert p.returncode == 0 and "taking over the lock file" in p.stdout + p.stderr
        assert times(proc[0])[-1] == "0.03"
    finally:
        umount_small_disk(disk)


# ---- row 6: parallel state ---------------------------------------------------


@pytest.mark.mpi
@pytest.mark.parametrize("mode", ["decomposed", "replicated"])
def test_reconstructPar_carries_grain_state(tmp_path, env, mode):
    """decomposePar, a parallel run, reconstructPar: the reconstructed time
    directories hold grainState.h5 (written by the master into the
    undecomposed case: decomposed, the state gathered from the ranks;
    replicated, its own copy, the same as each rank's) and the lagrangian
    cloud, and a serial run continues from the last one."""
    from foamcase import run_parallel

    case = stack(tmp_path, "par", extra_props=f"grainDecomposition {mode};\n")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run_parallel("grainFoam", case, env, n=2)
    run("reconstructPar", case, env)
    # the state file carries a FoamFile header (HDF5 user block): neither
    # decomposePar nor reconstructPar warns about it
    for app in ("decomposePar", "reconstructPar"):
        log = open(os.path.join(case, f"log.{app}")).read()
        assert "FoamFile" not in log and "grainState" not in log, log[-2000:]
    for t in ("0.01", "0.02"):
        assert os.path.isfile(os.path.join(case, t, "grainState.h5"))
        assert os.path.isfile(os.path.join(case, t, "lagrangian", "grains", "positions"))
    if mode == "replicated":
        a = open(os.path.join(case, "0.02", "grainState.h5"), "rb").read()
        b = open(os.path.join(case, "processor0", "0.02", "grainState.h5"), "rb").read()
        assert a == b
    else:
        assert not os.path.exists(os.path.join(case, "processor0", "0.02", "grainState.h5"))
    shutil.rmtree(os.path.join(case, "processor0"))
    shutil.rmtree(os.path.join(case, "processor1"))
    set_control(case, endTime=0.03)
    out = run("grainFoam", case, env).stdout
    assert "Create time" in out and times(case)[-1] == "0.03"


@pytest.mark.mpi
def test_sigusr1_to_mpirun_writes_and_stops(tmp_path, env):
    """In parallel, SIGUSR1 sent to mpirun (Open MPI forwards it to every
    rank) writes the current step (the grain state gathered into the
    undecomposed case, each rank's lagrangian cloud) and stops with exit 0
    (SIGTERM to mpirun kills the ranks: README)."""
    case = stack(tmp_path, "sigpar", end=100, write_interval=50)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    decompose(case, env, n=2)
    logp = os.path.join(case, "log.grainFoam")
    proc = run_in_background(
        ["mpirun", "-np", "2", "grainFoam", "-parallel", "-case", case],
        env,
        logp,
        lambda log: "Time = 0.05" in log,
    )
    if proc.poll() is not None:
        pytest.skip("mpirun cannot start here: " + open(logp).read()[-300:])
    proc.send_signal(signal.SIGUSR1)
    assert proc.wait(timeout=60) == 0
    out = open(logp).read()
    m = log_message(out, r"Stop signal 10 \(SIGUSR1\) received: wrote time (\S+) ")
    t = m.group(1)
    assert os.path.isfile(os.path.join(case, t, "grainState.h5"))
    assert nscdpost.read_run_end(case)[-1]["reason"] == "stopSignal"  # the master's
    for d in ("processor0", "processor1"):
        assert os.path.isdir(os.path.join(case, d, t, "lagrangian")), d


def test_missing_state_names_previous_write(tmp_path, env):
    """startFrom startTime on a time directory without grainState.h5 (an
    interrupted write): the message names the previous write holding one.
    (startFrom latestTime skips such a directory: row 7 below.)"""
    case = deposited(tmp_path, "missing", env)
    run("grainFoam", case, env)
    os.remove(os.path.join(case, "0.02", "grainState.h5"))
    set_control(case, startFrom="startTime", startTime="0.02")
    fails_with(
        run("grainFoam", case, env, check=False),
        "Cannot find the grain state",
        "interrupted",
        "previous write 0.01",
        "startTime 0.01",
    )


def test_latestTime_skips_incomplete_time_directory(tmp_path, env):
    """Row 7: the last time directory of an interrupted write (grainState.h5
    missing, a grainState.h5.tmp left) is moved aside with a warning naming
    it, and startFrom latestTime restarts from the previous complete one: the
    rerun rewrites it as the uninterrupted run did (same grain positions)."""
    case = deposited(tmp_path, "incomplete", env)
    run("grainFoam", case, env)
    good = open(os.path.join(case, "0.02", "lagrangian", "grains", "positions")).read()
    os.rename(
        os.path.join(case, "0.02", "grainState.h5"), os.path.join(case, "0.02", "grainState.h5.tmp")
    )
    p = run("grainFoam", case, env)
    out = p.stdout + p.stderr
    assert "0.02 is incomplete" in out and "grainState.h5" in out, out[-3000:]
    assert "moved to 0.02.incomplete" in out and "starts from 0.01" in out
    assert times(case) == ["0", "0.01", "0.02"]
    assert os.path.isdir(os.path.join(case, "0.02.incomplete"))
    assert open(os.path.join(case, "0.02", "lagrangian", "grains", "positions")).read() == good


def test_vansFoam_latestTime_skips_time_without_fluid_fields(tmp_path, env):
    """Row 7 with the fluid: grainState.h5 written but U and p missing (the
    disk filled up after the grains): vansFoam restarts from the previous
    time and reaches the end (the fields of the uninterrupted run)."""
    from test_vansFoam import small_sedimentation

    case = str(tmp_path / "vinc")
    small_sedimentation(case, env, end=0.07, write=0.035)
    run("vansFoam", case, env)
    U = open(os.path.join(case, "0.07", "U")).read()
    for f in ("U", "p"):
        os.remove(os.path.join(case, "0.07", f))
    p = run("vansFoam", case, env)
    out = p.stdout + p.stderr
    assert "0.07 is incomplete (missing: 2(U p))" in out, out[-3000:]
    assert times(case) == ["0", "0.035", "0.07"]
    assert open(os.path.join(case, "0.07", "U")).read() == U
