# SPDX-License-Identifier: GPL-3.0-or-later
"""Grains leaving through an orifice of a wall floor (outletPatches): the
crossed boundary face is found by the exact point-in-face test
(grainCloud::firstCrossing), so a grain whose centre crosses the orifice a
hair from its edge leaves through the orifice, not through the floor face
next to it (issue 60 item 2; the circumscribed-circle test gave the floor and
stopped the run).  2D and 3D grains grazing the rim, and a small silo
discharge run to its end."""

import os

import numpy as np
import pytest
from faultcase import MAT, G, times
from foamcase import log_message, make_box_case, run, write
from test_faults_boundaries import outlet_rows, remaining

#: the grain radius and rim offset of the issue: the centre crosses the
#: orifice 1.05 mm inside its edge, radius 1.054 mm (it touches the rim)
R = 1.054e-3
OFF = 1.05e-3


def carve_orifice(case, env, lo, hi):
    """Move the faces of `walls` whose centres lie in the box lo-hi into a new
    open patch `orifice` (topoSet + createPatch; the patch comes after
    `walls`, so a tie taken by patch order would name the wall)."""
    write(
        os.path.join(case, "system", "topoSetDict"),
        "dictionary",
        "topoSetDict",
        "actions ( { name orifice; type faceSet; action new; source boxToFace;\n"
        f"  box ({lo[0]} {lo[1]} {lo[2]}) ({hi[0]} {hi[1]} {hi[2]}); }} );\n",
    )
    write(
        os.path.join(case, "system", "createPatchDict"),
        "dictionary",
        "createPatchDict",
        "pointSync false;\npatches ( { name orifice; patchInfo { type patch; }\n"
        "  constructFrom set; set orifice; } );\n",
    )
    run("blockMesh", case, env)
    run("topoSet", case, env)
    run("createPatch", case, env, args=("-overwrite",))
    assert "orifice" in open(os.path.join(case, "constant", "polyMesh", "boundary")).read()


def run_rim(case, env, grains, hi, cells, end, orifice, two_d=True):
    """A box (0, hi) of cells with an orifice carved from the floor (the
    box orifice), the grains falling through it until end; checks that
    every grain left through the orifice and the run reached end."""
    make_box_case(
        case,
        (0, 0, 0),
        hi,
        cells,
        (0, -G, 0),
        MAT,
        grains=grains,
        end_time=end,
        dt=1e-3,
        write_interval=end / 3,
        two_d=two_d,
        extra_props="outletPatches (orifice);\n",
    )
    carve_orifice(case, env, *orifice)
    run("grainDeposit", case, env)
    out = run("grainFoam", case, env).stdout
    assert float(times(case)[-1]) == pytest.approx(end)
    check_all_left(case, out, len(grains))


def check_all_left(case, out, n):
    """Every one of the n grains left through the orifice; exit 0, no other exit."""
    assert "left the mesh" not in out
    rows = outlet_rows(case, "0")
    assert rows and rows[-1][4] == n, rows
    assert all(r[1] == "orifice" for r in rows)
    assert remaining(case, times(case)[-1]) == ([], [])


@pytest.mark.fast
def test_grains_grazing_the_orifice_rim_2d(tmp_path, env):
    """2D, 1 cm cells, orifice x in [0.04, 0.06] of the floor: discs falling
    with their centre 1.05 mm (radius 1.054 mm) and 0.5 mm inside either rim
    touch it and leave through the orifice (the neighbouring floor face's
    circumscribed circle reaches 2.07 mm into the orifice); the run goes on
    to its end."""
    case = str(tmp_path / "rim2d")
    xs = [0.04 + OFF, 0.06 - OFF, 0.04 + 0.5e-3, 0.06 - 0.5e-3, 0.05]
    grains = [(x, 0.02 + 0.01 * k, 0, 2 * R) for k, x in enumerate(xs)]
    run_rim(
        case, env, grains, (0.1, 0.1, 0.01), (10, 10, 1), 0.15, ((0.04, -1, -1), (0.06, 1e-6, 1))
    )


@pytest.mark.fast
def test_grains_grazing_the_orifice_rim_3d(tmp_path, env):
    """3D, 1 cm cells, a 2 x 2 face orifice x, z in [0.02, 0.04] of the
    floor: spheres crossing 1.05 mm inside its edges and 1.05 mm inside a
    corner of it (where three floor faces' circumscribed circles reach in)
    touch the rim and leave through the orifice."""
    case = str(tmp_path / "rim3d")
    pts = [
        (0.02 + OFF, 0.03),
        (0.04 - OFF, 0.025),
        (0.035, 0.02 + OFF),
        (0.02 + OFF, 0.02 + OFF),
        (0.04 - OFF, 0.04 - OFF),
        (0.03, 0.03),
    ]
    grains = [(x, 0.012 + 0.008 * k, z, 2 * R) for k, (x, z) in enumerate(pts)]
    run_rim(
        case,
        env,
        grains,
        (0.06, 0.06, 0.06),
        (6, 6, 6),
        0.12,
        ((0.02, -1, 0.02), (0.04, 1e-6, 0.04)),
        two_d=False,
    )


def small_silo(case, env, end, write_interval=0.05):
    """The 2D silo of test_small_silo_discharge_runs_to_its_end: 6 cm wide,
    5 mm cells, a 2 cm central orifice (x 0.02-0.04) in its floor, 288
    discs of 2.7-3.3 mm (fixed pseudo-random sizes) in a loose lattice, dt
    5e-4 s, to end.  Runs blockMesh, topoSet, createPatch and grainDeposit;
    returns the grains (x, y, z, d)."""
    rng = np.random.default_rng(60)
    grains = []
    for j in range(18):
        for i in range(16):
            x = 0.002 + 0.0036 * i + (0.0018 if j % 2 else 0)
            if x > 0.058:
                continue
            grains.append((x, 0.003 + 0.0036 * j, 0, 0.003 * (1 + 0.1 * (2 * rng.random() - 1))))
    make_box_case(
        case,
        (0, 0, 0),
        (0.06, 0.1, 0.005),
        (12, 20, 1),
        (0, -G, 0),
        MAT,
        grains=grains,
        end_time=end,
        dt=5e-4,
        write_interval=write_interval,
        extra_props="outletPatches (orifice);\n",
    )
    carve_orifice(case, env, (0.02, -1, -1), (0.04, 1e-6, 1))
    run("grainDeposit", case, env)
    return grains


@pytest.mark.slow
def test_small_silo_discharge_runs_to_its_end(tmp_path, env):
    """A 2D silo 6 cm wide, 5 mm cells, a 2 cm central orifice in its floor,
    288 discs of 2.7-3.3 mm (fixed pseudo-random sizes) in a loose lattice:
    0.25 s of discharge runs to its end (exit 0, no grain 'left the mesh'),
    grains leave only through the orifice, and removed + remaining =
    initial by number and mass (input diameters)."""
    case = str(tmp_path / "silo")
    grains = small_silo(case, env, 0.25)
    out = run("grainFoam", case, env).stdout
    assert "left the mesh" not in out
    assert times(case)[-1] == "0.25"
    rows = outlet_rows(case, "0")
    assert all(r[1] == "orifice" for r in rows)
    n_out, m_out = rows[-1][4], rows[-1][5]
    ids, ds = remaining(case, "0.25")
    assert n_out > 20, n_out  # it discharges
    assert n_out + len(ids) == len(grains)
    mass = [MAT["glass"]["density"] * np.pi * (g[3] / 2) ** 2 * 0.005 for g in grains]
    assert m_out + sum(
        MAT["glass"]["density"] * np.pi * (d / 2) ** 2 * 0.005 for d in ds
    ) == pytest.approx(sum(mass), rel=1e-9)
    log_message(out, r"grainOutlets summary \(since the case started\): orifice \d+ grains")
