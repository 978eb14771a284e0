# SPDX-License-Identifier: GPL-3.0-or-later
"""Write small grainFoam cases from Python (test helper); dictionaries are
edited in place with foamlib."""

import glob
import json
import os
import re
import shutil
import subprocess
import time

import nscdpost
from foamlib import FoamFile

HEADER = "FoamFile { version 2.0; format ascii; class %s; object %s; }\n"


def write(path, cls, obj, body):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(HEADER % (cls, obj))
        f.write(body)


def vec(v):
    return "(" + " ".join(f"{x:.17g}" for x in v) + ")"


def write_schemes(case, div=""):
    """system/fvSchemes: Euler, Gauss linear gradients, corrected Gauss
    linear laplacians and linear interpolation; divSchemes default none
    plus div (the solver's convection terms, e.g. "div(phi,U) Gauss
    linear;")."""
    write(
        os.path.join(case, "system", "fvSchemes"),
        "dictionary",
        "fvSchemes",
        "ddtSchemes { default Euler; }\ngradSchemes { default Gauss linear; }\n"
        "divSchemes { default none;" + (f" {div}" if div else "") + " }\n"
        "laplacianSchemes { default Gauss linear corrected; }\n"
        "interpolationSchemes { default linear; }\nsnGradSchemes { default corrected; }\n",
    )


def write_coupling(
    case, drag="DallavalleDiFelice", force_model="A", void_method="overlap", extra=""
):
    """constant/couplingProperties of a vansFoam / vansInterFoam case: the
    drag and force models, the void fraction method (epsMin 1e-8), then
    extra (more entries, text)."""
    write(
        os.path.join(case, "constant", "couplingProperties"),
        "dictionary",
        "couplingProperties",
        f"dragModel {drag};\nforceModel {force_model};\n"
        f"voidFraction {{ method {void_method}; epsMin 1e-8; }}\n" + extra,
    )


def write_grain_numerics(case):
    """fvSchemes and fvSolution of a case without fluid (grainFoam,
    grainDeposit)."""
    write_schemes(case)
    write(os.path.join(case, "system", "fvSolution"), "dictionary", "fvSolution", "solvers {}\n")


def make_box_case(
    case,
    lo,
    hi,
    cells,
    gravity,
    materials,
    grains=None,
    end_time=0.3,
    dt=1e-3,
    write_interval=0.1,
    two_d=True,
    extra_props="",
    deposit=None,
    wall_patches="walls",
    contact_tolerance=1e-8,
    max_iterations=5000,
):
    """A box mesh whose six (2D: four) sides are one wall patch `walls`
    (2D: z faces `frontAndBack` empty), grainProperties, g, controlDict and,
    if grains is given, a grainDepositDict with method list."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    nx, ny, nz = cells
    verts = [
        (x0, y0, z0),
        (x1, y0, z0),
        (x1, y1, z0),
        (x0, y1, z0),
        (x0, y0, z1),
        (x1, y0, z1),
        (x1, y1, z1),
        (x0, y1, z1),
    ]
    side = "(1 5 4 0) (0 4 7 3) (2 6 5 1) (3 7 6 2)"
    ends = "(0 3 2 1) (4 5 6 7)"
    if two_d:
        bnd = (
            f"walls {{ type wall; faces ({side}); }}\n"
            f"frontAndBack {{ type empty; faces ({ends}); }}\n"
        )
        nz = 1
    else:
        bnd = f"walls {{ type wall; faces ({side} {ends}); }}\n"
    write(
        os.path.join(case, "system", "blockMeshDict"),
        "dictionary",
        "blockMeshDict",
        "scale 1;\nvertices (" + " ".join(vec(v) for v in verts) + ");\n"
        f"blocks ( hex (0 1 2 3 4 5 6 7) ({nx} {ny} {nz}) simpleGrading (1 1 1) );\n"
        f"boundary (\n{bnd});\n",
    )
    write(
        os.path.join(case, "system", "controlDict"),
        "dictionary",
        "controlDict",
        f"application grainFoam; startFrom latestTime; startTime 0; stopAt endTime;\n"
        f"endTime {end_time}; deltaT {dt}; writeControl adjustableRunTime;\n"
        f"writeInterval {write_interval}; writeFormat ascii; writePrecision 17;\n"
        f"timeFormat general; timePrecision 8; runTimeModifiable false;\n",
    )
    write_grain_numerics(case)
    write(
        os.path.join(case, "constant", "g"),
        "uniformDimensionedVectorField",
        "g",
        f"dimensions [0 1 -2 0 0 0 0];\nvalue {vec(gravity)};\n",
    )
    mats = "\n".join(
        f"{name} {{ density {m['density']}; friction {m['friction']}; }}"
        for name, m in materials.items()
    )
    write(
        os.path.join(case, "constant", "grainProperties"),
        "dictionary",
        "grainProperties",
        f"materials {{\n{mats}\n}}\n"
        f"contactSolver {{ tolerance {contact_tolerance}; maxIterations {max_iterations}; }}\n"
        + extra_props,
    )
    if grains is not None:
        first = next(iter(materials))
        body = (
            deposit
            if deposit is not None
            else (
                f"material {first};\nmethod list;\ngrains (\n"
                + "\n".join("(" + " ".join(f"{v:.17g}" for v in g) + ")" for g in grains)
                + "\n);\n"
            )
        )
        write(
            os.path.join(case, "system", "grainDepositDict"), "dictionary", "grainDepositDict", body
        )


def gmsh_box(case, env, lo, hi, h, polyhedral=False):
    """Replace the case's mesh by a gmsh tetrahedral mesh of the box lo..hi
    (cell size at most h [m]), one wall patch `walls` (as make_box_case's
    3D box); polyhedral: its dual mesh (OpenFOAM's polyDualMesh, feature
    angle 70 deg), polyhedral cells."""
    size = [b - a for a, b in zip(lo, hi)]
    with open(os.path.join(case, "box.geo"), "w") as f:
        f.write(
            'SetFactory("OpenCASCADE");\n'
            f"Box(1) = {{{lo[0]}, {lo[1]}, {lo[2]}, {size[0]}, {size[1]}, {size[2]}}};\n"
            f"Mesh.CharacteristicLengthMax = {h};\n"
            'Physical Surface("walls") = {1, 2, 3, 4, 5, 6};\nPhysical Volume("fluid") = {1};\n'
        )
    subprocess.run(
        ["gmsh", "-3", "-format", "msh2", "box.geo", "-o", "box.msh"],
        cwd=case,
        check=True,
        capture_output=True,
    )
    run("gmshToFoam", case, env, args=(os.path.join(case, "box.msh"),))
    bnd = os.path.join(case, "constant", "polyMesh", "boundary")
    txt = open(bnd).read()
    open(bnd, "w").write(re.sub(r"(walls\s*\{\s*type\s+)patch", r"\1wall", txt))
    if polyhedral:
        # cwd: polyDualMesh writes its feature .obj files there
        run("polyDualMesh", case, env, args=("70", "-overwrite"), cwd=case)


def run(app, case, env, args=(), check=True, cwd=None):
    """Run an application in a case; returns CompletedProcess (stdout+stderr)."""
    p = subprocess.run(
        [app, "-case", case, *args], env=env, capture_output=True, text=True, cwd=cwd
    )
    with open(os.path.join(case, f"log.{app}"), "w") as f:
        f.write(p.stdout + p.stderr)
    if check and p.returncode != 0:
        raise AssertionError(f"{app} failed in {case}:\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}")
    return p


def run_check(app, case, env, args=()):
    """Run a test application of tests/foam that writes <case>/<app>, a
    dictionary of "name value;" lines, and return it as {name: float}."""
    run(app, case, env, args=args)
    out = {}
    for line in open(os.path.join(case, app)):
        key, value = line.rstrip(";\n").split()
        out[key] = float(value)
    return out


def log_message(text, pattern, every=False):
    """A message of a tool's output that a user reads: a FATAL ERROR or
    warning naming a keyword, a start-up report of the settings, an end of
    run summary, a utility's report.  The re.Match of `pattern` (re.M) in
    `text`, asserted to be there; every=True: all matches (re.findall).
    The numbers of the time steps (budgets, statistics, solver health) are
    not read from the log but from postProcessing/<name>/<start>/<name>.dat
    (nscdpost.read_step_data); this helper keeps the two apart."""
    if every:
        return re.findall(pattern, text, re.M)
    m = re.search(pattern, text, re.M)
    assert m, f"no {pattern!r} in the output:\n{text[-3000:]}"
    return m


def fails_with(p, *words, banner="FOAM FATAL"):
    """Check that the finished run p (a CompletedProcess of `run(...,
    check=False)`) stopped on an OpenFOAM fatal error: non-zero exit, the
    banner (e.g. "FOAM FATAL IO ERROR" for a bad input), each of words in
    its output, and no signal (no stack trace of OpenFOAM's signal
    handlers, no segmentation fault).  Returns stdout + stderr."""
    out = p.stdout + p.stderr
    assert p.returncode != 0, "expected a failure:\n" + out[-2000:]
    assert banner in out, out[-3000:]
    for w in words:
        assert w in out, f"'{w}' missing from:\n{out[-3000:]}"
    assert "printStack" not in out and "sigHandler" not in out and "Segmentation" not in out
    assert "sigsegv" not in out.lower()
    return out


def run_fatal_io(app, case, env):
    """Run an application that must stop on a FatalIOError (a bad input):
    `fails_with` its run and the FatalIOError banner; returns stdout +
    stderr for the caller's checks of the message."""
    return fails_with(run(app, case, env, check=False), banner="FOAM FATAL IO ERROR")


def decompose(case, env, n=2, delta=0.001, split=None):
    """decomposePar the case into n x 1 x 1 slabs (simple method; split:
    another (nx, ny, nz))."""
    nx, ny, nz = split or (n, 1, 1)
    write(
        os.path.join(case, "system", "decomposeParDict"),
        "dictionary",
        "decomposeParDict",
        f"numberOfSubdomains {n};\nmethod simple;\nsimpleCoeffs {{ n ({nx} {ny} {nz}); delta {delta}; }}\n",
    )
    # (in the case: decomposePar links a time's uniform/ into a rank without
    # that time directory relative to the working directory)
    run("decomposePar", case, env, args=("-force",), cwd=case)


def run_parallel(app, case, env, n=2, delta=0.001, split=None, args=(), check=True):
    """decomposePar the case into n x 1 x 1 slabs (simple method; split:
    another (nx, ny, nz)) and run `mpirun -np n app -parallel [args]`;
    writes log.<app>, skips the test when mpirun cannot start here, fails on
    a non-zero exit unless check is False (then `fails_with` checks a run
    that must stop).  Returns the CompletedProcess (stdout + stderr)."""
    import pytest

    decompose(case, env, n, delta, split)
    p = subprocess.run(
        ["mpirun", "-np", str(n), app, "-parallel", "-case", case, *args],
        env=env,
        capture_output=True,
        text=True,
    )
    with open(os.path.join(case, f"log.{app}"), "w") as f:
        f.write(p.stdout + p.stderr)
    if mpirun_could_not_start(p):
        pytest.skip("mpirun cannot start here: " + p.stderr[-300:])
    if check:
        assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    return p


def run_in_background(cmd, env, logpath, reached, timeout=60, poll=0.5, **popen):
    """Start cmd with its output in logpath and return its Popen once
    reached(the log text) holds, the process has ended or timeout seconds
    have passed (the caller checks proc.poll()); popen: more Popen
    arguments (start_new_session=True to signal a whole mpirun group)."""
    with open(logpath, "w") as log:
        proc = subprocess.Popen(
            cmd, env=env, stdout=log, stderr=subprocess.STDOUT, text=True, **popen
        )
    deadline = time.time() + timeout
    while time.time() < deadline and not reached(open(logpath).read()):
        time.sleep(poll)
        if proc.poll() is not None:
            break
    return proc


def mpirun_could_not_start(p):
    """True if the failed `mpirun` CompletedProcess p failed to start its
    ranks (no slots, no daemon), not because an application failed: a
    failing application calls MPI_ABORT, and Open MPI's help text then names
    orte_base_help_aggregate, which a test of "orte" alone takes for a start
    failure (that hid a broken case for several sessions)."""
    err = p.stderr.lower()
    if p.returncode == 0 or "mpi_abort" in err or "foam fatal" in (p.stdout + p.stderr).lower():
        return False
    return any(
        m in err
        for m in (
            "not enough slots",
            "orte was unable",
            "unable to launch",
            "daemon has unexpectedly failed",
            "could not find an allocated",
        )
    )


def add_fluid(
    case,
    rho,
    nu,
    drag="DallavalleDiFelice",
    force_model="A",
    void_method="overlap",
    max_co=0.5,
    max_dt=1e-3,
    n_correctors=2,
    n_outer=1,
    extra_coupling="",
):
    """Add the fluid of a vansFoam case to a case made by make_box_case:
    0/U (no-slip walls), 0/p (fixedFluxPressure walls), transportProperties,
    couplingProperties, fvSchemes, fvSolution, and an adjustable time step."""

    two_d = "frontAndBack" in open(os.path.join(case, "system", "blockMeshDict")).read()
    emp = "frontAndBack { type empty; }" if two_d else ""
    write(
        os.path.join(case, "0", "U"),
        "volVectorField",
        "U",
        "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (0 0 0);\n"
        f"boundaryField {{ walls {{ type noSlip; }} {emp} }}\n",
    )
    write(
        os.path.join(case, "0", "p"),
        "volScalarField",
        "p",
        "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
        f"boundaryField {{ walls {{ type fixedFluxPressure; value uniform 0; }} {emp} }}\n",
    )
    write(
        os.path.join(case, "constant", "transportProperties"),
        "dictionary",
        "transportProperties",
        f"rho {rho};\nnu {nu};\n",
    )
    write_coupling(case, drag, force_model, void_method, extra_coupling)
    write_schemes(case, "div(phi,U) Gauss limitedLinearV 1;")
    write(
        os.path.join(case, "system", "fvSolution"),
        "dictionary",
        "fvSolution",
        "solvers {\n"
        "  p { solver PCG; preconditioner DIC; tolerance 1e-9; relTol 0.01; }\n"
        "  pFinal { $p; relTol 0; }\n"
        '  "(U|UFinal)" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-9; relTol 0; }\n'
        "}\n"
        f"PIMPLE {{ momentumPredictor yes; nOuterCorrectors {n_outer}; nCorrectors {n_correctors};\n"
        "  nNonOrthogonalCorrectors 0; pRefCell 0; pRefValue 0; }\n",
    )
    with FoamFile(os.path.join(case, "system", "controlDict")) as f:
        f["application"] = "vansFoam"
        f["adjustTimeStep"] = True
        f["maxCo"] = max_co
        f["maxDeltaT"] = max_dt


def inlet_outlet_box(case):
    """Make the bottom (y = min) of a 3D make_box_case box the patch `inlet`,
    the top the patch `outlet` and the four sides `walls`; remove the pressure
    reference (the outlet fixes p).  Call after add_fluid."""
    with FoamFile(os.path.join(case, "system", "blockMeshDict")) as f:
        f["boundary"] = [
            ("inlet", {"type": "patch", "faces": [[1, 5, 4, 0]]}),
            ("outlet", {"type": "patch", "faces": [[3, 7, 6, 2]]}),
            (
                "walls",
                {"type": "wall", "faces": [[0, 4, 7, 3], [2, 6, 5, 1], [0, 3, 2, 1], [4, 5, 6, 7]]},
            ),
        ]
    fs = os.path.join(case, "system", "fvSolution")
    if os.path.exists(fs):
        with FoamFile(fs) as f:
            for key in ("pRefCell", "pRefValue"):
                if key in f["PIMPLE"]:
                    del f["PIMPLE", key]


def inflow_fields(case, velocity, side_u, side_p):
    """0/U and 0/p of a case with an `inlet` and an `outlet` patch: U
    uniform and fixed at the inlet to `velocity` (an OpenFOAM vector, e.g.
    "(0 0.1 0)" [m/s]), zeroGradient at the outlet; p fixed (0) at the
    outlet, zeroGradient at the inlet. side_u, side_p: the boundaryField
    entries of the other patches for U and for p."""
    write(
        os.path.join(case, "0", "U"),
        "volVectorField",
        "U",
        f"dimensions [0 1 -1 0 0 0 0];\ninternalField uniform {velocity};\n"
        f"boundaryField {{ inlet {{ type fixedValue; value uniform {velocity}; }}\n"
        f" outlet {{ type zeroGradient; }} {side_u} }}\n",
    )
    write(
        os.path.join(case, "0", "p"),
        "volScalarField",
        "p",
        "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
        "boundaryField { inlet { type zeroGradient; } outlet { type fixedValue; value uniform 0; }\n"
        f" {side_p} }}\n",
    )


def uniform_inflow(case, Us):
    """inlet_outlet_box with a uniform upward flow Us [m/s] everywhere at the
    start: fixedValue inlet, zeroGradient outlet, slip side walls for U; p
    fixed (0) at the outlet, zeroGradient elsewhere."""
    inflow_fields(case, f"(0 {Us:g} 0)", "walls { type slip; }", "walls { type zeroGradient; }")
    inlet_outlet_box(case)


def fixed_lattice_bed(
    case, env, spacing, d, nx, ny, rows, Us, rho, nu, drag="DallavalleDiFelice", extra_coupling=""
):
    """A fixed simple cubic lattice of glass spheres (diameter d, one per
    cubic cell of size `spacing`) in the cell rows `rows` (y indices) of an
    nx x ny x nx box, water flowing up at the superficial velocity Us
    (uniform_inflow); runs blockMesh, grainDeposit and vansFoam.  Returns
    the pressure of the last write as an (nx, ny, nx) array [kinematic]."""
    grains = [
        ((i + 0.5) * spacing, (j + 0.5) * spacing, (k + 0.5) * spacing, d)
        for j in rows
        for i in range(nx)
        for k in range(nx)
    ]
    make_box_case(
        case,
        (0, 0, 0),
        (nx * spacing, ny * spacing, nx * spacing),
        (nx, ny, nx),
        (0, 0, 0),
        {"glass": {"density": 2500, "friction": 0.4}},
        grains=grains,
        end_time=0.2,
        dt=1e-3,
        write_interval=0.2,
        two_d=False,
    )
    with FoamFile(os.path.join(case, "system", "grainDepositDict")) as f:
        f["fixed"] = True
    add_fluid(case, rho, nu, drag=drag, extra_coupling=extra_coupling)
    uniform_inflow(case, Us)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("vansFoam", case, env)
    t, name = nscdpost.time_dirs(case)[-1]
    return read_internal(os.path.join(case, name, "p")).reshape(nx, ny, nx, order="F")


def add_solver(case, field, entry, extra=()):
    """Insert the solver entry `field { entry }` first in the solvers of
    system/fvSolution (text edit: the rest of the file unchanged); extra:
    (old, new) replacements made in the same pass."""
    fs = os.path.join(case, "system", "fvSolution")
    replace_in(fs, ("solvers {\n", f"solvers {{\n  {field} {{ {entry} }}\n"), *extra)


def replace_in(path, *pairs, count=-1):
    """Text edit of the file path: each (old, new) of pairs in turn, the
    first count occurrences (-1: all).  Each old must be in the file (an
    AssertionError naming it otherwise: an edit that does nothing would
    leave a case other than the test means)."""
    txt = open(path).read()
    for old, new in pairs:
        assert old in txt, f"{old!r} not in {path}"
        txt = txt.replace(old, new, count)
    with open(path, "w") as f:
        f.write(txt)


def set_contact_tolerance(case, tol):
    """Set contactSolver's `tolerance` in constant/grainProperties to tol
    (text edit of the `contactSolver { ... }` block, on one line as
    make_box_case writes it or over several as the tutorials'); an
    AssertionError if there is not exactly one such entry."""
    path = os.path.join(case, "constant", "grainProperties")
    text, n = re.subn(
        r"(contactSolver\s*\{[^}]*?\btolerance\s+)[^;]*;", rf"\g<1>{tol};", open(path).read()
    )
    assert n == 1, f"contactSolver tolerance not found once in {path}"
    with open(path, "w") as f:
        f.write(text)


def add_scalar_transport(
    case,
    field,
    div_scheme,
    solver="solver PBiCGStab; preconditioner DILU; tolerance 1e-14; relTol 0;",
):
    """Add the fvSolution solver and the fvSchemes div(phi,<field>) entry of
    a transported scalar (T, psi) to a case made by add_fluid; `solver` and
    `div_scheme` in OpenFOAM syntax (dictionary body, scheme words)."""
    with FoamFile(os.path.join(case, "system", "fvSolution")) as f:
        f["solvers", field] = dict(FoamFile.loads(solver))
    with FoamFile(os.path.join(case, "system", "fvSchemes")) as f:
        f["divSchemes", f"div(phi,{field})"] = FoamFile.loads(f"s {div_scheme};")["s"]


read_internal = nscdpost.read_internal_field


def tutorial_modules(solver, case, names=("setupCase", "postProcess")):
    """Import the Python scripts of tutorials/<solver>/<case> (setupCase.py,
    postProcess.py) as modules, so that a case test reuses the tutorial's own
    set-up and measurement on a reduced case."""
    root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
    tut = os.path.join(root, "tutorials", solver, case)
    return tuple(
        nscdpost.load_module(f"{case}_{name}", os.path.join(tut, name + ".py")) for name in names
    )


def copy_tutorial(solver, case, dst):
    """Copy tutorials/<solver>/<case> to dst, only the files under version
    control (no output of an earlier run is reused); returns dst."""
    root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
    src = os.path.join(root, "tutorials", solver, case)
    files = subprocess.run(
        ["git", "ls-files", "."], cwd=src, check=True, capture_output=True, text=True
    ).stdout.split()
    if not files:
        raise RuntimeError(f"{src}: no files under version control")
    for f in files:
        os.makedirs(os.path.join(dst, os.path.dirname(f)), exist_ok=True)
        shutil.copy2(os.path.join(src, f), os.path.join(dst, f))
    return dst


def run_allrun(work, env, args, results, pngs, timeout=900):
    """Run work/Allrun with args (a copied tutorial) and check what every
    Allrun promises: exit 0, no log.* ending in FOAM FATAL (unless the
    Allrun says it "stopped" on purpose), a non-empty results.json at
    work/results and, for the glob work/pngs, at least one PNG that is not
    blank (the field and its colour bar drawn).  Returns results.json's
    content."""
    import matplotlib.image as mpimg
    import numpy as np

    p = subprocess.run(
        ["./Allrun", *args], cwd=work, env=env, capture_output=True, text=True, timeout=timeout
    )
    assert p.returncode == 0, f"./Allrun {' '.join(args)}:\n" + p.stdout[-3000:] + p.stderr[-3000:]
    for log in glob.glob(os.path.join(work, "**", "log.*"), recursive=True):
        text = open(log, errors="replace").read()
        if "FOAM FATAL" in text:
            # the Allruns that tolerate an early stop say so on their output
            assert "stopped" in p.stdout, f"{log}:\n{text[-2000:]}"
    res = json.load(open(os.path.join(work, results)))
    assert res, results
    found = glob.glob(os.path.join(work, pngs))
    assert found, f"no {pngs} in {work}: {sorted(os.listdir(work))}"
    for f in found:
        px = np.asarray(mpimg.imread(f))[..., :3]
        assert px.std() > 0.05 and len(np.unique(px.reshape(-1, 3), axis=0)) > 20, f
    return res


def heat_cell_case(case, grains, rhop, depth, end_time):
    """make_box_case of the grain heat tests' 2D cell: 0.04 x 0.06 m, depth,
    9 x 13 cells, gravity -9.81 y, the grains of density rhop (friction 0.3),
    dt = 1e-3 s, written once at end_time."""
    material = {"grains": {"density": rhop, "friction": 0.3}}
    box = ((0, 0, 0), (0.04, 0.06, depth), (9, 13, 1), (0, -9.81, 0))
    make_box_case(
        case, *box, material, grains=grains, end_time=end_time, dt=1e-3, write_interval=end_time
    )
