#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Resolved-regime cases of vansFoam (thesis sections 3.3.3-3.3.4): one or a
few discs spanning many cells in a 2D box of water-like fluid.  The grains
are NSCD discs; in the cells they cover eps -> epsMin and the semi-implicit
drag (eq. 3.46-3.50) penalises the fluid towards the grain velocity.

write_case() writes a complete case (blockMesh, fields, dictionaries,
grainDepositDict); it is also used by ../draftingKissingTumbling and by
tests/cases/test_resolvedRegime.py (reduced copies).

usage (the tutorial): setupCase.py CASEDIR [ENDTIME] [CELLS_PER_D] [HEIGHT] [ROTATION yes|no] [MAXDT] [SCHEME] [WALLS]
  SCHEME resolved (default): couplingProperties `resolvedCellsPerDiameter 4;`,
  the resolved-regime scheme of vansCloud.H (grain velocity out of the
  pressure solve, added mass C_A = 1, stable as the cylinder nears a wall);
  SCHEME default: no keyword (grain weight in the cells).  Measured
  (2026-11-22, D/h = 8, released D/100 off the axis, rotation coupling,
  maxDeltaT 1e-3 s, 8 s): with `resolved` the cylinder falls at 1.8-2.15
  cm/s and wanders +-6 mm about the axis through the whole run; with
  `default` (no rotation) it drifts steadily to the side (11 mm at 3.5 s,
  lateral velocity 0.75 cm/s), with rotation coupling faster (17 mm at
  3 s), and at D/h = 15 the coupling blew up 1.8 cells from the wall at
  3.15 s (tests/bench/results/cylinderSedimentation.json).  Its 2.4-2.6
  cm/s plateau is fortuitous (+18 % when released on the axis; vansCloud.H,
  Known limits).
  WALLS: the side walls' distance from the axis in diameters, default 4
  (the thesis box); larger: graded side blocks (setupCase.side_blocks).
  MAXDT: maxDeltaT [s], default 1e-3: at D/h = 15 maxDeltaT 2.5e-3 and 5e-3
  give a spurious upward kick of the grain within 0.1 s (measured), 1e-3 is smooth.
  Namkoong et al. (2008), thesis 3.3.3: D = 5 mm, rho_s/rho_f = 1.01,
  rho_f = 996 kg/m^3, nu = 8e-7 m^2/s, box [-0.02, 0.02] x [-0.16, 0.16] m,
  15 cells per diameter (uniform mesh: 120 x 960 cells).
"""

import math
import os
import re
import sys

HEADER = "FoamFile { version 2.0; format ascii; class %s; object %s; }\n"

# Namkoong, Yoo & Choi (2008), J. Fluid Mech. 604:33-53 (a cylinder in an INFINITE fluid) (thesis ref. [101])
D = 5e-3  # [m]
RHO_F = 996.0  # [kg/m^3]
RHO_S = 1.01 * RHO_F
NU = 8e-7  # [m^2/s]
UT_REF = 0.02501  # [m/s] terminal velocity (thesis 3.3.3, Re = 156)
WIDTH = 0.04  # [m] x in [-0.02, 0.02]
HEIGHT = 0.32  # [m] y in [-0.16, 0.16]


def _write(path, cls, obj, body):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(HEADER % (cls, obj))
        f.write(body)


def write_case(
    case,
    lo,
    hi,
    cells,
    grains,
    rho_s,
    rho_f,
    nu,
    gravity=(0, -9.81, 0),
    end_time=1.0,
    write_interval=0.05,
    max_co=0.5,
    max_dt=5e-3,
    fixed=False,
    inflow=None,
    n_correctors=2,
    n_outer=1,
    rotation=False,
    inlet_pressure="zeroGradient",
    side=None,
):
    """Write a 2D vansFoam case.

    lo, hi: (x, y) corners of the box [m]; cells: (nx, ny); the mesh is one
    cell thick in z (depth = hi[0]-lo[0] / nx, `frontAndBack` empty).
    grains: list of (x, y, d) [m] discs of density rho_s [kg/m^3];
    fixed: all grains fixed (grainDeposit `fixed yes`).
    rotation: couplingProperties `rotationCoupling yes` (grain rotation
    imposed in the penalised cells, fluid torque on the grain).
    inflow: None (closed box, no-slip `walls`) or U0 [m/s]: a uniform flow in
    +x, fixedValue U0 at the `inlet` (x = lo), p = 0 at the `outlet`
    (x = hi) and walls y = lo, hi moving at U0 (the frame of a disc
    translating at -U0 between fixed plane walls, Faxen's problem);
    or a list of (t [s], U0 [m/s]) pairs: the same with U0(t) interpolated
    linearly in that table (OpenFOAM uniformFixedValue; the frame of a disc
    translating with a prescribed velocity history, initial field U0(0)).
    inlet_pressure: p condition at the `inlet` when inflow is given,
    "zeroGradient" or "fixedFluxPressure" (needed at Re ~ 100 and for an
    accelerating inflow: the pressure gradient then carries dU0/dt).
    side: None, or (width [m], n, ratio): a closed box only (inflow None),
    widened by a block of `width` on each side of [lo, hi] in x, of n cells
    growing geometrically away from the box, first cell (x1-x0)/nx, last
    over first `ratio` (blockMesh simpleGrading): the walls move out to
    x0 - width, x1 + width at the cost of 2 n ny cells.  Used to measure the
    walls' effect on a grain that stays in the uniform middle block.
    """
    (x0, y0), (x1, y1) = lo, hi
    nx, ny = cells
    dz = (x1 - x0) / nx
    v = [
        (x0, y0, 0),
        (x1, y0, 0),
        (x1, y1, 0),
        (x0, y1, 0),
        (x0, y0, dz),
        (x1, y0, dz),
        (x1, y1, dz),
        (x0, y1, dz),
    ]
    if inflow is None:
        bnd = "walls { type wall; faces ((1 5 4 0) (0 4 7 3) (2 6 5 1) (3 7 6 2)); }\n"
        uB = "walls { type noSlip; }"
        pB = "walls { type fixedFluxPressure; value uniform 0; }"
        pref = "pRefCell 0; pRefValue 0;"
    else:
        if inlet_pressure not in ("zeroGradient", "fixedFluxPressure"):
            raise ValueError(
                f"inlet_pressure {inlet_pressure!r}: zeroGradient or fixedFluxPressure"
            )
        if isinstance(inflow, (int, float)):
            u_in = f"type fixedValue; value uniform ({inflow} 0 0);"
            u_init = f"{inflow}"
        else:
            tab = " ".join("(%.12g (%.12g 0 0))" % (t, u) for t, u in inflow)
            u_in = f"type uniformFixedValue; uniformValue table ({tab});"
            u_init = "%.12g" % inflow[0][1]
        bnd = (
            "inlet { type patch; faces ((0 4 7 3)); }\n"
            "outlet { type patch; faces ((2 6 5 1)); }\n"
            "walls { type wall; faces ((1 5 4 0) (3 7 6 2)); }\n"
        )
        uB = f"inlet {{ {u_in} }}\n    outlet {{ type zeroGradient; }}\n    walls {{ {u_in} }}"
        p_in = (
            "type zeroGradient;"
            if inlet_pressure == "zeroGradient"
            else "type fixedFluxPressure; value uniform 0;"
        )
        pB = (
            f"inlet {{ {p_in} }}\n"
            "    outlet { type fixedValue; value uniform 0; }\n"
            "    walls { type zeroGradient; }"
        )
        pref = ""
    if side is None:
        vs = " ".join("(%.12g %.12g %.12g)" % p for p in v)
        _write(
            os.path.join(case, "system", "blockMeshDict"),
            "dictionary",
            "blockMeshDict",
            f"scale 1;\nvertices ({vs});\n"
            f"blocks ( hex (0 1 2 3 4 5 6 7) ({nx} {ny} 1) simpleGrading (1 1 1) );\n"
            f"boundary (\n{bnd}frontAndBack {{ type empty; faces ((0 3 2 1) (4 5 6 7)); }}\n);\n",
        )
    else:
        if inflow is not None:
            raise ValueError("side blocks: closed box only (inflow None)")
        _write_widened_mesh(case, lo, hi, cells, side)
    u0 = f"({u_init} 0 0)" if inflow is not None else "(0 0 0)"
    _write(
        os.path.join(case, "0", "U"),
        "volVectorField",
        "U",
        f"dimensions [0 1 -1 0 0 0 0];\ninternalField uniform {u0};\n"
        f"boundaryField\n{{\n    {uB}\n    frontAndBack {{ type empty; }}\n}}\n",
    )
    _write(
        os.path.join(case, "0", "p"),
        "volScalarField",
        "p",
        "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
        f"boundaryField\n{{\n    {pB}\n    frontAndBack {{ type empty; }}\n}}\n",
    )
    _write(
        os.path.join(case, "constant", "g"),
        "uniformDimensionedVectorField",
        "g",
        "dimensions [0 1 -2 0 0 0 0];\nvalue (%.12g %.12g %.12g);\n" % tuple(gravity),
    )
    _write(
        os.path.join(case, "constant", "transportProperties"),
        "dictionary",
        "transportProperties",
        f"rho {rho_f!r};   // [kg/m^3]\nnu {nu!r};   // [m^2/s]\n",
    )
    _write(
        os.path.join(case, "constant", "couplingProperties"),
        "dictionary",
        "couplingProperties",
        "// resolved regime: eps -> epsMin inside the grains, the semi-implicit\n"
        "// drag (eq. 3.46-3.50) acts as a volume penalisation (thesis 3.3.3)\n"
        "dragModel DallavalleDiFelice;\ntwoDimensionalDrag perUnitDepth;\nforceModel A;\n"
        "voidFraction { method overlap; epsMin 1e-8; }\n"
        + ("rotationCoupling yes;\n" if rotation else ""),
    )
    _write(
        os.path.join(case, "constant", "grainProperties"),
        "dictionary",
        "grainProperties",
        f"materials {{ solid {{ density {rho_s!r}; friction 0; }} }}\n"
        "maxDisplacementFraction 0.1;\n"
        "contactSolver { tolerance 1e-6; maxIterations 1000; overlapTolerance 1e-2; }\n",
    )
    lines = "\n".join("(%.12g %.12g 0 %.12g)" % g for g in grains)
    _write(
        os.path.join(case, "system", "grainDepositDict"),
        "dictionary",
        "grainDepositDict",
        f"material solid;\nmethod list;\nfixed {'yes' if fixed else 'no'};\n"
        f"grains\n(\n{lines}\n);\n",
    )
    _write(
        os.path.join(case, "system", "controlDict"),
        "dictionary",
        "controlDict",
        "application vansFoam;\nstartFrom latestTime;\nstartTime 0;\nstopAt endTime;\n"
        f"endTime {end_time};\ndeltaT {min(max_dt, 1e-3)};\nadjustTimeStep yes;\n"
        f"maxCo {max_co};\nmaxDeltaT {max_dt};\nwriteControl adjustableRunTime;\n"
        f"writeInterval {write_interval};\nwriteFormat ascii;\nwritePrecision 10;\n"
        "timeFormat general;\ntimePrecision 8;\nrunTimeModifiable false;\n",
    )
    _write(
        os.path.join(case, "system", "fvSchemes"),
        "dictionary",
        "fvSchemes",
        "ddtSchemes { default Euler; }\ngradSchemes { default Gauss linear; }\n"
        "divSchemes { default none; div(phi,U) Gauss limitedLinearV 1; }\n"
        "laplacianSchemes { default Gauss linear corrected; }\n"
        "interpolationSchemes { default linear; }\nsnGradSchemes { default corrected; }\n",
    )
    _write(
        os.path.join(case, "system", "fvSolution"),
        "dictionary",
        "fvSolution",
        "solvers\n{\n"
        "    p { solver GAMG; smoother DIC; tolerance 1e-9; relTol 0.01; }\n"
        "    pFinal { $p; relTol 0; }\n"
        # Krylov solver for U: the resolved grains' viscosity penalty
        # (couplingProperties rigidViscosityRatio, vansCloud.H) makes
        # the momentum matrix stiff, Gauss-Seidel stalls there
        '    "(U|UFinal)" { solver PBiCGStab; preconditioner DILU; tolerance 1e-9; relTol 0; }\n'
        "}\n"
        f"PIMPLE {{ momentumPredictor yes; nOuterCorrectors {n_outer}; nCorrectors {n_correctors};\n"
        f"    nNonOrthogonalCorrectors 0; {pref} }}\n",
    )


def _write_widened_mesh(case, lo, hi, cells, side):
    """blockMeshDict of write_case's closed box [lo, hi] (nx x ny uniform
    cells) between two graded side blocks side = (width, n, ratio): three
    blocks in x, walls on the outer faces, `frontAndBack` empty."""
    (x0, y0), (x1, y1) = lo, hi
    nx, ny = cells
    width, n_side, ratio = side
    dz = (x1 - x0) / nx
    xs = (x0 - width, x0, x1, x1 + width)

    def vid(i, j, k):  # vertex (x index i, y index j, z index k)
        return 8 * k + 4 * j + i

    verts = [(xs[i], (y0, y1)[j], (0.0, dz)[k]) for k in (0, 1) for j in (0, 1) for i in range(4)]
    vs = " ".join("(%.12g %.12g %.12g)" % p for p in verts)
    blocks, walls, empty = [], [], []
    for b, (n, grade) in enumerate(((n_side, 1.0 / ratio), (nx, 1.0), (n_side, ratio))):
        hexv = (
            vid(b, 0, 0),
            vid(b + 1, 0, 0),
            vid(b + 1, 1, 0),
            vid(b, 1, 0),
            vid(b, 0, 1),
            vid(b + 1, 0, 1),
            vid(b + 1, 1, 1),
            vid(b, 1, 1),
        )
        blocks.append(
            "hex (%s) (%d %d 1) simpleGrading (%.12g 1 1)"
            % (" ".join(map(str, hexv)), n, ny, grade)
        )
        for j in (0, 1):  # bottom and top
            walls.append((vid(b, j, 0), vid(b + 1, j, 0), vid(b + 1, j, 1), vid(b, j, 1)))
        for k in (0, 1):
            empty.append((vid(b, 0, k), vid(b, 1, k), vid(b + 1, 1, k), vid(b + 1, 0, k)))
    walls += [
        (vid(0, 0, 0), vid(0, 0, 1), vid(0, 1, 1), vid(0, 1, 0)),
        (vid(3, 0, 0), vid(3, 1, 0), vid(3, 1, 1), vid(3, 0, 1)),
    ]

    def faces(fs):
        return " ".join("(%s)" % " ".join(map(str, f)) for f in fs)

    _write(
        os.path.join(case, "system", "blockMeshDict"),
        "dictionary",
        "blockMeshDict",
        f"scale 1;\nvertices ({vs});\nblocks (\n" + "\n".join(blocks) + "\n);\n"
        f"boundary (\nwalls {{ type wall; faces ({faces(walls)}); }}\n"
        f"frontAndBack {{ type empty; faces ({faces(empty)}); }}\n);\n",
    )


def side_blocks(h, width, growth=1.1):
    """(width, n, ratio) for write_case's `side`: the fewest cells growing by
    at most `growth` per cell from h [m] that fill `width` [m] (the last
    cell then grows by exactly that factor from its neighbour's size)."""
    n = max(1, math.ceil(math.log(1.0 + width * (growth - 1.0) / h) / math.log(growth)))
    # solve h (q^n - 1)/(q - 1) = width for q (bisection, q in (1, growth])
    lo_q, hi_q = 1.0 + 1e-12, growth
    for _ in range(200):
        q = 0.5 * (lo_q + hi_q)
        if h * (q**n - 1.0) / (q - 1.0) > width:
            hi_q = q
        else:
            lo_q = q
    return width, n, q ** (n - 1)


def mesh_layout(case):
    """(nx, cells, walls, height) of a case written by write_case: nx the
    cells across the uniform block (the only block, or the middle one
    between graded side blocks), cells the total over all blocks, walls the
    largest |x| of the vertices [m] (for cylinder_case's box, centred on
    x = 0: the side walls' distance from the axis), height its y extent [m].
    Raises ValueError if system/blockMeshDict has no such layout."""
    path = os.path.join(case, "system", "blockMeshDict")
    bm = open(path).read()
    blocks = re.findall(r"hex \([\d ]+\) \((\d+) (\d+) 1\) simpleGrading \((\S+) 1 1\)", bm)
    uniform = [int(b[0]) for b in blocks if float(b[2]) == 1.0]
    if not blocks or len(uniform) != 1:
        raise ValueError(
            f"{path}: {len(blocks)} 2D hex blocks, {len(uniform)} uniform; "
            "expected write_case's layout (one uniform block)"
        )
    verts = re.search(r"vertices \((.*?)\);", bm, re.S).group(1)
    pts = [[float(c) for c in v.split()] for v in re.findall(r"\(([^()]*)\)", verts)]
    walls = max(abs(p[0]) for p in pts)
    height = max(p[1] for p in pts) - min(p[1] for p in pts)
    return uniform[0], sum(int(b[0]) * int(b[1]) for b in blocks), walls, height


def cylinder_case(
    case,
    end_time=4.0,
    cells_per_d=15,
    height=HEIGHT,
    write_interval=0.02,
    max_co=0.5,
    max_dt=5e-3,
    y0=None,
    x0=None,
    rotation=False,
    wall_distance=None,
    rho_s=None,
):
    """The falling cylinder of thesis 3.3.3 (Namkoong et al. 2008), box
    [-0.02, 0.02] x [-height/2, height/2]; released from rest at
    (x0, y0) (default: x0 = D/100, an offset that seeds the symmetry
    breaking of the wake, y0 = height/2 - 4 D).
    wall_distance: None (the thesis box, walls at x = +-4 D) or the walls'
    distance from the axis [m] > WIDTH/2: the uniform box keeps its cells
    and graded side blocks (side_blocks, growth 1.1 per cell) fill the rest.
    rho_s: the cylinder's density [kg/m^3] (default RHO_S).
    Returns the number of cells."""
    h = D / cells_per_d
    nx, ny = round(WIDTH / h), round(height / h)
    x0 = D / 100 if x0 is None else x0
    y0 = height / 2 - 4 * D if y0 is None else y0
    side = None
    if wall_distance is not None and wall_distance > WIDTH / 2 * (1 + 1e-9):
        side = side_blocks(WIDTH / nx, wall_distance - WIDTH / 2)
    elif wall_distance is not None and wall_distance < WIDTH / 2 * (1 - 1e-9):
        raise ValueError(f"wall_distance {wall_distance} m: at least WIDTH/2 = {WIDTH / 2} m")
    write_case(
        case,
        (-WIDTH / 2, -height / 2),
        (WIDTH / 2, height / 2),
        (nx, ny),
        [(x0, y0, D)],
        RHO_S if rho_s is None else rho_s,
        RHO_F,
        NU,
        end_time=end_time,
        write_interval=write_interval,
        max_co=max_co,
        max_dt=max_dt,
        rotation=rotation,
        side=side,
    )
    return nx * ny + (0 if side is None else 2 * side[1] * ny)


def opt_in_resolved(case, extra=""):
    """Switch a written case to the resolved-regime scheme of vansCloud.H
    ("Resolved grains"): append `resolvedCellsPerDiameter 4;` and `extra`
    (more couplingProperties entries) to constant/couplingProperties.  The
    U solver written by write_case (PBiCGStab) suits its viscosity penalty."""
    with open(os.path.join(case, "constant", "couplingProperties"), "a") as f:
        f.write("resolvedCellsPerDiameter 4;\n" + extra)


def main():
    case = sys.argv[1]
    end = float(sys.argv[2]) if len(sys.argv) > 2 else 4.0
    cpd = float(sys.argv[3]) if len(sys.argv) > 3 else 15
    height = float(sys.argv[4]) if len(sys.argv) > 4 else HEIGHT
    rot = len(sys.argv) > 5 and sys.argv[5] in ("yes", "on", "true", "1")
    max_dt = float(sys.argv[6]) if len(sys.argv) > 6 else 1e-3
    scheme = sys.argv[7] if len(sys.argv) > 7 else "resolved"
    walls = float(sys.argv[8]) if len(sys.argv) > 8 else WIDTH / 2 / D
    if scheme not in ("resolved", "default"):
        sys.exit(f"setupCase.py: SCHEME {scheme!r} unknown (7th argument): use resolved or default")
    if walls < WIDTH / 2 / D - 1e-9:
        sys.exit(
            f"setupCase.py: WALLS {walls:g} (8th argument, walls' distance from the "
            f"axis in diameters): at least {WIDTH / 2 / D:g} (the thesis box)"
        )
    n = cylinder_case(
        case,
        end,
        cpd,
        height,
        write_interval=0.05,
        rotation=rot,
        max_dt=max_dt,
        wall_distance=walls * D,
    )
    if scheme == "resolved":
        opt_in_resolved(case)
    print(
        f"{case}: {n} cells, D/h = {cpd:g}, endTime {end:g} s, maxDeltaT {max_dt:g} s, "
        f"scheme {scheme}"
    )


if __name__ == "__main__":
    main()
