# SPDX-License-Identifier: GPL-3.0-or-later
"""vansFoam's per-grain coupling sub-models with the grains decomposed over
the ranks: rotationCoupling (a grain's fluid torque and rotational drag
summed over its copies, as its drag), undisturbedVelocity (the overlap
kernel's widths gathered over a grain's copies, as the fluid velocity) and
resolvedCellsPerDiameter (the sizes of the cells a grain overlaps summed
over its copies; the pressure scheme the same on every rank).
grainDecomposition replicated stays an option (checked with rotation).

Reference, independent of the decomposition: the serial run of the same
case (undecomposed grains and mesh), grain by grain; a sum made on one
rank's cells only changes the drag coefficient of a grain straddling a
processor boundary by O(1), and its path by far more than the tolerance.
"""

import os
import shutil

import h5py
import numpy as np
import pytest
from faultcase import open_bottom_cube
from foamcase import run, run_parallel
from test_vansFoam import small_sedimentation

pytestmark = [pytest.mark.slow, pytest.mark.mpi]

END = 0.04

#: (couplingProperties entries, spheres (x, y, z, d)) per sub-model: the
#: spheres straddle the processor boundaries x = 0.02 and y = 0.02 of the
#: 40 mm cube of 10 mm cells
CASES = {
    # dilute small spheres (h/d = 2.5, the model's range) settling
    "undisturbedVelocity": (
        "undisturbedVelocity steadyOseen;",
        [
            (0.02, 0.025, 0.02, 0.004),
            (0.011, 0.03, 0.015, 0.004),
            (0.029, 0.02, 0.026, 0.004),
            (0.018, 0.033, 0.03, 0.004),
        ],
    ),
    # spheres of a cell's size, resolved (d >= 0.5 h)
    "resolvedCellsPerDiameter": (
        "resolvedCellsPerDiameter 0.5;",
        [(0.02, 0.025, 0.02, 0.01), (0.012, 0.032, 0.03, 0.008)],
    ),
}


def _add_coupling(case, entries):
    """Add entries to constant/couplingProperties (before forceModel)."""
    path = os.path.join(case, "constant", "couplingProperties")
    text = open(path).read()
    open(path, "w").write(text.replace("forceModel", entries + "\nforceModel", 1))


def _state(case, time_name):
    """Positions, velocities and angular velocities in id order (the
    gathered grain state)."""
    with h5py.File(os.path.join(case, time_name, "grainState.h5"), "r") as f:
        order = np.argsort(f["grainIds"][()])
        return tuple(f[c][()][order] for c in ("positions", "velocities", "angularVelocities"))


def _deviation(serial, par, t, d, label):
    """Largest distance from the serial positions [d], and largest velocity
    and angular velocity differences relative to the largest serial ones,
    at time t; also the serial scales (speed, spin)."""
    a, b = _state(serial, t), _state(par, t)
    dx = np.max(np.abs(a[0] - b[0])) / d
    scales = [np.max(np.linalg.norm(v, axis=1)) for v in a[1:]]
    dv, dw = (np.max(np.abs(u - v)) / max(s, 1e-300) for u, v, s in zip(a[1:], b[1:], scales))
    print(
        f"[ {label} t={t} ] max |x - x_serial| {dx:.2e} d, |v - v_serial| {dv:.2e} and "
        f"|w - w_serial| {dw:.2e} of the largest serial ({scales[0]:.3e} m/s, {scales[1]:.3e} rad/s)"
    )
    return dx, dv, dw, scales


@pytest.fixture(scope="module")
def rotation_runs(tmp_path_factory, env):
    """test_vansFoam_decomposed's sedimentation (60 discs of 3 mm through
    water) with rotationCoupling yes to 0.1 s: serial, with the grains
    decomposed on 2 and 4 ranks, and on 2 ranks with grainDecomposition
    replicated (the option)."""
    base = tmp_path_factory.mktemp("rotationDecomposed")
    serial = str(base / "serial")
    small_sedimentation(serial, env, end=0.1, write=0.05, nrow=6, ncol=10)
    _add_coupling(serial, "rotationCoupling yes;")
    out = {"serial": serial}
    for name, n, split in (("np2", 2, (2, 1, 1)), ("np4", 4, (2, 2, 1)), ("replicated", 2, None)):
        par = str(base / name)
        shutil.copytree(serial, par)
        if name == "replicated":
            with open(os.path.join(par, "constant", "grainProperties"), "a") as f:
                f.write("grainDecomposition replicated;\n")
        p = run_parallel("vansFoam", par, env, n=n, split=split)
        if name == "replicated":
            assert "every rank holds every grain (grainDecomposition replicated)" in p.stdout
        else:
            assert f"grains decomposed over {n} ranks" in p.stdout
        out[name] = par
    run("vansFoam", serial, env)
    return out


@pytest.mark.parametrize("name", ["np2", "np4", "replicated"])
def test_rotation_coupling_decomposed_matches_serial(rotation_runs, name):
    """rotationCoupling with the grains decomposed: after 0.05 and 0.1 s
    (the rows colliding and spinning as they fall) every disc is within
    1e-4 d of its serial position and its angular velocity within 1e-3 of
    the largest serial |omega| (the solver tolerances, as the sedimentation
    without rotation; measured 2026-11-26: 1.7-8.1e-6 d and 2.6e-5 to
    1.0e-4 on 2 and 4 ranks, replicated alike); the same with
    grainDecomposition replicated.  The torque summed on each rank's cells
    only (a mutation: no sum over the copies) gives 0.59 d and 1.9 times
    the largest spin at 0.05 s."""
    for t in ("0.05", "0.1"):
        dx, _, dw, scales = _deviation(rotation_runs["serial"], rotation_runs[name], t, 3e-3, name)
        assert scales[1] > 1e-3, "the discs should spin"
        assert dx < 1e-4
        assert dw < 1e-3


@pytest.mark.parametrize("model", list(CASES))
@pytest.mark.parametrize("n,split", [(2, (2, 1, 1)), (4, (2, 2, 1))])
def test_submodel_decomposed_matches_serial(tmp_path, env, model, n, split):
    """The spheres settle as in the serial run: after END (40 steps) every
    sphere is within 1e-3 d of its serial position and its velocity within
    1e-3 of the largest serial speed.  The decomposition's own scatter (the
    fluid solvers in parallel) sets the scale: the same cases without the
    sub-model on 4 ranks deviate by 3.5e-5 d (small spheres) and 1.6e-4 d
    (spheres of a cell's size), measured 2026-11-26, as with it (3.4e-5 d,
    1.6e-4 d; 2 ranks: 6e-8 d and 1.6e-4 d).  A kernel width summed on one
    rank's cells only changes undisturbedVelocity's drag correction of the
    spheres straddling the boundaries by O(1); on this uniform mesh the
    resolved marking does not depend on the sum (the mean cell size is the
    same on every rank), so that case checks the decomposed run itself
    (collectives in step, the pressure scheme the same on every rank)."""
    entries, grains = CASES[model]
    serial = str(tmp_path / "serial")
    open_bottom_cube(serial, env, grains, end=END, write_interval=END)
    path = os.path.join(serial, "constant", "couplingProperties")
    text = open(path).read()
    open(path, "w").write(text.replace("forceModel", entries + "\nforceModel", 1))
    par = str(tmp_path / f"np{n}")
    shutil.copytree(serial, par)
    run("vansFoam", serial, env)
    p = run_parallel("vansFoam", par, env, n=n, split=split)
    assert f"grains decomposed over {n} ranks" in p.stdout
    dx, dv, _, scales = _deviation(
        serial, par, str(END), min(g[3] for g in grains), f"{model} np{n}"
    )
    assert scales[0] > 1e-3, "the spheres should settle"
    assert dx < 1e-3
    assert dv < 1e-3
