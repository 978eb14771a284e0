# SPDX-License-Identifier: GPL-3.0-or-later
"""Faults at the boundaries: grains never vanish silently
(rows 2-3: wallPatches typos, open patches, a wall retyped after the
deposit) and grains leaving through the open boundaries listed in
outletPatches are removed and counted (item 4).  Small 2D cases (seconds
each) and two small 3D vansFoam cases; helpers in faultcase.py."""

import os

import numpy as np
import pytest
from faultcase import MAT, G, box, open_bottom_cube, set_control, times
from foamcase import fails_with, log_message, replace_in, run

pytestmark = pytest.mark.fast


# ---- rows 2-3: grains never vanish silently ---------------------------------


def test_wallPatches_typo_is_an_error(tmp_path, env):
    case = box(tmp_path, "typo", [(0.05, 0.05, 0, 0.01)], extra_props="wallPatches (walls flor);\n")
    run("blockMesh", case, env)
    fails_with(
        run("grainDeposit", case, env, check=False),
        "wallPatches entry 'flor'",
        "grainProperties",
        "Patches",
        "walls",
        "frontAndBack",
    )


def open_bottom(case):
    """Make the bottom (y = 0) of a 2D make_box_case box the open patch `bottom`."""
    split_bottom(case, "bottom { type patch; faces ((1 5 4 0)); }")


def split_bottom(case, patch):
    """Take the bottom face (y = 0) of a 2D make_box_case box out of its
    patch `walls` into patch (an entry of the blockMeshDict boundary)."""
    replace_in(
        os.path.join(case, "system", "blockMeshDict"),
        ("walls { type wall; faces ((1 5 4 0) ", f"{patch}\nwalls {{ type wall; faces ("),
    )


def test_grainFoam_grain_through_open_patch(tmp_path, env):
    """Row 3: grainFoam with an open bottom: the grain leaves the mesh and the
    run stops naming the open patch (no fall forever, no exit 0); the writes
    before stay."""
    case = box(tmp_path, "open", [(0.05, 0.03, 0, 0.01)], end=0.5, write_interval=0.05)
    open_bottom(case)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    p = run("grainFoam", case, env, check=False)
    fails_with(
        p, "Grain 0 (grainId 0) left the mesh", "open patch bottom", "type patch", "wallPatches"
    )
    # it fell 0.025 m in ~0.07 s: the run stopped right after, the 0.05 write is intact
    assert "0.05" in times(case)
    assert os.path.isfile(os.path.join(case, "0.05", "grainState.h5"))
    assert not any(float(t) > 0.1 for t in times(case))


def test_grain_through_open_patch_not_in_wallPatches(tmp_path, env):
    """A wall patch left out of wallPatches is open for the grains: named as such."""
    case = box(
        tmp_path,
        "notlisted",
        [(0.05, 0.03, 0, 0.01)],
        end=0.5,
        write_interval=0.05,
        extra_props="wallPatches (walls);\n",
    )
    split_bottom(case, "floor { type wall; faces ((1 5 4 0)); }")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    fails_with(run("grainFoam", case, env, check=False), "open patch floor", "not in wallPatches")


def test_vansFoam_grain_through_open_patch(tmp_path, env):
    """vansFoam (3D): a grain sinking through the open bottom patch `inlet`
    is reported as such (it was 'move the grain inside the domain')."""
    case = str(tmp_path / "vopen")
    open_bottom_cube(case, env, [(0.02, 0.012, 0.02, 0.01)], end=0.5, write_interval=0.05)
    p = run("vansFoam", case, env, check=False)
    fails_with(p, "Grain 0 (grainId 0) left the mesh", "open patch inlet", "type patch")
    assert "0.05" in times(case)


def test_wall_patch_retyped_after_deposit(tmp_path, env):
    """Row 3, second case: the floor retyped to an open patch after
    grainDeposit: the state's walls no longer match the mesh's, an error at
    start (not grains falling through)."""
    case = box(tmp_path, "retyped", [(0.05, 0.03, 0, 0.01)], end=0.5, write_interval=0.05)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    open_bottom(case)
    run("blockMesh", case, env)
    fails_with(
        run("grainFoam", case, env, check=False),
        "walls but the wall patches",
        "re-run grainDeposit",
    )


# ---- row 3 / item 4: grains through open boundaries (outletPatches) ---------

#: discs (x, y, z, d) falling freely in separate columns through the open
#: bottom `bottom` (y = 0) of the 0.1 m box: each leaves when its centre
#: crosses y = 0, at t = sqrt(2 y0/g) = 0.064 ... 0.132 s
OUTLET_GRAINS = [
    (0.015, 0.020, 0, 0.008),
    (0.030, 0.035, 0, 0.010),
    (0.045, 0.045, 0, 0.006),
    (0.060, 0.060, 0, 0.010),
    (0.075, 0.070, 0, 0.008),
    (0.090, 0.085, 0, 0.006),
]
DEPTH = 0.01  # mesh depth [m] of box(): 2D masses are over it


def outlet_case(tmp_path, name, env, end):
    case = box(
        tmp_path,
        name,
        OUTLET_GRAINS,
        end=end,
        write_interval=0.05,
        extra_props="outletPatches (bottom);\n",
    )
    open_bottom(case)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    return case


def disc_mass(d):
    """Mass [kg] of a glass disc over the mesh depth (input data, not the code's)."""
    return MAT["glass"]["density"] * np.pi * (d / 2) ** 2 * DEPTH


def outlet_rows(case, start):
    """(time, patch, grains, mass, total grains, total mass) of the steps in
    which grains left through the (one) outlet patch, from grainOutlets.dat
    (a row per step, the columns <patch>_grains, _mass, _totalGrains,
    _totalMass)."""
    import nscdpost

    path = os.path.join(case, "postProcessing", "grainOutlets", start, "grainOutlets.dat")
    cols = nscdpost.dat_columns(path)
    assert cols[0] == "Time" and len(cols) == 5 and cols[1].endswith("_grains"), cols
    p = cols[1][: -len("_grains")]
    a = np.loadtxt(path, ndmin=2)
    return [(float(r[0]), p, int(r[1]), float(r[2]), int(r[3]), float(r[4])) for r in a if r[1] > 0]


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
    removed = log_message(
        out,
        r"grainOutlets: (\d+) grains \(mass (\S+) kg\) left through bottom"
        r" at time (\S+), ids ([\d ]+);",
        every=True,
    )
    assert len(removed) == 3, out[-3000:]
    m0 = [disc_mass(g[3]) for g in OUTLET_GRAINS]
    for _n, mass, t, ids in removed:
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
    fails_with(
        run("grainDeposit", case, env, check=False), "outletPatches", "wall for the grains", "Fix"
    )
    case = box(tmp_path, "typoout", [(0.05, 0.05, 0, 0.01)], extra_props="outletPatches (botom);\n")
    run("blockMesh", case, env)
    fails_with(
        run("grainDeposit", case, env, check=False),
        "outletPatches entry 'botom'",
        "matches no patch",
    )


@pytest.mark.mpi
def test_grains_leave_through_outlet_in_parallel(tmp_path, env):
    """The outlet case on 2 ranks (x slabs, the grains decomposed: each
    grain crosses the bottom on one rank, which removes it): the counts and
    times are those of the serial run, and every rank writes the totals."""
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
        assert (
            "grains 6;" in open(os.path.join(par, proc, "0.15", "uniform", "grainOutlets")).read()
        )


def test_vansFoam_grain_leaves_through_outlet(tmp_path, env):
    """vansFoam (3D): with outletPatches (inlet) the grain sinking through
    the open bottom is removed and the run goes on (vansCloud compacts its
    per-grain columns follow the grains: the remaining grain's fluid force is
    written); exit 0,
    grains remaining + removed = initial."""
    case = str(tmp_path / "voutlet")
    grains = [(0.01, 0.012, 0.02, 0.01), (0.03, 0.033, 0.02, 0.01)]
    open_bottom_cube(case, env, grains, end=0.09, write_interval=0.03, outlet=True)
    out = run("vansFoam", case, env).stdout
    log_message(
        out, r"grainOutlets: 1 grains \(mass \S+ kg\) left through inlet at time \S+, ids 0;"
    )
    last = times(case)[-1]
    ids, ds = remaining(case, last)
    assert ids == [1]
    from nscdpost import read_grains

    assert read_grains(case, last)["Ffluid"].shape == (1, 3)
    rows = outlet_rows(case, "0")
    assert rows[-1][4] + len(ids) == 2
    m = MAT["glass"]["density"] * np.pi / 6 * 0.01**3
    assert rows[-1][5] == pytest.approx(m, rel=1e-12)
