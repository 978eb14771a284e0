# SPDX-License-Identifier: GPL-3.0-or-later
"""Nusselt-number closures (src/vansCoupling/heatTransferModels) through the
nusseltTable utility, against closed forms written here independently:

- DiFeliceColburn: thesis eq. 4.9-4.12 (section 4.1.2),
    Nu = g(eps, eps Re) f(eps Re) (0.18 sqrt(eps Re) + 1.39)^2 Pr^0.4,
    g = eps^-(1.8 - exp(-(1.5 - log10(eps Re))^2 / 2))            (eq. 4.10)
    f(x) = (x + 500) / (0.11 x^1.4 + x + 500)                     (eq. 4.9)
  with Re the interstitial-slip Reynolds number and eps Re the superficial
  one (the log is base 10 as in Di Felice 1994 and in the repository's
  DallavalleDiFelice drag exponent).
- Gunn: D.J. Gunn, Int. J. Heat Mass Transfer 21 (1978) 467-476,
    Nu = (7 - 10 eps + 5 eps^2)(1 + 0.7 Re_s^0.2 Pr^1/3)
       + (1.33 - 2.4 eps + 1.2 eps^2) Re_s^0.7 Pr^1/3,  Re_s = eps Re;
  physical limit eps = 1, Re = 0: Nu = 2 (conduction from an isolated sphere).
- Ranz & Marshall (1952): Nu = 2 + 0.6 Re^1/2 Pr^1/3 (single sphere).

The thesis gives no number read off Figure 4.3 (only the curve at eps = 0.45
against the packed-bed data of its ref. [115]), so there is no figure check.
"""

import json
import os

import correlations
import pytest
from foamcase import fails_with, run

pytestmark = pytest.mark.fast

EPS, PR = 0.45, 0.71
RES = [1.0, 10.0, 100.0, 1000.0]


def nu_difelice_colburn(eps, Re, Pr, **coeffs):
    return correlations.nusselt_difelice_colburn(eps, eps * Re, Pr, **coeffs)


def nu_gunn(eps, Re, Pr):
    return correlations.nusselt_gunn(eps, eps * Re, Pr)


def nu_ranz_marshall(eps, Re, Pr):
    return correlations.nusselt_ranz_marshall(eps, eps * Re, Pr)


REFERENCE = {
    "DiFeliceColburn": nu_difelice_colburn,
    "Gunn": nu_gunn,
    "RanzMarshall": nu_ranz_marshall,
}


def make_case(tmp_path, name, body):
    """A mesh-less case: only constant/couplingProperties."""
    case = str(tmp_path / name)
    os.makedirs(os.path.join(case, "constant"))
    with open(os.path.join(case, "constant", "couplingProperties"), "w") as f:
        f.write(
            "FoamFile { version 2.0; format ascii; class dictionary;"
            " object couplingProperties; }\n" + body
        )
    return case


def table(case, env, eps, Pr, Re, extra=()):
    """Run nusseltTable -json; returns (Re list, Nu list)."""
    p = run(
        "nusseltTable",
        case,
        env,
        [
            "-eps",
            repr(eps),
            "-Pr",
            repr(Pr),
            "-Re",
            "(" + " ".join(repr(r) for r in Re) + ")",
            "-json",
            *extra,
        ],
    )
    line = [l for l in p.stdout.splitlines() if l.startswith("{")][-1]
    data = json.loads(line)
    return data["Re"], data["Nu"]


@pytest.mark.parametrize("model", ["DiFeliceColburn", "Gunn", "RanzMarshall"])
def test_closed_form(tmp_path, env, model):
    case = make_case(
        tmp_path, model, f"dragModel DallavalleDiFelice;\nheatTransferModel {model};\n"
    )
    Re, Nu = table(case, env, EPS, PR, RES)
    assert Re == RES
    for r, nu in zip(Re, Nu):
        assert nu == pytest.approx(REFERENCE[model](EPS, r, PR), rel=1e-6), r


def test_plain_columns(tmp_path, env):
    """Default output: '#' comments then 'Re Nu' columns."""
    case = make_case(tmp_path, "columns", "heatTransferModel Gunn;\n")
    p = run("nusseltTable", case, env, ["-eps", "0.45", "-Pr", "0.71", "-Re", "(1 10)"])
    out = p.stdout.splitlines()
    i = out.index("# Re Nu")
    rows = [tuple(map(float, l.split())) for l in out[i + 1 : i + 3]]
    assert [r for r, _ in rows] == [1.0, 10.0]
    for r, nu in rows:
        assert nu == pytest.approx(nu_gunn(0.45, r, 0.71), rel=1e-6)


def test_gunn_isolated_sphere_limit(tmp_path, env):
    case = make_case(tmp_path, "gunnLimit", "heatTransferModel Gunn;\n")
    _, Nu = table(case, env, 1.0, PR, [0.0])
    assert abs(Nu[0] - 2.0) < 1e-9


def test_difelice_colburn_zero_re_limit(tmp_path, env):
    """Re = 0: finite value 1.39^2 eps^-1.8 Pr^0.4, continuous with Re -> 0."""
    case = make_case(tmp_path, "dfLimit", "heatTransferModel DiFeliceColburn;\n")
    _, Nu = table(case, env, EPS, PR, [0.0, 1e-10])
    ref = 1.39**2 * EPS**-1.8 * PR**0.4
    assert Nu[0] == pytest.approx(ref, rel=1e-12)
    assert Nu[1] == pytest.approx(ref, rel=1e-4)


def test_coeffs_and_dict_option(tmp_path, env):
    """-dict file, and DiFeliceColburnCoeffs overriding delta and alpha."""
    case = make_case(tmp_path, "coeffs", "heatTransferModel Gunn;\n")
    d = str(tmp_path / "htDict")
    with open(d, "w") as f:
        f.write(
            "heatTransferModel DiFeliceColburn;\n"
            "DiFeliceColburnCoeffs { delta 5000; alpha 0.33; }\n"
        )
    Re, Nu = table(case, env, EPS, PR, RES, ["-dict", d])
    for r, nu in zip(Re, Nu):
        ref = nu_difelice_colburn(EPS, r, PR, delta=5000.0, alpha=0.33)
        assert nu == pytest.approx(ref, rel=1e-6)


FATAL_IO = "FOAM FATAL IO ERROR"


def test_unknown_model(tmp_path, env):
    case = make_case(tmp_path, "unknown", "heatTransferModel Gun;\n")
    p = run("nusseltTable", case, env, check=False)
    fails_with(
        p,
        "Unknown heatTransferModel type Gun",
        "DiFeliceColburn",
        "Gunn",
        "RanzMarshall",
        "or none (no fluid-grain heat exchange)",
        banner=FATAL_IO,
    )


def test_none_has_no_nusselt_number(tmp_path, env):
    """`heatTransferModel none;` switches the exchange off in the solvers
    (test_vansFoam_heat.py::test_heat_transfer_model_none); asked for a
    table it is a clear error, not a table of zeros."""
    case = make_case(tmp_path, "none", "heatTransferModel none;\n")
    p = run("nusseltTable", case, env, check=False)
    fails_with(
        p, "heatTransferModel none", "switches the fluid-grain heat exchange off", banner=FATAL_IO
    )


def test_unknown_coeff_keyword(tmp_path, env):
    case = make_case(
        tmp_path,
        "badCoeff",
        "heatTransferModel DiFeliceColburn;\nDiFeliceColburnCoeffs { delta 500; alfa 0.4; }\n",
    )
    p = run("nusseltTable", case, env, check=False)
    fails_with(p, "Unknown keyword", "alfa", "alpha", banner=FATAL_IO)
