# SPDX-License-Identifier: GPL-3.0-or-later
"""Faults of run control: never hang (sub-step cap, a blown-up
fluid), solver health and time control (rows 1, 8-10, 11, 13); every row
fails loudly (exit status, the message's key words) or does what is
documented; the earlier results of the case stay intact.  Small 2D cases
(seconds each); helpers in faultcase.py."""

import math
import os
import subprocess
import time

import nscdpost
import pytest
from faultcase import MAT, G, box, digest, set_control, stack, times
from foamcase import (
    add_fluid,
    decompose,
    fails_with,
    log_message,
    make_box_case,
    run,
    run_parallel,
    write,
)

pytestmark = pytest.mark.fast


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
    fails_with(p, "maxSubSteps = 5", "sub-steps", "grain 0", "Fix", "deltaT", "last written time")
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
    make_box_case(
        case,
        (0, 0, 0),
        (0.1, 0.1, 0.01),
        (10, 10, 1),
        (0, -G, 0),
        MAT,
        grains=grains,
        end_time=5,
        dt=0.05,
        write_interval=0.05,
    )
    add_fluid(case, 1000, 1e-6, max_dt=0.05)
    open(os.path.join(case, "system", "controlDict"), "a").write("adjustTimeStep no;\n")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    u = os.path.join(case, "0", "U")
    txt = open(u).read()
    open(u, "w").write(txt.replace("uniform (0 0 0)", "uniform (0 1e4 0)"))
    before = digest(case, "0")
    t0 = time.time()
    p = subprocess.run(
        ["vansFoam", "-case", case], env=env, capture_output=True, text=True, timeout=120
    )
    open(os.path.join(case, "log.vansFoam"), "w").write(p.stdout + p.stderr)
    assert time.time() - t0 < 120
    fails_with(
        p,
        "fluid solution blew up",
        "before the fluid solve",
        "Courant number",
        "Fix",
        "adjustTimeStep yes",
        "last written time",
    )
    assert times(case) == ["0"]
    assert digest(case, "0") == before


def test_vansFoam_diverging_momentum_solve_stops_with_cause(tmp_path, env):
    """A coupled momentum solve that diverges (30 discs settling with a
    fixed time step of 0.2 s, 100x what maxCo 0.5 allows: cell Courant
    number 31 after the first step, and the smoothSolver's Gauss-Seidel
    iteration on the far from diagonally dominant matrix of the second
    step overflows) stops with a FatalError naming the equation, its
    residuals, the Courant number and the fix; it ended in a SIGFPE inside
    the smoother before (stack trace only).  The write of the first step
    is intact."""
    from test_vansFoam import small_sedimentation

    case = str(tmp_path / "diverge")
    small_sedimentation(case, env, end=2.0, write=0.2)
    set_control(case, deltaT=0.2, adjustTimeStep="no")
    p = run("vansFoam", case, env, check=False)
    fails_with(
        p,
        "The momentum predictor diverged at time 0.4",
        "not finite",
        "final residual (nan",
        "Courant number",
        "last written time",
        "Fix",
        "adjustTimeStep yes",
    )
    assert times(case) == ["0", "0.2"]
    assert os.path.isfile(os.path.join(case, "0.2", "grainState.h5"))
    assert os.path.isfile(os.path.join(case, "0.2", "U"))


# ---- rows 8-10, 13: solver health and time control --------------------------


def test_non_converged_contact_steps_are_counted(tmp_path, env):
    case = stack(tmp_path, "notconv", max_iterations=1, contact_tolerance=1e-12)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    p = run("grainFoam", case, env)
    out = p.stdout + p.stderr
    assert out.count("The contact solver did NOT converge at time") == 1, out[-3000:]
    assert "maxIterations" in out
    m = log_message(
        out, r"NOT converged in (\d+) of (\d+) grain steps(?:.|\n)*worst overlap/d_min (\S+)"
    )
    assert int(m.group(2)) == 20 and 1 <= int(m.group(1)) <= 20
    assert float(m.group(3)) >= 0
    # capped solves of this stack would have raised the kinetic energy; the
    # summary says so and by which factor the impulses were scaled (nscd
    # limitCappedEnergy: the step dissipates)
    e = log_message(
        out,
        r"In (\d+) of them the impulses of the unconverged solve would have raised the"
        r" kinetic energy \(by up to (\S+) of the free-flight energy\); they were scaled"
        r" down \(factor >= (\S+)\)",
    )
    assert 1 <= int(e.group(1)) <= int(m.group(1))
    assert float(e.group(2)) > 0 and 0 <= float(e.group(3)) < 1


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
    set_control(case, endTime=0.01)  # latestTime = 0.02
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
    log_message(out, r"Progress: 66\.7 % of the run, about \d+ s of clock time left")


# ---- never overwrite results: a second solver, a decomposed restart ---------
def _host(out):
    """The host name of an OpenFOAM banner (`Host   : vm`)."""
    return log_message(out, r'^Host\s*:\s*"?([^\s"]+)').group(1)


def test_second_solver_in_the_case_is_refused(tmp_path, env):
    """The lock file <case>/.nscdFoam.lock (process id, host, application)
    refuses a second solver in a case while the first runs, and a lock of
    another host (it cannot be checked); a lock left by a process that no
    longer runs (kill -9) is taken over with a warning; a run that ends
    removes its lock.  The earlier results stay intact."""
    case = box(tmp_path, "lock", [(0.05, 0.05, 0, 0.01)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    out = run("grainFoam", case, env).stdout
    lock = os.path.join(case, ".nscdFoam.lock")
    assert not os.path.exists(lock)
    host = _host(out)
    before = digest(case, "0.02")
    set_control(case, endTime=0.03)
    for holder in (f"{os.getpid()} {host} vansFoam", "1 otherhost vansFoam"):
        with open(lock, "w") as f:
            f.write(holder + "\n")
        fails_with(
            run("grainFoam", case, env, check=False),
            "vansFoam (process",
            "runs in this case",
            ".nscdFoam.lock",
            "Fix",
        )
        assert times(case)[-1] == "0.02" and digest(case, "0.02") == before
    gone = subprocess.Popen(["true"])
    gone.wait()
    with open(lock, "w") as f:
        f.write(f"{gone.pid} {host} grainFoam\n")
    p = run("grainFoam", case, env)
    assert "taking over the lock file" in p.stdout + p.stderr
    assert times(case)[-1] == "0.03" and not os.path.exists(lock)


@pytest.mark.mpi
def test_decomposed_restart_before_later_writes_is_refused(tmp_path, env):
    """A 2-rank grainFoam run continued on 3 ranks after a fresh
    decomposePar without reconstructPar (the new processor directories start at 0, the
    case holds the grain states of 0.01 and 0.02) stops with the fix
    instead of restarting from 0 over the earlier writes; with the fix
    (the time directory 0.02 in each processor directory: the grain state
    is whole in the case) it continues from 0.02 with every grain."""
    case = box(tmp_path, "redecomp", [(0.03 + 0.012 * i, 0.05, 0, 0.01) for i in range(4)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run_parallel("grainFoam", case, env, n=2)
    before = digest(case, "0.02")
    set_control(case, endTime=0.03)
    # a fresh decomposition (-force replaces the processor directories): the
    # time directories of the case hold only the grain state (no field), so
    # the new processor directories start at 0
    decompose(case, env, n=3)
    mpi = ["mpirun", "-np", "3", "grainFoam", "-parallel", "-case", case]
    p = subprocess.run(mpi, env=env, capture_output=True, text=True)
    out = fails_with(p, "holds the grain state of t = 0.02", "reconstructPar -latestTime")
    assert "Time = 0.001" not in out
    assert digest(case, "0.02") == before
    for r in range(3):
        os.makedirs(os.path.join(case, f"processor{r}", "0.02"))
    p = subprocess.run(mpi, env=env, capture_output=True, text=True)
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    assert "Time = 0.021" in p.stdout and "Time = 0.001" not in p.stdout
    ids = nscdpost.read_h5(os.path.join(case, "0.03", "grainState.h5"), "/grainIds")
    assert sorted(int(i) for i in ids) == [0, 1, 2, 3]


@pytest.mark.mpi
def test_decomposed_restart_after_an_interrupted_write(tmp_path, env):
    """The check above leaves an interrupted write alone: a 2-rank run whose
    latest write is incomplete on one rank (a *.tmp left in processor1/0.02,
    the grain state of 0.02 complete in the case) restarts from 0.01 and
    redoes 0.02, as skipIncompleteTimes documents."""
    case = box(tmp_path, "interrupted", [(0.03 + 0.012 * i, 0.05, 0, 0.01) for i in range(4)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run_parallel("grainFoam", case, env, n=2)
    open(os.path.join(case, "processor1", "0.02", "junk.tmp"), "w").close()
    set_control(case, endTime=0.03)
    mpi = ["mpirun", "-np", "2", "grainFoam", "-parallel", "-case", case]
    p = subprocess.run(mpi, env=env, capture_output=True, text=True)
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    assert "moved to 0.02.incomplete" in p.stdout + p.stderr
    assert "Time = 0.011" in p.stdout and "Time = 0.03" in p.stdout


# ---- row 11: grainDeposit region against the mesh bounds --------------------


def deposit_box(lo, hi, n=20, dmin=2e-3):
    return (
        f"material glass;\nmethod box;\nbox {{ min {lo}; max {hi}; }}\n"
        f"number {n};\ndMin {dmin};\nseed 3;\n"
        "settle { maxTime 0.5; deltaT 5e-4; speedTolerance 2e-3; }\n"
    )


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
    fails_with(
        run("grainDeposit", case, env, check=False),
        "does not intersect the mesh bounds",
        "grainDepositDict",
        "in mm on a mesh in m",
    )


def test_deposit_few_small_grains_in_a_large_box(tmp_path, env):
    """Two 1 um discs in a 0.1 m box: the insertion lattice has ~8e9 nodes
    (spacing 1.1 d_max), which grainDeposit used to list and sort in full
    (one 10 um sphere in a 3 cm box: 7 GB and no end); it now walks the
    lattice bottom first and stops at the grains asked for, so the cost
    follows the grain count.  The grains sit on the lowest lattice row."""
    case = box(
        tmp_path, "tiny", [], deposit=deposit_box("(0 0 0)", "(0.1 0.1 0.01)", n=2, dmin=1e-6)
    )
    run("blockMesh", case, env)
    t0 = time.time()
    p = run("grainDeposit", case, env)
    assert time.time() - t0 < 30
    assert "Placed 2 grains" in p.stdout, p.stdout[-2000:]


def test_deposit_region_errors_name_the_keyword(tmp_path, env):
    """A box with min and max swapped, `number 0` and an empty cellZone
    each stop grainDeposit with a FatalIOError naming grainDepositDict, the
    keyword and the fix (they gave "holds 0 grains" and a region "in mm on
    a mesh in m"); the deposit written before stays."""
    cases = [
        (
            "swapped",
            deposit_box("(0.1 0.1 0)", "(0 0 0.01)"),
            ("max.x is not above min.x", "swap them"),
        ),
        ("none", deposit_box("(0 0 0)", "(0.1 0.1 0.01)", n=0), ("number 0", "at least one grain")),
        (
            "emptyZone",
            deposit_box("(0 0 0)", "(0.1 0.1 0.01)").replace(
                "method box;", "method cellZone;\ncellZone empty;"
            ),
            ("cellZone empty", "holds no cells", "topoSet"),
        ),
    ]
    for name, deposit, words in cases:
        case = box(tmp_path, name, [(0.05, 0.05, 0, 0.01)])
        run("blockMesh", case, env)
        run("grainDeposit", case, env)
        before = digest(case, "0")
        if name == "emptyZone":
            deposit = deposit.replace("box { min (0 0 0); max (0.1 0.1 0.01); }\n", "")
            write(
                os.path.join(case, "constant", "polyMesh", "cellZones"),
                "regIOobject",
                "cellZones",
                "1\n(\nempty\n{\n    type cellZone;\n    cellLabels List<label> 0();\n}\n)\n",
            )
        write(
            os.path.join(case, "system", "grainDepositDict"),
            "dictionary",
            "grainDepositDict",
            deposit,
        )
        fails_with(
            run("grainDeposit", case, env, check=False),
            "grainDepositDict",
            "Fix",
            *words,
            banner="FOAM FATAL IO ERROR",
        )
        assert digest(case, "0") == before, name


def test_deposit_against_slanted_walls(tmp_path, env):
    """A box deposit over a 2D box whose side walls lean by 30 deg (the
    region is the mesh's bounding box): every grain clears both slanted
    walls (distance from its centre >= its radius; grainDeposit used to
    test only that the centre was in a cell, and placed grains across the
    walls).  Reference: the walls' lines x = s y and x = W + s y."""
    from test_vansFoam import shear_box

    s = math.tan(math.radians(30))
    width, height = 0.1, 0.1
    case = box(
        tmp_path,
        "slanted",
        [],
        deposit=deposit_box("(0 0 0)", f"({width + s * height} {height} 0.01)", n=40, dmin=8e-3)
        .replace("seed 3;", "seed 3;\nsizeRatio 1.25;")
        .replace("settle { maxTime 0.5; deltaT 5e-4; speedTolerance 2e-3; }\n", ""),
    )
    shear_box(case, s)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    state = os.path.join(case, "0", "grainState.h5")
    x = nscdpost.read_h5(state, "/positions", 3)
    r = nscdpost.read_h5(state, "/radii")
    assert len(r) == 40
    left = (x[:, 0] - s * x[:, 1]) / math.hypot(1, s)
    right = (width + s * x[:, 1] - x[:, 0]) / math.hypot(1, s)
    assert (left >= r * (1 - 1e-9)).all(), (left / r).min()
    assert (right >= r * (1 - 1e-9)).all(), (right / r).min()
    # the lattice still reaches the walls: the nearest grain is within a spacing
    assert min(left.min(), right.min()) < 2 * r.max()
