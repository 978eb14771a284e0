# SPDX-License-Identifier: GPL-3.0-or-later
"""Measurement function objects of libfreeSurfaceFunctionObjects:
waveGauges, runUp, granularFront, grainCentreOfMass
(src/freeSurfaceFunctionObjects).

References (exact results, no fitted numbers):
- waveGauges: for a prescribed alpha field that is the exact cell-volume
  fraction of water under a surface y = h(x) (flat and tilted), the column
  integral min(y) + sum(alpha dy) of the column holding the gauge is h at
  the column's centre to round-off (the field is built from h(x_c): the
  discretisation is the column width dx, |eta - h(x_gauge)| <= |h'| dx/2).
  MPI: a 2-rank decomposition that splits every column gives the serial
  values to 1e-12 (reductions).
- runUp: the highest wet cell centre (alpha >= 0.5) and the highest wetted
  wall-face centre, computed here independently from the prescribed field;
  the maximum over times is the maximum of the per-time values.
- granularFront: a frictionless disc sliding on a floor under gravity
  g = 9.81 (sin 10deg, -cos 10deg): x(t) = x0 + a t^2/2, a = g sin(theta)
  (rigid-body mechanics); with the NSCD symplectic Euler step (thesis eq.
  2.37, x^{n+1} = x^n + dt v^{n+1}) the backward difference of the front is
  v(t) = a t to within one step a dt, so v_f = a T and Fr_f = a T /
  sqrt(|g| h0) within a dt / (a T) = dt/T.  A smaller disc ahead of it that
  does not reach the band y = h0 is ignored (thesis 5.2.3, "the furthest
  grain at a height y = h0").
- grainCentreOfMass: two discs falling freely (no contact) from heights
  y0_i: the centre of mass of the symplectic Euler step has U_c = -g t
  exactly and y_c = sum m y0 / M - g t^2/2 - g t dt/2 (the step's sum
  of dt^2 n); each disc crosses the plane y = yp at the free-fall speed
  sqrt(2 g (y0_i - yp)) (energy conservation), so the mass that crossed is
  int mdot dt = M (within v dt/(2 w) of the band's step sampling) and the
  flux-weighted speed sum m_i v_i / M (within the speed's variation across
  the band, (w/dz)^2 ~ 1e-3).
The library must be built (Allwmake, src/freeSurfaceFunctionObjects).
"""

import math
import os
import re
import shutil

import nscdpost
import numpy as np
import pytest
from foamcase import make_box_case, run, run_parallel, write, write_schemes

pytestmark = pytest.mark.fast

G = 9.81
NX, NY = 20, 25
LX, LY = 1.0, 0.5
DX, DY = LX / NX, LY / NY
XC = (np.arange(NX) + 0.5) * DX
YC = (np.arange(NY) + 0.5) * DY


def alpha_under(h):
    """Exact water fraction of each cell under y = h(x_c) (blockMesh order:
    x fastest)."""
    X, Y = np.meshgrid(XC, YC)
    return np.clip((h(X) - (Y - 0.5 * DY)) / DY, 0.0, 1.0)


def write_alpha(case, time, a, field="alpha.water", empty="frontAndBack"):
    """Cell values a of the water fraction as <case>/<time>/<field>; empty:
    the 2D case's empty patch (None in 3D)."""
    a = np.asarray(a).ravel()
    write(
        os.path.join(case, time, field),
        "volScalarField",
        field,
        "dimensions [0 0 0 0 0 0 0];\n"
        f"internalField nonuniform List<scalar> {a.size} (\n"
        + "\n".join(f"{v:.17g}" for v in a)
        + "\n);\n"
        "boundaryField { walls { type zeroGradient; }"
        + (f" {empty} {{ type empty; }}" if empty else "")
        + " }\n",
    )


def box(tmp_path, name, functions):
    case = str(tmp_path / name)
    make_box_case(
        case,
        (0, 0, 0),
        (LX, LY, 0.02),
        (NX, NY, 1),
        (0, -G, 0),
        {"glass": {"density": 2500, "friction": 0.5}},
    )
    with open(os.path.join(case, "system", "controlDict"), "a") as f:
        f.write("functions {\n" + functions + "\n}\n")
    return case


def read_dat(case, name, file, time="0"):
    path = os.path.join(case, "postProcessing", name, time, file)
    rows = [l.split() for l in open(path) if not l.startswith("#") and l.strip()]
    return np.array([[float(v) for v in r] for r in rows])


GAUGES = [0.1, 0.5, 0.52, 0.999]


def gauges_fo(still=0.2):
    xs = " ".join(str(x) for x in GAUGES)
    return (
        "gauges { type waveGauges; libs (freeSurfaceFunctionObjects);\n"
        f"  x ({xs}); stillWaterLevel {still}; }}\n"
    )


@pytest.mark.parametrize("slope", [0.0, 0.1], ids=["flat", "tilted"])
def test_wave_gauges_exact(tmp_path, env, slope):
    """eta = h(x_c) - still water level to 1e-12; within |h'| dx/2 of h(x)."""

    def h(x):
        return 0.2307 + slope * x  # level not on a cell face

    case = box(tmp_path, f"gauges_{slope}", gauges_fo())
    write_alpha(case, "0", alpha_under(h))
    run("blockMesh", case, env)
    run("postProcess", case, env, ["-time", "0"])
    eta = read_dat(case, "gauges", "waveGauges.dat")[0, 1:]
    col = [min(int(x / DX + 1e-9), NX - 1) for x in GAUGES]  # gauge on a face: the right column
    expected = [h(XC[c]) - 0.2 for c in col]
    assert np.allclose(eta, expected, rtol=0, atol=1e-12), (eta, expected)
    assert np.all(np.abs(eta - (h(np.array(GAUGES)) - 0.2)) <= slope * DX / 2 + 1e-12)


def test_wave_gauges_sheared_mesh(tmp_path, env):
    """A mesh whose columns are sheared (parallelogram cells, top shifted by
    2.5 cells): the vertical gauge line crosses a different column in each
    row and the cells' bounding boxes overlap, as on an unstructured (gmsh)
    mesh.  A flat surface y = h gives the exact cell fractions
    clip((h - y_j)/dy) in every row, so the line integral is h to 1e-12
    whichever cell of a row the line crosses (a bounding-box column would
    count ~2 cells per row and read ~2h)."""
    h = 0.2307
    case = box(tmp_path, "gauges_sheared", gauges_fo())
    shear = 2.5 * DX
    verts = [
        (0, 0, 0),
        (LX, 0, 0),
        (LX + shear, LY, 0),
        (shear, LY, 0),
        (0, 0, 0.02),
        (LX, 0, 0.02),
        (LX + shear, LY, 0.02),
        (shear, LY, 0.02),
    ]
    write(
        os.path.join(case, "system", "blockMeshDict"),
        "dictionary",
        "blockMeshDict",
        "scale 1;\nvertices (" + " ".join("(%r %r %r)" % v for v in verts) + ");\n"
        f"blocks ( hex (0 1 2 3 4 5 6 7) ({NX} {NY} 1) simpleGrading (1 1 1) );\n"
        "boundary (\nwalls { type wall; faces ((1 5 4 0) (0 4 7 3) (2 6 5 1) (3 7 6 2)); }\n"
        "frontAndBack { type empty; faces ((0 3 2 1) (4 5 6 7)); }\n);\n",
    )
    write_alpha(case, "0", alpha_under(lambda x: h + 0 * x))
    run("blockMesh", case, env)
    # gauges inside the sheared domain at every height: shear <= x <= LX
    with open(os.path.join(case, "system", "controlDict")) as f:
        cd = f.read()
    cd = re.sub(r"x \([^)]*\);", "x (0.2 0.5 0.52 0.9);", cd)
    with open(os.path.join(case, "system", "controlDict"), "w") as f:
        f.write(cd)
    run("postProcess", case, env, ["-time", "0"])
    eta = read_dat(case, "gauges", "waveGauges.dat")[0, 1:]
    assert np.allclose(eta, h - 0.2, rtol=0, atol=1e-12), eta


@pytest.mark.mpi
def test_wave_gauges_parallel_equals_serial(tmp_path, env):
    """2 ranks splitting every column (1 x 2 slabs): same elevations (1e-12)."""

    def h(x):
        return 0.2307 + 0.1 * x + 0.02 * np.sin(6 * x)

    case = box(tmp_path, "gauges_par", gauges_fo())
    write_alpha(case, "0", alpha_under(h))
    run("blockMesh", case, env)
    run("postProcess", case, env, ["-time", "0"])
    serial = read_dat(case, "gauges", "waveGauges.dat")[0, 1:]
    shutil.rmtree(os.path.join(case, "postProcessing"))
    run_parallel("postProcess", case, env, split=(1, 2, 1), args=("-time", "0"))
    par = read_dat(case, "gauges", "waveGauges.dat")[0, 1:]
    assert np.allclose(par, serial, rtol=0, atol=1e-12), (par, serial)


def gauges_3d_case(tmp_path, env):
    """A 3D box of two cell layers in z under y = h(x) = 0.2307 + 0.1 x;
    returns the case and the expected elevations h(x_c) - 0.2."""

    def h(x):
        return 0.2307 + 0.1 * x

    case = str(tmp_path / "gauges3d")
    make_box_case(
        case,
        (0, 0, 0),
        (LX, LY, 0.1),
        (NX, NY, 2),
        (0, -G, 0),
        {"glass": {"density": 2500, "friction": 0.5}},
        two_d=False,
    )
    with open(os.path.join(case, "system", "controlDict"), "a") as f:
        f.write("functions {\n" + gauges_fo() + "\n}\n")
    a = alpha_under(h).ravel()
    write_alpha(case, "0", np.concatenate([a, a]), empty=None)  # z layer by z layer
    run("blockMesh", case, env)
    col = [min(int(x / DX + 1e-9), NX - 1) for x in GAUGES]
    return case, [h(XC[c]) - 0.2 for c in col]


def test_wave_gauges_3d_line_on_faces(tmp_path, env):
    """3D, two cell layers in z: the gauge line (the mesh centre along z)
    lies in the face between them.  Each cell crossed counts once: eta =
    h(x_c) - still water level to 1e-12 (the line counted in the cells on
    both sides gave eta = 2 h - still)."""
    case, expected = gauges_3d_case(tmp_path, env)
    run("postProcess", case, env, ["-time", "0"])
    eta = read_dat(case, "gauges", "waveGauges.dat")[0, 1:]
    assert np.allclose(eta, expected, rtol=0, atol=1e-12), (eta, expected)


@pytest.mark.mpi
def test_wave_gauges_3d_line_on_a_processor_boundary(tmp_path, env):
    """The same on 2 ranks, one z layer each: the line on the processor
    boundary counts once over the ranks."""
    case, expected = gauges_3d_case(tmp_path, env)
    run_parallel("postProcess", case, env, split=(1, 1, 2), args=("-time", "0"))
    eta = read_dat(case, "gauges", "waveGauges.dat")[0, 1:]
    assert np.allclose(eta, expected, rtol=0, atol=1e-12), (eta, expected)


def test_run_up_prescribed(tmp_path, env):
    """Run-up of wet cells and of a wetted wall patch at two times, and the
    maximum over the times, against the values computed here."""
    fos = (
        "cells { type runUp; libs (freeSurfaceFunctionObjects); stillWaterLevel 0.2; }\n"
        "shore { type runUp; libs (freeSurfaceFunctionObjects); patches (walls);\n"
        "  xRange (0.9 2); stillWaterLevel 0.2; }\n"
    )
    case = box(tmp_path, "runup", fos)
    surfaces = {"0": lambda x: 0.2307 + 0.1 * x, "1": lambda x: 0.21 + 0.02 * x}
    expected_cells, expected_wall = [], []
    for t, h in surfaces.items():
        a = alpha_under(h)
        write_alpha(case, t, a)
        expected_cells.append(np.max(np.where(a >= 0.5, YC[:, None], -1.0)) - 0.2)
        # right wall x = 1 (zeroGradient: face value = last column's cell)
        expected_wall.append(np.max(np.where(a[:, -1] >= 0.5, YC, -1.0)) - 0.2)
    run("blockMesh", case, env)
    run("postProcess", case, env)
    # the files are opened at the start time of the case (startFrom latestTime)
    cells = read_dat(case, "cells", "runUp.dat", "1")
    wall = read_dat(case, "shore", "runUp.dat", "1")
    assert np.allclose(cells[:, 1], expected_cells, atol=1e-12), cells
    assert np.allclose(wall[:, 1], expected_wall, atol=1e-12), wall
    assert cells[1, 2] == pytest.approx(max(expected_cells), abs=1e-12)
    assert wall[1, 2] == pytest.approx(max(expected_wall), abs=1e-12)
    assert expected_cells[1] < expected_cells[0]  # the max is kept


def write_scalar_transport(case, time_s, a):
    """The water fraction as the field T of OpenFOAM's scalarTransportFoam
    (U = 0, DT = 0: T is carried unchanged from step to step), so that a
    solver run with write times and a restart drives the function object."""
    write_alpha(case, time_s, a, field="T")


def test_run_up_maximum_restored_on_restart(tmp_path, env):
    """A run writes at t = 0.5 with a high surface; the restart from 0.5
    sees a lower one.  The maximum after the restart must still be the
    first part's (the runUp state in 0.5/uniform/functionObjects), not the
    lower restarted value (it was, before the state was kept)."""
    fos = "cells { type runUp; libs (freeSurfaceFunctionObjects); alpha T; stillWaterLevel 0.2; }\n"
    case = box(tmp_path, "restart", fos)
    ctrl = os.path.join(case, "system", "controlDict")
    text = open(ctrl).read().replace("application grainFoam;", "application scalarTransportFoam;")
    text = re.sub(r"endTime [^;]*;", "endTime 0.5;", text, count=1)
    text = re.sub(r"deltaT [^;]*;", "deltaT 0.1;", text, count=1)
    text = re.sub(r"writeInterval [^;]*;", "writeInterval 0.5;", text, count=1)
    open(ctrl, "w").write(text)
    write_schemes(case, "div(phi,T) Gauss upwind;")
    write(
        os.path.join(case, "system", "fvSolution"),
        "dictionary",
        "fvSolution",
        "solvers { T { solver PBiCGStab; preconditioner DILU; tolerance 1e-12; relTol 0; } }\n"
        "SIMPLE { nNonOrthogonalCorrectors 0; }\n",
    )
    write(
        os.path.join(case, "constant", "transportProperties"),
        "dictionary",
        "transportProperties",
        "DT DT [0 2 -1 0 0 0 0] 0;\n",
    )
    write(
        os.path.join(case, "0", "U"),
        "volVectorField",
        "U",
        "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
        "boundaryField { walls { type noSlip; } frontAndBack { type empty; } }\n",
    )
    high, low = (lambda x: 0.2307 + 0.1 * x), (lambda x: 0.21 + 0.02 * x)
    a_high, a_low = alpha_under(high), alpha_under(low)
    r_high = np.max(np.where(a_high >= 0.5, YC[:, None], -1.0)) - 0.2
    r_low = np.max(np.where(a_low >= 0.5, YC[:, None], -1.0)) - 0.2
    assert r_low < r_high - DY / 2  # the test can tell them apart
    write_scalar_transport(case, "0", a_high)
    run("blockMesh", case, env)
    run("scalarTransportFoam", case, env)
    assert os.path.isdir(os.path.join(case, "0.5", "uniform", "functionObjects"))
    # the surface drops before the restart
    write_scalar_transport(case, "0.5", a_low)
    text = re.sub(r"endTime [^;]*;", "endTime 1;", open(ctrl).read(), count=1)
    open(ctrl, "w").write(text)
    run("scalarTransportFoam", case, env)
    after = read_dat(case, "cells", "runUp.dat", "0.5")
    assert np.allclose(after[:, 1], r_low, atol=1e-12), after
    assert np.allclose(after[:, 2], r_high, atol=1e-12), after


@pytest.mark.parametrize(
    "fo,key",
    [
        (
            "gauges { type waveGauges; libs (freeSurfaceFunctionObjects); x (0.5); stilWaterLevel 0; }",
            "stilWaterLevel",
        ),
        ("r { type runUp; libs (freeSurfaceFunctionObjects); patchs (walls); }", "patchs"),
        ("g { type waveGauges; libs (freeSurfaceFunctionObjects); x (); }", "x"),
    ],
)
def test_keyword_checks(tmp_path, env, fo, key):
    case = box(tmp_path, "kw", fo)
    write_alpha(case, "0", alpha_under(lambda x: 0.2 + 0 * x))
    run("blockMesh", case, env)
    p = run("postProcess", case, env, ["-time", "0"], check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0 and key in out and "FOAM FATAL" in out, out[-1500:]


def test_granular_front_sliding_disc(tmp_path, env):
    theta = math.radians(10.0)
    a = G * math.sin(theta)
    R, r, h0, T, dt = 0.01, 0.002, 0.015, 0.2, 1e-3
    case = str(tmp_path / "front")
    # big disc at x = 0.05 (reaches y = h0), small disc ahead (does not)
    make_box_case(
        case,
        (0, 0, 0),
        (1.0, 0.05, 0.01),
        (20, 1, 1),
        (G * math.sin(theta), -G * math.cos(theta), 0),
        {"ice": {"density": 900, "friction": 0.0}},
        grains=[(0.05, R, 0, 2 * R), (0.08, r, 0, 2 * r)],
        end_time=T,
        dt=dt,
        write_interval=T,
    )
    with open(os.path.join(case, "system", "controlDict"), "a") as f:
        f.write(
            "functions {\n front { type granularFront; libs (freeSurfaceFunctionObjects);\n"
            f"  h0 {h0}; frontDirection (1 0 0); }}\n"
            f" smooth {{ type granularFront; libs (freeSurfaceFunctionObjects);\n"
            f"  h0 {h0}; smoothingTime 0.02; }}\n}}\n"
        )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("grainFoam", case, env)
    d = read_dat(case, "front", "granularFront.dat")
    t, xf, vf, vmax, fr = d[-1]
    assert t == pytest.approx(T)
    # the front is the big disc (the small one is outside the band)
    assert xf == pytest.approx(0.05 + R + 0.5 * a * T**2, abs=a * T * dt)
    assert vmax == pytest.approx(a * T, abs=a * dt)
    assert fr == pytest.approx(vmax / math.sqrt(G * h0), rel=1e-12)
    assert fr == pytest.approx(a * T / math.sqrt(G * h0), rel=dt / T)
    # least squares over 0.02 s of a parabola: the slope at the window centre
    s = read_dat(case, "smooth", "granularFront.dat")[-1]
    assert s[2] == pytest.approx(a * (T - 0.01), abs=a * dt)
    g = nscdpost.read_grains(case, nscdpost.time_dirs(case)[-1][1])
    assert g["x"][1, 0] + r > xf  # the small disc is ahead, not counted


def falling_case(tmp_path, env, name, grains, T, dt, fo):
    """A 1 x 2 m 2D box of rock discs (x, y, 0, d) released at rest,
    grainFoam to T with the function-object entry fo; returns the case."""
    case = str(tmp_path / name)
    make_box_case(
        case,
        (0, 0, 0),
        (1.0, 2.0, 0.01),
        (10, 20, 1),
        (0, -G, 0),
        {"rock": {"density": 2640, "friction": 0.9}},
        grains=grains,
        end_time=T,
        dt=dt,
        write_interval=T,
    )
    with open(os.path.join(case, "system", "controlDict"), "a") as f:
        f.write(
            "functions {\n com { type grainCentreOfMass; libs (freeSurfaceFunctionObjects);\n"
            f"  {fo} }}\n}}\n"
        )
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    return case


def test_grain_centre_of_mass_free_fall(tmp_path, env):
    T, dt, yp, w = 0.5, 1e-3, 1.0, 0.1
    falls = [(0.3, 1.8, 0.04), (0.7, 1.6, 0.08)]  # x, y0, d
    case = falling_case(
        tmp_path,
        env,
        "com",
        [(x, y0, 0, d) for x, y0, d in falls],
        T,
        dt,
        f"fluxPoint (0 {yp} 0); fluxNormal (0 -1 0); fluxBandHalfWidth {w};",
    )
    run("grainFoam", case, env)
    d = read_dat(case, "com", "grainCentreOfMass.dat")
    t = d[:, 0]
    m = np.array([2640 * math.pi / 4 * dd**2 for _x, _y, dd in falls])
    M = m.sum()
    y0 = np.array([y for _x, y, _d in falls])
    assert np.allclose(d[:, 1], M, rtol=1e-12)
    assert np.allclose(d[:, 2], np.sum(m * [x for x, _y, _d in falls]) / M, atol=1e-12)
    yc = np.sum(m * y0) / M - 0.5 * G * t**2 - 0.5 * G * t * dt
    assert np.allclose(d[:, 3], yc, atol=1e-9), np.max(np.abs(d[:, 3] - yc))
    assert np.allclose(d[:, 6], -G * t, atol=1e-9)
    assert np.allclose(d[:, 5], 0, atol=1e-12)
    dts = np.diff(np.concatenate([[0.0], t]))
    crossed = np.sum(d[:, 8] * dts)
    v = np.sqrt(2 * G * (y0 - yp))
    assert crossed == pytest.approx(M, rel=v.max() * dt / (2 * w)), (crossed, M)
    speed = np.sum(d[:, 9] * dts) / crossed
    assert speed == pytest.approx(np.sum(m * v) / M, rel=1e-2), (speed, np.sum(m * v) / M)


def test_grain_centre_of_mass_keyword(tmp_path, env):
    """fluxPoint without fluxBandHalfWidth: FatalIOError naming both."""
    case = falling_case(
        tmp_path, env, "comkw", [(0.5, 0.5, 0, 0.1)], 0.01, 1e-3, "fluxPoint (0 0.5 0);"
    )
    p = run("grainFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0 and "fluxBandHalfWidth" in out and "FOAM FATAL" in out, out[-1500:]
