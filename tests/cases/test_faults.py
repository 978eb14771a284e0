"""Faults of issue 27: every row of its table fails loudly (exit status, the
message's key words) or does what is documented, never hangs, never crashes
on a signal, never exits 0 with grains lost; the earlier results of the case
stay intact.  Small 2D cases (seconds each)."""
import hashlib
import os
import re
import shutil
import signal
import struct
import subprocess
import time

import numpy as np
import pytest

from foamcase import add_fluid, make_box_case, run, write

G = 9.81
MAT = {"glass": {"density": 2500, "friction": 0.4}}


def box(tmp_path, name, grains, end=0.02, dt=1e-3, write_interval=0.01, **kw):
    case = str(tmp_path / name)
    make_box_case(case, (0, 0, 0), (0.1, 0.1, 0.01), (4, 4, 1), (0, -G, 0), MAT,
                  grains=grains, end_time=end, dt=dt, write_interval=write_interval, **kw)
    return case


def set_control(case, **entries):
    """Replace `key value;` entries of system/controlDict."""
    path = os.path.join(case, "system", "controlDict")
    txt = open(path).read()
    for k, v in entries.items():
        txt, n = re.subn(rf"\b{k} [^;]*;", f"{k} {v};", txt)
        assert n == 1, k
    open(path, "w").write(txt)


def digest(case, time_name):
    """Hashes of every file of a time directory (the 'earlier results')."""
    out = {}
    root = os.path.join(case, time_name)
    for d, _, files in os.walk(root):
        for f in files:
            p = os.path.join(d, f)
            out[os.path.relpath(p, root)] = hashlib.sha1(open(p, "rb").read()).hexdigest()
    assert out, root
    return out


def times(case):
    return sorted((t for t in os.listdir(case) if re.fullmatch(r"[0-9.e-]+", t)), key=float)


def fails_with(p, *words):
    out = p.stdout + p.stderr
    assert p.returncode != 0, "expected a failure:\n" + out[-2000:]
    assert "FOAM FATAL" in out, out[-2000:]
    for w in words:
        assert w in out, f"'{w}' missing from:\n{out[-3000:]}"
    # no signal: no stack trace of OpenFOAM's signal handlers
    assert "printStack" not in out and "sigHandler" not in out and "Segmentation" not in out


def poke(path, dataset, index, value):
    """Overwrite element `index` (flat, float64) of a contiguous dataset of an
    HDF5 file (located with h5dump: no h5py here)."""
    hdr = subprocess.run(["h5dump", "-p", "-H", "-d", dataset, path],
                         capture_output=True, text=True, check=True).stdout
    assert "CONTIGUOUS" in hdr, hdr
    off = int(re.search(r"OFFSET (\d+)", hdr).group(1))
    with open(path, "r+b") as f:
        f.seek(off + 8 * index)
        f.write(struct.pack("<d", value))


# ---- row 1: never hang -------------------------------------------------------

def test_substep_cap_stops_with_cause_and_fix(tmp_path, env):
    """A step that needs more sub-steps than contactSolver maxSubSteps stops
    at once with the cause (sub-steps, the fastest grain) and the fix; the
    last write is kept and nothing is written after it."""
    case = box(tmp_path, "cap", [(0.05, 0.05, 0, 0.01)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    before = digest(case, "0.02")
    # a time step 100x too large for a low cap: g dt^2 / (0.1 d) ~ 10 sub-steps
    set_control(case, endTime=1, deltaT=0.1, writeInterval=0.1)
    gp = os.path.join(case, "constant", "grainProperties")
    txt = open(gp).read().replace("maxIterations 5000;", "maxIterations 5000; maxSubSteps 5;")
    open(gp, "w").write(txt)
    t0 = time.time()
    p = run("grainFoam", case, env, check=False)
    assert time.time() - t0 < 60
    fails_with(p, "maxSubSteps = 5", "sub-steps", "grain 0", "Fix", "deltaT",
               "last written time")
    assert times(case) == ["0", "0.01", "0.02"]
    assert digest(case, "0.02") == before
    # a bad value is a keyword error
    open(gp, "w").write(txt.replace("maxSubSteps 5;", "maxSubSteps 0;"))
    fails_with(run("grainFoam", case, env, check=False), "maxSubSteps must be >= 1")


def test_vansFoam_blown_up_fluid_stops(tmp_path, env):
    """Row 1 on the fluid side: a fluid velocity that has blown up (here
    1e4 m/s in the initial field: cell Courant number ~5e4) stops vansFoam
    before the grain step, with the cause and the fix, within seconds;
    0/ stays as it was (the issue's case, dt 100x too large with
    adjustTimeStep no, reached ~1e110 sub-steps and never returned)."""
    case = str(tmp_path / "blowup")
    grains = [(0.01 + 0.02 * i, 0.006, 0, 0.01) for i in range(5)]
    make_box_case(case, (0, 0, 0), (0.1, 0.1, 0.01), (10, 10, 1), (0, -G, 0), MAT,
                  grains=grains, end_time=5, dt=0.05, write_interval=0.05)
    add_fluid(case, 1000, 1e-6, max_dt=0.05)
    open(os.path.join(case, "system", "controlDict"), "a").write("adjustTimeStep no;\n")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    u = os.path.join(case, "0", "U")
    txt = open(u).read()
    open(u, "w").write(txt.replace("uniform (0 0 0)", "uniform (0 1e4 0)"))
    before = digest(case, "0")
    t0 = time.time()
    p = subprocess.run(["vansFoam", "-case", case], env=env, capture_output=True,
                       text=True, timeout=120)
    open(os.path.join(case, "log.vansFoam"), "w").write(p.stdout + p.stderr)
    assert time.time() - t0 < 120
    fails_with(p, "fluid solution blew up", "before the fluid solve", "Courant number",
               "Fix", "adjustTimeStep yes", "last written time")
    assert times(case) == ["0"]
    assert digest(case, "0") == before


# ---- rows 2-3: grains never vanish silently ---------------------------------

def test_wallPatches_typo_is_an_error(tmp_path, env):
    case = box(tmp_path, "typo", [(0.05, 0.05, 0, 0.01)],
               extra_props="wallPatches (walls flor);\n")
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False),
               "wallPatches entry 'flor'", "grainProperties", "Patches", "walls", "frontAndBack")


def open_bottom(case):
    """Make the bottom (y = 0) of a 2D make_box_case box the open patch `bottom`."""
    bm = os.path.join(case, "system", "blockMeshDict")
    txt = open(bm).read()
    txt = txt.replace("walls { type wall; faces ((1 5 4 0) ",
                      "bottom { type patch; faces ((1 5 4 0)); }\nwalls { type wall; faces (")
    open(bm, "w").write(txt)


def test_grainFoam_grain_through_open_patch(tmp_path, env):
    """Row 3: grainFoam with an open bottom: the grain leaves the mesh and the
    run stops naming the open patch (no fall forever, no exit 0); the writes
    before stay."""
    case = box(tmp_path, "open", [(0.05, 0.03, 0, 0.01)], end=0.5, write_interval=0.05)
    open_bottom(case)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    p = run("grainFoam", case, env, check=False)
    fails_with(p, "Grain 0 (grainId 0) left the mesh", "open patch bottom", "type patch", "wallPatches")
    # it fell 0.025 m in ~0.07 s: the run stopped right after, the 0.05 write is intact
    assert "0.05" in times(case)
    assert os.path.isfile(os.path.join(case, "0.05", "grainState.h5"))
    assert not any(float(t) > 0.1 for t in times(case))


def test_grain_through_open_patch_not_in_wallPatches(tmp_path, env):
    """A wall patch left out of wallPatches is open for the grains: named as such."""
    case = box(tmp_path, "notlisted", [(0.05, 0.03, 0, 0.01)], end=0.5, write_interval=0.05,
               extra_props="wallPatches (walls);\n")
    bm = os.path.join(case, "system", "blockMeshDict")
    txt = open(bm).read().replace("walls { type wall; faces ((1 5 4 0) ",
                                  "floor { type wall; faces ((1 5 4 0)); }\n"
                                  "walls { type wall; faces (")
    open(bm, "w").write(txt)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    fails_with(run("grainFoam", case, env, check=False), "open patch floor",
               "not in wallPatches")


# ---- row 4: bad state files -------------------------------------------------

def deposited(tmp_path, name, env):
    case = box(tmp_path, name, [(0.05, 0.006, 0, 0.01), (0.07, 0.006, 0, 0.01)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    return case


def test_nan_and_negative_values_in_state(tmp_path, env):
    for dataset, index, value, words in [
            ("/positions", 3 + 1, float("nan"), ("grain 1", "non-finite position")),
            ("/velocities", 0, float("inf"), ("grain 0", "non-finite velocity")),
            ("/radii", 1, -0.005, ("grain 1", "radius", "> 0"))]:
        case = deposited(tmp_path, "bad" + dataset.strip("/"), env)
        poke(os.path.join(case, "0", "grainState.h5"), dataset, index, value)
        fails_with(run("grainFoam", case, env, check=False), *words, "Cannot use the grain state",
                   "Fix", "grainDeposit")


def test_truncated_state_names_previous_write(tmp_path, env):
    case = deposited(tmp_path, "trunc", env)
    run("grainFoam", case, env)
    path = os.path.join(case, "0.02", "grainState.h5")
    data = open(path, "rb").read()
    open(path, "wb").write(data[:len(data) // 2])
    p = run("grainFoam", case, env, check=False)
    fails_with(p, "damaged or truncated", "previous write 0.01", "startTime 0.01")
    assert os.path.getsize(os.path.join(case, "0.01", "grainState.h5")) > 0


# ---- rows 8-10, 13: solver health and time control --------------------------

def stack(tmp_path, name, **kw):
    # a 2 x 3 stack of touching discs on the floor
    d = 0.01
    grains = [(0.04 + d * 1.0001 * i, d / 2 * 1.0001 + d * j * 1.0001, 0, d) for i in range(2) for j in range(3)]
    return box(tmp_path, name, grains, **kw)


def test_non_converged_contact_steps_are_counted(tmp_path, env):
    case = stack(tmp_path, "notconv", max_iterations=1, contact_tolerance=1e-12)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    p = run("grainFoam", case, env)
    out = p.stdout + p.stderr
    assert out.count("The contact solver did NOT converge at time") == 1, out[-3000:]
    assert "maxIterations" in out
    m = re.search(r"NOT converged in (\d+) of (\d+) grain steps.*worst overlap/d_min (\S+)",
                  out, re.S)
    assert m, out[-2000:]
    assert int(m.group(2)) == 20 and 1 <= int(m.group(1)) <= 20
    assert float(m.group(3)) >= 0


def test_converged_run_summary(tmp_path, env):
    case = stack(tmp_path, "conv")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    out = run("grainFoam", case, env).stdout
    assert "grainCloud summary: 20 grain steps, contact solver converged in all" in out


def test_endTime_before_startTime_warns(tmp_path, env):
    case = box(tmp_path, "endtime", [(0.05, 0.05, 0, 0.01)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    set_control(case, endTime=0.01)   # latestTime = 0.02
    out = run("grainFoam", case, env).stdout
    assert "endTime 0.01 is not after the start time 0.02" in out
    assert "no time step will run" in out


def test_writeInterval_zero_is_an_error(tmp_path, env):
    """OpenFOAM's Time divides by writeInterval (SIGFPE in every application,
    blockMesh included): the project's applications stop before it."""
    case = box(tmp_path, "wi0", [(0.05, 0.05, 0, 0.01)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    set_control(case, writeInterval=0)
    before = digest(case, "0")
    for app in ("grainFoam", "vansFoam", "vansInterFoam", "grainDeposit"):
        fails_with(run(app, case, env, check=False), "writeInterval 0", "controlDict", "> 0")
    assert digest(case, "0") == before


def test_endTime_always_written(tmp_path, env):
    case = box(tmp_path, "endwrite", [(0.05, 0.05, 0, 0.01)], end=0.015)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    out = run("grainFoam", case, env).stdout
    assert times(case) == ["0", "0.01", "0.015"]
    for f in ("grainState.h5", "lagrangian/grains/positions"):
        assert os.path.isfile(os.path.join(case, "0.015", f))
    assert "Progress: 100.0 % of the run" in out
    assert re.search(r"Progress: 66\.7 % of the run, about \d+ s of clock time left", out)


# ---- row 14: lagrangian output on the case's own mesh -----------------------

def positions_cells(case, time_name):
    """Cell index of each grain in lagrangian/grains: from `positions`
    ((x y z) celli) and `coordinates` ((a b c d) celli tetFacei tetPti),
    which must agree."""
    d = os.path.join(case, time_name, "lagrangian", "grains")
    pos = [int(c) for c in re.findall(r"\)\s+(-?\d+)\s*$", open(os.path.join(d, "positions")).read(),
                                      re.M)]
    bary = [int(c) for c in re.findall(r"\)\s+(-?\d+)\s+-?\d+\s+-?\d+\s*$",
                                       open(os.path.join(d, "coordinates")).read(), re.M)]
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
    make_box_case(fine, (0, 0, 0), (0.1, 0.1, 0.01), (20, 20, 1), (0, -G, 0), MAT,
                  grains=grains, end_time=0.002, dt=1e-3, write_interval=0.002)
    run("blockMesh", fine, env)
    run("grainDeposit", fine, env)
    assert max(positions_cells(fine, "0")) > 4
    coarse = str(tmp_path / "coarse")
    make_box_case(coarse, (0, 0, 0), (0.1, 0.1, 0.01), (2, 2, 1), (0, -G, 0), MAT,
                  end_time=0.002, dt=1e-3, write_interval=0.002)
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
    case = stack(tmp_path, "sigterm", end=100, write_interval=50)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    log = open(os.path.join(case, "log.grainFoam"), "w")
    proc = subprocess.Popen(["grainFoam", "-case", case], env=env, stdout=log,
                            stderr=subprocess.STDOUT, text=True)
    deadline = time.time() + 60
    while time.time() < deadline:
        time.sleep(0.5)
        if "Time = 0.05" in open(os.path.join(case, "log.grainFoam")).read():
            break
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=60) == 0
    log.close()
    out = open(os.path.join(case, "log.grainFoam")).read()
    assert "Stop signal 15 (SIGTERM) received: wrote time" in out
    last = times(case)[-1]
    assert float(last) >= 0.05
    assert os.path.isfile(os.path.join(case, last, "grainState.h5"))
    # and the run continues from it
    set_control(case, endTime=float(last) + 0.002)
    out = run("grainFoam", case, env).stdout
    assert f"Create time" in out and "End" in out


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
    for f in ("U", "p", os.path.join("lagrangian", "grains", "positions"),
              os.path.join("lagrangian", "grains", "U"), "uniform/time"):
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
    fails_with(p, "Writing the grain state", "no space left on device",
               "the empty time directory was removed")
    assert times(case) == ["0"]
    # and the run restarts as if nothing happened
    set_control(case, startFrom="latestTime")
    run("grainFoam", case, env)
    assert times(case) == ["0", "0.01", "0.02"]
    assert not any(f.endswith(".tmp") for f in os.listdir(os.path.join(case, "0.02")))


# ---- row 6: parallel state ---------------------------------------------------

def test_reconstructPar_carries_grain_state(tmp_path, env):
    """decomposePar, a parallel run, reconstructPar: the reconstructed time
    directories hold grainState.h5 (written by the master into the
    undecomposed case), and a serial run continues from the last one."""
    from foamcase import run_parallel
    case = stack(tmp_path, "par")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run_parallel("grainFoam", case, env, n=2)
    p = run("reconstructPar", case, env)
    # the state file carries a FoamFile header (HDF5 user block): neither
    # decomposePar nor reconstructPar warns about it
    for app in ("decomposePar", "reconstructPar"):
        log = open(os.path.join(case, f"log.{app}")).read()
        assert "FoamFile" not in log and "grainState" not in log, log[-2000:]
    for t in ("0.01", "0.02"):
        assert os.path.isfile(os.path.join(case, t, "grainState.h5"))
        assert os.path.isfile(os.path.join(case, t, "lagrangian", "grains", "positions"))
    a = open(os.path.join(case, "0.02", "grainState.h5"), "rb").read()
    b = open(os.path.join(case, "processor0", "0.02", "grainState.h5"), "rb").read()
    assert a == b
    shutil.rmtree(os.path.join(case, "processor0"))
    shutil.rmtree(os.path.join(case, "processor1"))
    set_control(case, endTime=0.03)
    out = run("grainFoam", case, env).stdout
    assert "Create time" in out and times(case)[-1] == "0.03"


# ---- row 11: grainDeposit region against the mesh bounds --------------------

def deposit_box(lo, hi, n=20, dmin=2e-3):
    return (f"material glass;\nmethod box;\nbox {{ min {lo}; max {hi}; }}\n"
            f"number {n};\ndMin {dmin};\nseed 3;\n"
            "settle { maxTime 0.5; deltaT 5e-4; speedTolerance 2e-3; }\n")


def test_deposit_box_in_mm_on_mesh_in_m(tmp_path, env):
    """A box given in mm on a mesh in m: the nodes outside the mesh bounds are
    not searched (the issue's case searched ~4e8 nodes for 40 min); the log
    says the region was clipped; a region away from the mesh is an error at
    once."""
    case = box(tmp_path, "mm", [], deposit=deposit_box("(0 0 0)", "(100 100 10)"))
    run("blockMesh", case, env)
    t0 = time.time()
    p = run("grainDeposit", case, env)
    assert time.time() - t0 < 30
    assert "extends beyond the mesh bounds" in p.stdout
    case = box(tmp_path, "away", [], deposit=deposit_box("(10 10 0)", "(20 20 0.01)"))
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), "does not intersect the mesh bounds",
               "grainDepositDict", "in mm on a mesh in m")


def test_sigusr1_to_mpirun_writes_and_stops(tmp_path, env):
    """In parallel, SIGUSR1 sent to mpirun (Open MPI forwards it to every
    rank) writes the current step on every rank and in the undecomposed case
    and stops with exit 0 (SIGTERM to mpirun kills the ranks: README)."""
    import pytest
    case = stack(tmp_path, "sigpar", end=100, write_interval=50)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    write(os.path.join(case, "system", "decomposeParDict"), "dictionary", "decomposeParDict",
          "numberOfSubdomains 2;\nmethod simple;\nsimpleCoeffs { n (2 1 1); delta 0.001; }\n")
    run("decomposePar", case, env)
    logp = os.path.join(case, "log.grainFoam")
    with open(logp, "w") as log:
        proc = subprocess.Popen(["mpirun", "-np", "2", "grainFoam", "-parallel", "-case", case],
                                env=env, stdout=log, stderr=subprocess.STDOUT, text=True)
        deadline = time.time() + 60
        while time.time() < deadline and "Time = 0.05" not in open(logp).read():
            time.sleep(0.5)
            if proc.poll() is not None:
                break
        if proc.poll() is not None:
            pytest.skip("mpirun cannot start here: " + open(logp).read()[-300:])
        proc.send_signal(signal.SIGUSR1)
        assert proc.wait(timeout=60) == 0
    out = open(logp).read()
    m = re.search(r"Stop signal 10 \(SIGUSR1\) received: wrote time (\S+) ", out)
    assert m, out[-2000:]
    t = m.group(1)
    for d in ("processor0", "processor1", "."):
        assert os.path.isfile(os.path.join(case, d, t, "grainState.h5")), d


def test_vansFoam_grain_through_open_patch(tmp_path, env):
    """vansFoam (3D): a grain sinking through the open bottom patch `inlet`
    is reported as such (it was 'move the grain inside the domain')."""
    from foamcase import uniform_inflow
    case = str(tmp_path / "vopen")
    make_box_case(case, (0, 0, 0), (0.04, 0.04, 0.04), (4, 4, 4), (0, -G, 0), MAT,
                  grains=[(0.02, 0.012, 0.02, 0.01)], end_time=0.5, dt=1e-3,
                  write_interval=0.05, two_d=False)
    add_fluid(case, 1000, 1e-6, max_dt=1e-3)
    uniform_inflow(case, 0.0)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    p = run("vansFoam", case, env, check=False)
    fails_with(p, "Grain 0 (grainId 0) left the mesh", "open patch inlet", "type patch")
    assert "0.05" in times(case)


def test_missing_state_names_previous_write(tmp_path, env):
    """startFrom startTime on a time directory without grainState.h5 (an
    interrupted write): the message names the previous write holding one.
    (startFrom latestTime skips such a directory: row 7 below.)"""
    case = deposited(tmp_path, "missing", env)
    run("grainFoam", case, env)
    os.remove(os.path.join(case, "0.02", "grainState.h5"))
    set_control(case, startFrom="startTime", startTime="0.02")
    fails_with(run("grainFoam", case, env, check=False), "Cannot find the grain state",
               "interrupted", "previous write 0.01", "startTime 0.01")


def test_latestTime_skips_incomplete_time_directory(tmp_path, env):
    """Row 7: the last time directory of an interrupted write (grainState.h5
    missing, a grainState.h5.tmp left) is moved aside with a warning naming
    it, and startFrom latestTime restarts from the previous complete one: the
    rerun rewrites it as the uninterrupted run did (same grain positions)."""
    case = deposited(tmp_path, "incomplete", env)
    run("grainFoam", case, env)
    good = open(os.path.join(case, "0.02", "lagrangian", "grains", "positions")).read()
    os.rename(os.path.join(case, "0.02", "grainState.h5"),
              os.path.join(case, "0.02", "grainState.h5.tmp"))
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


def test_wall_patch_retyped_after_deposit(tmp_path, env):
    """Row 3, second case: the floor retyped to an open patch after
    grainDeposit: the state's walls no longer match the mesh's, an error at
    start (not grains falling through)."""
    case = box(tmp_path, "retyped", [(0.05, 0.03, 0, 0.01)], end=0.5, write_interval=0.05)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    open_bottom(case)
    run("blockMesh", case, env)
    fails_with(run("grainFoam", case, env, check=False), "walls but the wall patches",
               "re-run grainDeposit")


# ---- row 3 / item 4: grains through open boundaries (outletPatches) ---------

#: discs (x, y, z, d) falling freely in separate columns through the open
#: bottom `bottom` (y = 0) of the 0.1 m box: each leaves when its centre
#: crosses y = 0, at t = sqrt(2 y0/g) = 0.064 ... 0.132 s
OUTLET_GRAINS = [(0.015, 0.020, 0, 0.008), (0.030, 0.035, 0, 0.010),
                 (0.045, 0.045, 0, 0.006), (0.060, 0.060, 0, 0.010),
                 (0.075, 0.070, 0, 0.008), (0.090, 0.085, 0, 0.006)]
DEPTH = 0.01   # mesh depth [m] of box(): 2D masses are over it


def outlet_case(tmp_path, name, env, end):
    case = box(tmp_path, name, OUTLET_GRAINS, end=end, write_interval=0.05,
               extra_props="outletPatches (bottom);\n")
    open_bottom(case)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    return case


def disc_mass(d):
    """Mass [kg] of a glass disc over the mesh depth (input data, not the code's)."""
    return MAT["glass"]["density"] * np.pi * (d / 2) ** 2 * DEPTH


def outlet_rows(case, start):
    path = os.path.join(case, "postProcessing", "grainOutlets", start, "grainOutlets.dat")
    rows = [ln.split() for ln in open(path) if not ln.startswith("#")]
    return [(float(t), p, int(n), float(m), int(tn), float(tm)) for t, p, n, m, tn, tm in rows]


def remaining(case, t):
    """Grain ids and diameters of the lagrangian cloud of time t (none: empty)."""
    from nscdpost import read_grains
    d = os.path.join(case, t, "lagrangian", "grains")
    if not os.path.isfile(os.path.join(d, "grainId")):
        return [], []
    g = read_grains(case, t)
    return [int(round(i)) for i in g["grainId"]], list(g["d"])


def test_grains_leave_through_outlet_and_are_counted(tmp_path, env):
    """Item 4: discs falling through the open bottom listed in outletPatches
    are removed when their centre crosses it (at the free-fall time
    sqrt(2 y0/g), analytical), counted per patch in the log, in
    postProcessing/grainOutlets and <time>/uniform/grainOutlets; exit 0.
    Conservation (independent of the code's masses: the input diameters):
    grains remaining + removed = initial, by number and mass.  A restart
    from the last write continues the counts; removed ids are not reused."""
    case = outlet_case(tmp_path, "outlet", env, end=0.1)
    p = run("grainFoam", case, env)
    out = p.stdout
    removed = re.findall(r"grainOutlets: (\d+) grains \(mass (\S+) kg\) left through bottom"
                         r" at time (\S+), ids ([\d ]+);", out)
    assert len(removed) == 3, out[-3000:]
    m0 = [disc_mass(g[3]) for g in OUTLET_GRAINS]
    for n, mass, t, ids in removed:
        (i,) = [int(k) for k in ids.split()]
        y0 = OUTLET_GRAINS[i][1]
        # free fall: the centre crosses y = 0 at sqrt(2 y0/g) to within the
        # steps (the symplectic Euler fall y0 - g dt^2 n (n + 1)/2 leads the
        # continuous one by g dt t/2, so the crossing may come a step early)
        assert abs(float(t) - np.sqrt(2 * y0 / G)) < 2e-3, (i, t)
        assert float(mass) == pytest.approx(m0[i], rel=1e-12)
    rows = outlet_rows(case, "0")
    assert [r[4] for r in rows] == [1, 2, 3]
    ids, ds = remaining(case, "0.1")
    assert sorted(ids) == [3, 4, 5]
    assert rows[-1][4] + len(ids) == len(OUTLET_GRAINS)
    assert rows[-1][5] + sum(disc_mass(d) for d in ds) == pytest.approx(sum(m0), rel=1e-12)
    assert "grains 3;" in open(os.path.join(case, "0.1", "uniform", "grainOutlets")).read()
    assert "grainOutlets summary (since the case started): bottom 3 grains" in out

    # restart from the last write: the counts continue, every grain leaves
    set_control(case, endTime=0.2)
    out = run("grainFoam", case, env).stdout
    assert "outlet counts continued" in out
    rows = outlet_rows(case, "0.1")
    assert [r[4] for r in rows] == [4, 5, 6]
    assert rows[-1][5] == pytest.approx(sum(m0), rel=1e-12)
    assert remaining(case, "0.2") == ([], [])
    assert "grains 6;" in open(os.path.join(case, "0.2", "uniform", "grainOutlets")).read()


def test_outlet_patch_must_be_open(tmp_path, env):
    """outletPatches naming a wall patch of the grains, or no patch, is an error."""
    case = box(tmp_path, "wallout", [(0.05, 0.05, 0, 0.01)], extra_props="outletPatches (walls);\n")
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), "outletPatches",
               "wall for the grains", "Fix")
    case = box(tmp_path, "typoout", [(0.05, 0.05, 0, 0.01)], extra_props="outletPatches (botom);\n")
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), "outletPatches entry 'botom'",
               "matches no patch")


def test_grains_leave_through_outlet_in_parallel(tmp_path, env):
    """The outlet case on 2 ranks (x slabs: each grain crosses the bottom on
    one rank): every rank removes the same grains, the counts and times are
    those of the serial run."""
    from foamcase import run_parallel
    serial = outlet_case(tmp_path, "serial", env, end=0.15)
    run("grainFoam", serial, env)
    par = outlet_case(tmp_path, "par", env, end=0.15)
    run_parallel("grainFoam", par, env, n=2)
    a, b = outlet_rows(serial, "0"), outlet_rows(par, "0")
    assert len(a) == 6 and [r[:5] for r in a] == [r[:5] for r in b]
    for ra, rb in zip(a, b):
        assert ra[5] == pytest.approx(rb[5], rel=1e-12)
    for proc in ("processor0", "processor1"):
        assert "grains 6;" in open(os.path.join(par, proc, "0.15", "uniform", "grainOutlets")).read()


def test_vansFoam_grain_leaves_through_outlet(tmp_path, env):
    """vansFoam (3D): with outletPatches (inlet) the grain sinking through
    the open bottom is removed and the run goes on (vansCloud compacts its
    per-grain lists: the remaining grain's fluid force is written); exit 0,
    grains remaining + removed = initial."""
    from foamcase import uniform_inflow
    case = str(tmp_path / "voutlet")
    make_box_case(case, (0, 0, 0), (0.04, 0.04, 0.04), (4, 4, 4), (0, -G, 0), MAT,
                  grains=[(0.01, 0.012, 0.02, 0.01), (0.03, 0.033, 0.02, 0.01)],
                  end_time=0.09, dt=1e-3, write_interval=0.03, two_d=False,
                  extra_props="outletPatches (inlet);\n")
    add_fluid(case, 1000, 1e-6, max_dt=1e-3)
    uniform_inflow(case, 0.0)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    out = run("vansFoam", case, env).stdout
    assert re.search(r"grainOutlets: 1 grains \(mass \S+ kg\) left through inlet at time \S+, ids 0;",
                     out), out[-3000:]
    last = times(case)[-1]
    ids, ds = remaining(case, last)
    assert ids == [1]
    from nscdpost import read_grains
    assert read_grains(case, last)["Ffluid"].shape == (1, 3)
    rows = outlet_rows(case, "0")
    assert rows[-1][4] + len(ids) == 2
    m = MAT["glass"]["density"] * np.pi / 6 * 0.01 ** 3
    assert rows[-1][5] == pytest.approx(m, rel=1e-12)
