# SPDX-License-Identifier: GPL-3.0-or-later
"""Bad input gives a clear FatalError naming the cause (and no crash/NaN run)."""

import os

import pytest
from faultcase import box
from foamcase import fails_with, run

pytestmark = pytest.mark.fast


def base(tmp_path, name, grains, **kw):
    """faultcase.box ending at t = 0.01 (one write)."""
    return box(tmp_path, name, grains, end=0.01, **kw)


def replace_in(case, rel, old, new):
    """Edit a case file: replace old by new in case/rel."""
    p = os.path.join(case, rel)
    txt = open(p).read()
    assert old in txt, f"'{old}' not in {p}"
    open(p, "w").write(txt.replace(old, new))


def test_overlapping_initial_grains(tmp_path, env):
    case = base(tmp_path, "overlap", [(0.05, 0.01, 0, 0.01), (0.055, 0.01, 0, 0.01)])
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), "Overlapping grains")


def test_grain_outside_mesh(tmp_path, env):
    case = base(tmp_path, "outside", [(0.5, 0.01, 0, 0.01)])
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), "outside the mesh")


def test_negative_diameter(tmp_path, env):
    case = base(tmp_path, "negative", [(0.05, 0.01, 0, -0.01)])
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), "diameter", "positive")


def test_unknown_keyword(tmp_path, env):
    case = base(tmp_path, "keyword", [(0.05, 0.01, 0, 0.01)], extra_props="frictoin 0.3;\n")
    run("blockMesh", case, env)
    fails_with(
        run("grainDeposit", case, env, check=False),
        "Unknown keyword",
        "frictoin",
        "grainProperties",
    )


def test_unknown_material_keyword(tmp_path, env):
    case = base(tmp_path, "matkey", [(0.05, 0.01, 0, 0.01)])
    replace_in(case, "constant/grainProperties", "friction 0.4;", "friction 0.4; densty 3;")
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), "Unknown keyword", "densty")


@pytest.mark.parametrize(
    "entry, words",
    [
        ("compliance -1e-7;", ("compliance of material glass", ">= 0", "allowed overlap")),
        ("compliance 1e-7; relativeCompliance 1e-3;", ("both compliance and relativeCompliance",)),
    ],
)
def test_bad_contact_compliance(tmp_path, env, entry, words):
    """A negative or doubly given contact compliance (nscd::Material) is a
    FatalIOError naming the keyword, the material and the allowed values."""
    case = base(tmp_path, "compliance", [(0.05, 0.01, 0, 0.01)])
    replace_in(case, "constant/grainProperties", "friction 0.4;", "friction 0.4; " + entry)
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), *words)


def test_missing_grain_properties(tmp_path, env):
    case = base(tmp_path, "missing", [(0.05, 0.01, 0, 0.01)])
    os.remove(os.path.join(case, "constant", "grainProperties"))
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), "grainProperties")


def test_missing_grain_state(tmp_path, env):
    case = base(tmp_path, "nostate", [(0.05, 0.01, 0, 0.01)])
    run("blockMesh", case, env)
    fails_with(run("grainFoam", case, env, check=False), "grainState.h5", "grainDeposit")


def test_unknown_material_name(tmp_path, env):
    case = base(tmp_path, "matname", [(0.05, 0.01, 0, 0.01)])
    p = os.path.join(case, "system", "grainDepositDict")
    txt = open(p).read().replace("material glass;", "material sand;")
    open(p, "w").write(txt)
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), "Unknown material", "sand")


@pytest.mark.parametrize(
    "entry, words",
    [
        (
            "method Jacobi",
            ("unknown contactSolver method", "Jacobi", "NLGS, overRelaxedNLGS, APGD, NNCG"),
        ),
        ("ordering random", ("unknown contactSolver ordering", "random", "fifo, symmetric")),
        (
            "frictionLaw tresca",
            ("unknown contactSolver frictionLaw", "tresca", "coulomb, anitescu"),
        ),
        (
            "frictionLaw anitescu; method APGD",
            ("frictionLaw anitescu", "method NLGS, overRelaxedNLGS, NNCG or newton"),
        ),
    ],
)
def test_unknown_contact_solver_choice(tmp_path, env, entry, words):
    case = base(tmp_path, "choice", [(0.05, 0.01, 0, 0.01)])
    replace_in(case, "constant/grainProperties", "maxIterations", entry + "; maxIterations")
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), *words)


def test_newton_needs_compliant_materials(tmp_path, env):
    """contactSolver method newton solves compliant contacts only: a material
    without compliance or relativeCompliance is a FatalIOError naming the
    method, the material's keyword and the fix."""
    case = base(tmp_path, "newton", [(0.05, 0.01, 0, 0.01)])
    replace_in(case, "constant/grainProperties", "maxIterations", "method newton; maxIterations")
    run("blockMesh", case, env)
    fails_with(
        run("grainDeposit", case, env, check=False),
        "contactSolver method newton",
        "relativeCompliance",
        "or use method NLGS",
    )


@pytest.mark.parametrize(
    "entry, words",
    [
        ("reorderInterval -1;", ("reorderInterval must be >= 0", "got -1")),
        ("verletSkin -0.1;", ("verletSkin must be finite and >= 0", "got -0.1")),
    ],
)
def test_negative_contact_solver_entry(tmp_path, env, entry, words):
    """contactSolver reorderInterval and verletSkin (nscd Settings) below 0: a FatalIOError naming the value."""
    case = base(tmp_path, "negative", [(0.05, 0.01, 0, 0.01)])
    replace_in(case, "constant/grainProperties", "maxIterations", entry + " maxIterations")
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), *words)


@pytest.mark.parametrize(
    "entry, words",
    [
        ("wallFriction { nowhere 0; }", ("wallFriction entry 'nowhere'", "matches no wall patch")),
        ('wallFriction { ".*" -0.1; }', ("friction coefficient must be a finite value >= 0",)),
        ("wallFriction { walls (0 1); }", ("wallFriction",)),
    ],
)
def test_wall_friction_errors(tmp_path, env, entry, words):
    """grainProperties wallFriction: an entry that matches no wall patch, a
    negative coefficient or a value that is not a number is a FatalIOError
    naming the entry."""
    case = base(tmp_path, "wallFriction", [(0.05, 0.01, 0, 0.01)], extra_props=entry + "\n")
    run("blockMesh", case, env)
    fails_with(run("grainDeposit", case, env, check=False), *words)


def test_unknown_grain_decomposition(tmp_path, env):
    """grainProperties grainDecomposition takes decomposed or replicated:
    another word is a FatalIOError naming both (also in a serial run)."""
    case = base(
        tmp_path,
        "decomposition",
        [(0.05, 0.01, 0, 0.01)],
        extra_props="grainDecomposition mixed;\n",
    )
    run("blockMesh", case, env)
    fails_with(
        run("grainDeposit", case, env, check=False),
        "grainDecomposition mixed: unknown",
        "decomposed",
        "replicated",
    )


def test_duplicated_material_name(tmp_path, env):
    """Two materials of one name in grainProperties: OpenFOAM's reading
    merges them (the later values winning, silently); grainDeposit and
    grainFoam stop with a FatalIOError naming the file, the line, the name
    and the fix; the deposit written before stays."""
    case = base(tmp_path, "twice", [(0.05, 0.01, 0, 0.01)])
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    state = open(os.path.join(case, "0", "grainState.h5"), "rb").read()
    replace_in(
        case,
        "constant/grainProperties",
        "friction 0.4;",
        "friction 0.4; }\n    glass { density 2600; friction 0.3;",
    )
    for app in ("grainDeposit", "grainFoam"):
        fails_with(
            run(app, case, env, check=False),
            "duplicate entry: glass",
            "grainProperties",
            "at line",
            "Fix",
            "its own name",
            banner="FOAM FATAL IO ERROR",
        )
    assert open(os.path.join(case, "0", "grainState.h5"), "rb").read() == state
    assert sorted(os.listdir(case)).count("0.01") == 0
