# SPDX-License-Identifier: GPL-3.0-or-later
"""vansInterFoam with the grains decomposed over the ranks (grainDecomposition
decomposed, the default of a parallel run): each rank owns the grains whose
centre lies in its cells and maps them and its neighbours' ghosts onto its
own cells; the per-grain overlap sums of the VOF coupling (mapped volume,
U, eps, grad p and the local mixture rho and mu of the drag and buoyancy)
are completed over the grains' copies as vansFoam's are.

References, independent of the decomposition:
  - the serial run of the same case.  Five 2 mm discs falling from the air
    through the free surface into the water of the closed 2D basin
    (interfoamcase.basin), the surface and a disc lying on the processor
    boundaries (y = 0.03 m on 2 ranks; x = 0.02 m as well on 4): the discs
    never touch one another, so nothing amplifies the solvers' round-off.
    Every pressure solve is converged to 1e-12 (relTol 0), so the
    decomposed preconditioner changes nothing beyond that tolerance: every
    disc must stay within 1e-9 d of its serial position, the change of the
    serial run when the p_rgh and psiEps tolerances are 1e-11 instead
    (measured 2026-11-26: 8e-10 d at 0.15 s; the decomposed runs 5e-11 d on
    2 and on 4 ranks.  With relTol 0.01 in the first pressure correctors
    the decomposed runs differed by 5e-6 d, the serial one by 4e-9 d: the
    block preconditioner's different intermediate pressures.  Before the
    ghosts over a rank's cells were exchanged at the start, the disc on x =
    0.02 m was mapped by half on 4 ranks at the first step, and alpha left
    [0, 1] by 0.25 at the second);
  - the reduced granularCollapse tutorial (`solitary`, 400 discs, 20 mm
    cells, 0.5 m basin, 0.25 s), its column cut by the y slabs of 2 and 4
    ranks.  Its dense contact network, solved to the contact tolerance,
    turns any round-off difference into a different grain arrangement
    (serial runs at contact tolerances 0.8 and 1.2 x 1e-5 differ from the
    1e-5 run by up to 16 d for single grains at 0.25 s), so the decomposed
    runs are checked against that serial scatter: an ensemble of seven
    serial runs (contact tolerance 0.7 to 1.3 x 1e-5), grain by grain by id
    (the root mean square of the grains' distances at every write), at the
    wave gauges and for the granular front; each decomposed run's deviation
    from the 1e-5 run must lie within 1.5 times the largest difference
    between two members of the ensemble (21 pairs).  The deviation is one
    draw of that pair difference, whose tail is heavy: the largest gauge
    difference of the 0.8 and 1.2 runs from the 1e-5 run fell from 4.7e-3
    to 1.1e-3 m when a change of summation order changed the runs'
    round-off (2026-11-29; the np 2 run's stayed 3.2-3.4e-3 m), and the 21
    pairs then spread from 2.9e-4 to 3.4e-3 m, all growing after 0.1 s;
  - the water volume sum(eps alpha V): conserved to round-off (closed
    domain, explicit MULES) on every rank count, and equal to the serial
    run's;
  - no grain lost or duplicated: every id once at every write.
"""

import itertools
import os
import re
import shutil

import nscdpost
import numpy as np
import pytest
from foamcase import log_message, run, run_parallel, set_contact_tolerance, tutorial_modules
from interfoamcase import basin

pytestmark = pytest.mark.slow

SPLITS = {2: (1, 2, 1), 4: (1, 4, 1)}


def _positions(case, time_name, n_grains):
    """Grain centres in id order (reconstructed state), every id once."""
    g = nscdpost.read_grains(case, time_name)
    ids = np.asarray(g["grainId"])
    assert sorted(ids) == list(range(n_grains)), f"{case} {time_name}: a grain lost or duplicated"
    return np.asarray(g["x"])[np.argsort(ids)]


def _water(case):
    return np.asarray(nscdpost.read_step_data(case, "waterVolume")["waterVolume"])


def _check_water(serial, par):
    """Conserved to round-off, and the serial run's volume."""
    ws, wp = _water(serial), _water(par)
    assert len(wp) == len(ws) > 10
    assert np.ptp(wp) < 1e-12 * ws[0], np.ptp(wp) / ws[0]
    assert abs(wp[0] - ws[0]) < 1e-12 * ws[0]


def _run_decomposed(case, env, n, split):
    """mpirun -np n vansInterFoam on y slabs; the log says the grains are
    decomposed and that each rank read its part; reconstructPar."""
    p = run_parallel("vansInterFoam", case, env, n=n, split=split)
    log_message(p.stdout, rf"grainCloud: grains decomposed over {n} ranks \(owned per rank")
    assert "each rank read its part of the start state" in p.stdout
    assert "every rank holds every grain" not in p.stdout
    run("reconstructPar", case, env)
    return p


@pytest.mark.mpi
def test_sinking_discs_match_serial(tmp_path, env):
    d = 2e-3
    grains = [(0.008 + 0.006 * i, 0.036 + 0.0025 * (i % 2), 0, d) for i in range(5)]
    serial = str(tmp_path / "serial")
    basin(
        serial,
        env,
        grains,
        fixed=False,
        end=0.15,
        write_interval=0.05,
        p_tol="tolerance 1e-12; relTol 0;",
    )
    cases = {}
    for n in (2, 4):
        cases[n] = str(tmp_path / f"np{n}")
        shutil.copytree(serial, cases[n])
    run("vansInterFoam", serial, env)
    for n, case in cases.items():
        _run_decomposed(case, env, n, (1, 2, 1) if n == 2 else (2, 2, 1))
        for t in ("0.05", "0.1", "0.15"):
            xs, xp = _positions(serial, t, 5), _positions(case, t, 5)
            dx = np.max(np.linalg.norm(xs - xp, axis=1))
            print(f"[ np{n} t={t} ] max |x - x_serial| = {dx / d:.2e} d")
            assert dx < 1e-9 * d
        # the discs crossed the surface and fell into the water
        assert np.all(_positions(case, "0.15", 5)[:, 1] < 0.03)
        _check_water(serial, case)


def _gauges(case):
    """(time, eta at each gauge) rows of waveGauges.dat."""
    return np.loadtxt(os.path.join(case, "postProcessing", "gauges", "0", "waveGauges.dat"))


def _front(case):
    """The granular front's position at y = h0 at the end [m]."""
    path = os.path.join(case, "postProcessing", "front", "0", "granularFront.dat")
    return float(np.loadtxt(path)[-1, 1])


def _measures(ref, case, n_grains, times):
    """Deviations of case from ref: the grains' rms distance at each write
    [m], the largest gauge difference [m], the front difference [m]."""
    rms = [
        float(
            np.sqrt(
                np.mean(
                    np.sum(
                        (_positions(ref, t, n_grains) - _positions(case, t, n_grains)) ** 2, axis=1
                    )
                )
            )
        )
        for t in times
    ]
    ga, gb = _gauges(ref), _gauges(case)
    assert ga.shape == gb.shape, "the runs took different time steps"
    return rms, float(np.max(np.abs(ga[:, 1:] - gb[:, 1:]))), abs(_front(ref) - _front(case))


@pytest.mark.mpi
def test_granular_collapse_matches_serial_scatter(tmp_path, env):
    setup, _ = tutorial_modules("vansInterFoam", "granularCollapse")
    base = str(tmp_path / "serial")
    params = setup.setup(base, "solitary", dx=0.02, basin=0.5, end_time=0.25)
    # a second gauge by the column, where the wave starts
    cd = os.path.join(base, "system", "controlDict")
    text, k = re.subn(r"x\s+\(0\.36\);", "x (0.16 0.36);", open(cd).read())
    assert k == 1
    open(cd, "w").write(text)
    for app in ("blockMesh", "setFields", "grainDeposit"):
        run(app, base, env)
    n_grains = params["n_grains"]
    cases = {}
    # the perturbed serial runs: name -> contact tolerance
    perturbed = {f"tol{f}": f * 1e-5 for f in (0.7, 0.8, 0.9, 1.1, 1.2, 1.3)}
    for name in [*perturbed, 2, 4]:
        cases[name] = str(tmp_path / str(name))
        shutil.copytree(base, cases[name])
    for name, tol in perturbed.items():
        set_contact_tolerance(cases[name], tol)
        run("vansInterFoam", cases[name], env)
    run("vansInterFoam", base, env)
    times = [name for _, name in nscdpost.numeric_dirs(base)][1:]
    assert len(times) == 10
    ensemble = [base] + [cases[k] for k in perturbed]
    scatter = [_measures(a, b, n_grains, times) for a, b in itertools.combinations(ensemble, 2)]
    rms_band = np.max([s[0] for s in scatter], axis=0)
    eta_band = max(s[1] for s in scatter)
    front_band = max(s[2] for s in scatter)
    for n in (2, 4):
        p = _run_decomposed(cases[n], env, n, SPLITS[n])
        owned = [
            int(v) for v in log_message(p.stdout, r"owned per rank \d+\(([\d ]+)\)")[1].split()
        ]
        assert sum(owned) == n_grains and sum(o > 0 for o in owned) >= 2, owned
        rms, eta, front = _measures(base, cases[n], n_grains, times)
        print(
            f"[ np{n} ] rms/d {np.round(np.array(rms) / 5e-3, 2)} "
            f"(serial scatter {np.round(rms_band / 5e-3, 2)}); "
            f"gauges {eta:.2e} m (scatter {eta_band:.2e}); front {front:.2e} m "
            f"(scatter {front_band:.2e})"
        )
        assert np.all(np.array(rms) <= 1.5 * rms_band)
        assert eta <= 1.5 * eta_band
        assert front <= 1.5 * front_band
        _check_water(base, cases[n])
