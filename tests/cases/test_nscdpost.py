# SPDX-License-Identifier: GPL-3.0-or-later
"""nscdpost's readers (foamlib underneath) on files written here with known
values, in the forms OpenFOAM v1912 writes: the reference is the values the
test wrote (17 significant digits round-trip exactly), not the reader.

The switch from the former hand-written parsers to foamlib was checked on
real runs (consistency check, not part of this suite: 353 grain sets and
1,355 vol fields of seven tutorials' outputs, identical values, dtypes and
shapes; commit message of the change)."""

import os

import nscdpost
import numpy as np
import pytest

pytestmark = pytest.mark.fast

HEAD = (
    "FoamFile\n{\n    version     2.0;\n    format      ascii;\n    class       %s;\n"
    '    location    "0.1/lagrangian/grains";\n    object      %s;\n}\n'
)


def _write(path, cls, body):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(HEAD % (cls, os.path.basename(path)) + body)


def _vecs(a):
    return "\n".join("(" + " ".join(f"{v:.17g}" for v in row) + ")" for row in a)


@pytest.fixture
def grains_case(tmp_path):
    """A case with one time 0.1 holding 5 grains: positions (legacy
    `(x y z) celli` list), d, U, a uniform fixed list and a vector Ffluid."""
    rng = np.random.default_rng(1)
    x, d, U, F = (
        rng.random((5, 3)),
        rng.random(5) * 1e-3,
        rng.normal(size=(5, 3)),
        rng.normal(size=(5, 3)),
    )
    g = tmp_path / "0.1" / "lagrangian" / "grains"
    _write(
        str(g / "positions"),
        "Cloud<passiveParticle>",
        "5\n(\n"
        + "\n".join(f"({a:.17g} {b:.17g} {c:.17g}) {i}" for i, (a, b, c) in enumerate(x))
        + "\n)\n",
    )
    _write(str(g / "d"), "scalarField", "5\n(\n" + "\n".join(f"{v:.17g}" for v in d) + "\n)\n")
    _write(str(g / "U"), "vectorField", "5\n(\n" + _vecs(U) + "\n)\n")
    _write(str(g / "fixed"), "labelField", "5{0}\n")
    _write(str(g / "Ffluid"), "vectorField", "5\n(\n" + _vecs(F) + "\n)\n")
    return str(tmp_path), dict(x=x, d=d, U=U, Ffluid=F)


def test_read_grains_exact(grains_case):
    case, ref = grains_case
    assert nscdpost.time_dirs(case) == [(0.1, "0.1")]
    g = nscdpost.read_grains(case, "0.1")
    for k in ("x", "d", "U", "Ffluid"):
        assert g[k].dtype == np.float64 and np.array_equal(g[k], ref[k]), k
    assert g["fixed"].dtype == bool and not g["fixed"].any()


def test_uniform_and_empty_lists(tmp_path):
    _write(str(tmp_path / "u"), "vectorField", "3{(1 2.5 -3)}\n")
    _write(str(tmp_path / "s"), "scalarField", "4{0.25}\n")
    _write(str(tmp_path / "e"), "vectorField", "0()\n")
    assert np.array_equal(nscdpost.read_vector_field(str(tmp_path / "u")), [[1, 2.5, -3]] * 3)
    assert np.array_equal(nscdpost.read_scalar_field(str(tmp_path / "s")), [0.25] * 4)
    assert nscdpost.read_vector_field(str(tmp_path / "e")).shape == (0, 3)


def test_read_internal_field(tmp_path):
    vol = (
        "dimensions [0 0 0 0 0 0 0];\ninternalField %s;\n"
        "boundaryField { walls { type calculated; value uniform 9; } }\n"
    )
    _write(str(tmp_path / "a"), "volScalarField", vol % "nonuniform List<scalar> 3(0.1 1 2e-3)")
    _write(str(tmp_path / "b"), "volVectorField", vol % "uniform (1 2 3)")
    _write(str(tmp_path / "c"), "volScalarField", vol % "uniform 0.5")
    _write(
        str(tmp_path / "k"),
        "volScalarField::Internal",
        "dimensions [0 0 0 0 0 0 0];\nvalue nonuniform List<scalar> 2(4 5);\n",
    )
    assert np.array_equal(nscdpost.read_internal_field(str(tmp_path / "a")), [0.1, 1.0, 2e-3])
    assert np.array_equal(nscdpost.read_internal_field(str(tmp_path / "b")), [1.0, 2.0, 3.0])
    c = nscdpost.read_internal_field(str(tmp_path / "c"))
    assert c.shape == () and c == 0.5
    assert np.array_equal(nscdpost.read_internal_field(str(tmp_path / "k")), [4.0, 5.0])
    with pytest.raises(FileNotFoundError):
        nscdpost.read_internal_field(str(tmp_path / "missing"))
