# SPDX-License-Identifier: GPL-3.0-or-later
"""vansInterFoam cases of the tests (test helper): the dam-break tutorial
(dam_break) and the files interFoam itself needs (interfoam_case), a state
with no grain (zero_grains), a make_box_case box turned into a water/air
case (add_two_phase) and the closed 2D basin (basin_box, basin)."""

import os
import re
import subprocess
import sys

from foamcase import make_box_case, replace_in, run, write, write_coupling, write_schemes

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
TUT = os.path.join(ROOT, "tutorials", "vansInterFoam", "damBreak")
G = 9.81


def dam_break(case, env, n=16, end=None, precision=None):
    """tutorials/vansInterFoam/damBreak on an n-cell (a/n) mesh, meshed and
    set (blockMesh, setFields); end: endTime and the write interval;
    precision: writePrecision."""
    subprocess.run(
        [sys.executable, os.path.join(TUT, "setupCase.py"), case, str(n)],
        capture_output=True,
        text=True,
        check=True,
    )
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read()
    if end is not None:
        txt = re.sub(r"endTime\s+\S+;", f"endTime {end};", txt)
        txt = re.sub(r"writeInterval\s+0\.01;", f"writeInterval {end};", txt)
    if precision is not None:
        txt = re.sub(r"writePrecision\s+\d+;", f"writePrecision {precision};", txt)
    open(cd, "w").write(txt)
    run("blockMesh", case, env)
    run("setFields", case, env)


def interfoam_case(case):
    """The extra files interFoam needs (laminar model, pcorr solver, its name
    of the viscous transpose term)."""
    write(
        os.path.join(case, "constant", "turbulenceProperties"),
        "dictionary",
        "turbulenceProperties",
        "simulationType laminar;\n",
    )
    replace_in(
        os.path.join(case, "system", "fvSolution"),
        (
            "    p_rgh\n",
            '    "pcorr.*" { solver PCG; preconditioner DIC; tolerance 1e-8; relTol 0; }\n'
            "    p_rgh\n",
        ),
        count=1,
    )
    replace_in(
        os.path.join(case, "system", "fvSchemes"),
        (
            "div((muEff*dev2(T(grad(U))))) Gauss linear;",
            "div((muEff*dev2(T(grad(U))))) Gauss linear;\n"
            "    div(((rho*nuEff)*dev2(T(grad(U))))) Gauss linear;",
        ),
    )


def zero_grains(case):
    """grainProperties + couplingProperties + a state with no grain."""
    write(
        os.path.join(case, "constant", "grainProperties"),
        "dictionary",
        "grainProperties",
        "materials { glass { density 2500; friction 0.3; } }\n",
    )
    write_coupling(case)
    write(
        os.path.join(case, "system", "grainDepositDict"),
        "dictionary",
        "grainDepositDict",
        "material glass;\nmethod list;\ngrains ();\n",
    )


def water_below(case, level, nu_water=1e-6, rho_water=1000):
    """system/setFieldsDict (water below y = level, air above) and
    constant/transportProperties (water nu_water, rho_water; air)."""
    write(
        os.path.join(case, "system", "setFieldsDict"),
        "dictionary",
        "setFieldsDict",
        "defaultFieldValues ( volScalarFieldValue alpha.water 0 );\n"
        f"regions ( boxToCell {{ box (-1 -1 -1) (1 {level} 1);\n"
        "  fieldValues ( volScalarFieldValue alpha.water 1 ); } );\n",
    )
    write(
        os.path.join(case, "constant", "transportProperties"),
        "dictionary",
        "transportProperties",
        "phases (water air);\n"
        f"water {{ transportModel Newtonian; nu {nu_water}; rho {rho_water}; }}\n"
        "air { transportModel Newtonian; nu 1.48e-5; rho 1; }\n"
        "sigma 0.072;\n",
    )


def add_two_phase(
    case,
    env,
    level,
    fixed=False,
    dt=None,
    max_co=0.5,
    p_tol="tolerance 1e-10; relTol 0.01;",
    nu_water=1e-6,
    open_top=None,
):
    """Turn a make_box_case case (walls `walls`) into a vansInterFoam case:
    water below y = level, air above (the drag sees the local mixture
    density and viscosity); blockMesh, setFields, grainDeposit.  open_top:
    the alpha.water flowing in through the top, which becomes the open
    patch `top` (p_rgh 0, pressureInletOutletVelocity); None: a wall."""
    if fixed:
        open(os.path.join(case, "system", "grainDepositDict"), "a").write("fixed yes;\n")
    bm = os.path.join(case, "system", "blockMeshDict")
    two_d = "frontAndBack" in open(bm).read()
    emp = "frontAndBack { type empty; }" if two_d else ""
    if open_top is not None:
        txt = open(bm).read().replace(" (3 7 6 2)", "")
        open(bm, "w").write(
            txt.replace("boundary (\n", "boundary (\ntop { type patch; faces ((3 7 6 2)); }\n")
        )
    top = (
        {"U": "", "p_rgh": "", "alpha.water": ""}
        if open_top is None
        else {
            "U": "top { type pressureInletOutletVelocity; value uniform (0 0 0); }",
            "p_rgh": "top { type totalPressure; p0 uniform 0; value uniform 0; }",
            "alpha.water": f"top {{ type inletOutlet; inletValue uniform {open_top}; "
            f"value uniform {open_top}; }}",
        }
    )
    write(
        os.path.join(case, "0", "U"),
        "volVectorField",
        "U",
        "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
        f"boundaryField {{ walls {{ type noSlip; }} {emp} {top['U']} }}\n",
    )
    write(
        os.path.join(case, "0", "p_rgh"),
        "volScalarField",
        "p_rgh",
        "dimensions [1 -1 -2 0 0 0 0];\ninternalField uniform 0;\n"
        f"boundaryField {{ walls {{ type fixedFluxPressure; value uniform 0; }} {emp} {top['p_rgh']} }}\n",
    )
    write(
        os.path.join(case, "0", "alpha.water"),
        "volScalarField",
        "alpha.water",
        "dimensions [0 0 0 0 0 0 0];\ninternalField uniform 0;\n"
        f"boundaryField {{ walls {{ type zeroGradient; }} {emp} {top['alpha.water']} }}\n",
    )
    water_below(case, level, nu_water)
    write_coupling(case)
    write_schemes(
        case,
        "div(rhoPhi,U) Gauss linearUpwind grad(U);\n"
        "  div(phi,alpha) Gauss vanLeer; div(phirb,alpha) Gauss linear;\n"
        "  div((muEff*dev2(T(grad(U))))) Gauss linear;",
    )
    write(
        os.path.join(case, "system", "fvSolution"),
        "dictionary",
        "fvSolution",
        "solvers {\n"
        '  "alpha.water.*" { nAlphaCorr 2; nAlphaSubCycles 1; cAlpha 1; MULESCorr no;\n'
        "    nLimiterIter 3; }\n"
        f"  p_rgh {{ solver PCG; preconditioner DIC; {p_tol} }}\n"
        "  psiEps { solver PCG; preconditioner DIC; tolerance 1e-12; relTol 0; }\n"
        "  p_rghFinal { $p_rgh; relTol 0; }\n"
        '  "(U|UFinal)" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-10; relTol 0; }\n'
        "}\n"
        "PIMPLE { momentumPredictor no; nOuterCorrectors 1; nCorrectors 3;\n"
        "  nNonOrthogonalCorrectors 0; pRefCell 0; pRefValue 0; }\n",
    )
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read().replace("application grainFoam;", "application vansInterFoam;")
    if dt is None:
        txt += f"adjustTimeStep yes; maxCo {max_co}; maxAlphaCo {max_co}; maxDeltaT 1e-3;\n"
    else:
        txt += "adjustTimeStep no; maxAlphaCo 1;\n"
    open(cd, "w").write(txt)
    run("blockMesh", case, env)
    run("setFields", case, env)
    run("grainDeposit", case, env)


def basin_box(case, grains, end, dt, write_interval, materials=None, **box):
    """The basin's closed 2D box 0.04 x 0.06 m, 16 x 24 cells (2.5 mm),
    gravity -G y, grains from a list (materials: 2 mm glass discs unless
    given); box: more make_box_case arguments."""
    make_box_case(
        case,
        (0, 0, 0),
        (0.04, 0.06, 0.0025),
        (16, 24, 1),
        (0, -G, 0),
        materials or {"glass": {"density": 2500, "friction": 0.3}},
        grains=grains,
        end_time=end,
        dt=dt,
        write_interval=write_interval,
        **box,
    )


def basin(case, env, grains, fixed, end, dt=None, write_interval=None, **kw):
    """Closed 2D box 0.04 x 0.06 m (basin_box), water below y = 0.03 m, air
    above, grains from a list (2 mm glass discs)."""
    basin_box(case, grains, end, dt or 1e-3, write_interval or end)
    add_two_phase(case, env, 0.03, fixed=fixed, dt=dt, **kw)
