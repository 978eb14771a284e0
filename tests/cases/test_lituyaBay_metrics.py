# SPDX-License-Identifier: GPL-3.0-or-later
"""The lituyaBay measures (tutorials/vansInterFoam/lituyaBay/slideMetrics.py)
on synthetic data with known answers, no run (the reduced run's values are
checked in test_lituyaBay.py).

References (exact results of the constructions):
- Water layer: a layer of thickness 3 m on a 45 deg shore up to the
  along-shore distance S (0.5 m beyond), its exact water fraction in 3 m
  cells aligned with the shore whose columns do not line up with the 5 m
  bins: int alpha dxi along the normal is 3 m (0.5 m) in every bin to
  round-off (each cell spread over its extent), the bins that straddle S
  excepted, and the run-up is the bin below S (within a bin).
- Centre of mass: grains sliding rigidly down the slope with v = v0 + a t;
  the centre of mass's height crosses y = 0 at the root t* of the quadratic
  and its speed there is v0 + a t* (linear interpolation between samples:
  the height's curvature gives |dt*| <= a dt^2 / (8 v), i.e. a relative
  speed error < 1e-4 with dt = 0.05 s).
- Flux-weighted speed: grains of masses m_i crossing a band of half width w
  at constant speeds v_i, the band sums of grainCentreOfMass.C recomputed
  each step: int mdot dt = sum m_i within the step sampling v dt / (2 w),
  and the weighted speed sum m_i v_i / sum m_i (each grain's steps in the
  band share the sampling error of numerator and denominator: exact).
- Froude: 110 m/s in h = 122 m is 3.18 (thesis 5.3.1).
- Spray outflow (postProcess.atmosphere_outflow): a constant flux F through
  the atmosphere leaves F t by time t; a run stopped by a signal at t_r and
  restarted there has no flux row for its last step: the outflow at the
  water-volume steps stays F t (exact for a constant flux), one step late at
  the stopped step (counted with the next row, over both steps' dt); a run
  stopped at its end has no next row: that last step's outflow is unknown
  and the water balance leaves it out (`outflow_known`).
- Thesis-grains slide (setupCase.py --packing, grainDeposit method rain,
  packed_block): geometry only, no run: the rock area is the stated mass
  98.5e6 kg / 2640 kg/m^3 to round-off, the mean radius 1.35 m within the
  sampling of 6,015 uniform diameters (2 %), no two discs overlap, none
  crosses the slope, and the interior's solid fraction is that of a dense
  2D disc packing (0.75-0.86: random close packing of discs ~0.82).
- Launched slide (SLIDE_SPEED): a consistency check of the case set-up (the
  launch velocity lies along the 45 deg left shore, pointing down).
"""

import json
import math
import os
import re
import subprocess
import sys

import numpy as np
import pytest
from foamcase import run, tutorial_modules

pytestmark = pytest.mark.fast

sm, setup, post = tutorial_modules(
    "vansInterFoam", "lituyaBay", names=("slideMetrics", "setupCase", "postProcess")
)

SQ2 = math.sqrt(2.0)


def layer_cells(toe, thickness, s_end, h=3.0, s0=0.7):
    """Cells of size h aligned with the shore (as gmsh's frontal quads
    along a boundary), rows from xi = 0, columns from s = s0 - h (not aligned
    with the bins), with the exact water fraction of the layer
    0 <= xi <= thickness (s_c < s_end) or 0.5 m (beyond)."""
    sc = np.arange(s0 - h, 900, h) + h / 2
    xc = np.arange(0, 60, h) + h / 2
    S, X = np.meshgrid(sc, xc)
    S, X = S.ravel(), X.ravel()
    t = np.where(S < s_end, thickness, 0.5)
    alpha = np.clip((t - (X - h / 2)) / h, 0.0, 1.0)
    C = np.asarray(toe) + np.outer(S, [1, 1]) / SQ2 + np.outer(X, [-1, 1]) / SQ2
    return C, alpha, np.full(len(S), h * h)


def test_water_layer_thickness_and_runup():
    toe = np.array([1220.0, -122.0])
    s_end, ds = 420.0, 5.0
    C, alpha, V = layer_cells(toe, 3.0, s_end)
    s, h = sm.shore_layer(C, alpha, V, toe, depth=1.0, ds=ds, xi_max=50.0)
    inner = (s > 10) & (s < s_end - 10)
    assert np.allclose(h[inner], 3.0, rtol=1e-12), h[inner]
    beyond = (s > s_end + 10) & (s < 850)
    assert np.allclose(h[beyond], 0.5, rtol=1e-12), h[beyond]
    top = sm.layer_runup(s, h, 1.0)
    assert abs(top - s_end) <= ds, (top, s_end)
    # a gap breaks the layer: the run-up stops below it
    h2 = h.copy()
    h2[(s > 300) & (s < 310)] = 0.0
    assert sm.layer_runup(s, h2, 1.0) < 300
    assert sm.layer_runup(s, np.zeros_like(h), 1.0) is None


def test_water_layer_at_rest():
    """Still water y < 0 against the shore from the toe at depth H: the
    layer along the 45 deg normal at along-shore distance s is H sqrt 2 - s
    (0 at the shoreline), so the >= 1 m layer ends 1 m below the shoreline,
    i.e. at -1/sqrt 2 m height, within a bin (ds/sqrt 2 in height)."""
    H, h, sub, ds = 122.0, 3.0, 20, 5.0
    toe = np.array([1220.0, -H])
    sc = np.arange(0.7 - h, 400, h) + h / 2
    xc = np.arange(0, 60, h) + h / 2
    S, X = (a.ravel() for a in np.meshgrid(sc, xc))
    off = (np.arange(sub) + 0.5) / sub * h - h / 2
    os_, ox = (a.ravel() for a in np.meshgrid(off, off))
    y = -H + ((S[:, None] + os_) + (X[:, None] + ox)) / SQ2  # sub-points' heights
    alpha = (y < 0).mean(axis=1)
    C = toe + np.outer(S, [1, 1]) / SQ2 + np.outer(X, [-1, 1]) / SQ2
    s, lay = sm.shore_layer(C, alpha, np.full(len(S), h * h), toe, ds=ds, xi_max=60.0)
    top = sm.layer_runup(s, lay, 1.0) / SQ2 - H
    assert abs(top - (-1 / SQ2)) <= ds / SQ2, top


def test_centre_of_mass_impact():
    rng = np.random.default_rng(3)
    m = rng.uniform(1.0, 5.0, 50)
    t_dir = np.array([1.0, -1.0]) / SQ2
    x0 = np.column_stack([rng.uniform(-300, -200, 50), rng.uniform(200, 300, 50)])
    v0, a, dt = 5.0, 4.0, 0.05
    t = np.arange(0, 30, dt)
    travel = v0 * t + 0.5 * a * t**2
    yc = np.sum(m * x0[:, 1]) / m.sum() + travel * t_dir[1]
    speed = v0 + a * t  # every grain's, hence the centre of mass's
    t_i, v_i = sm.centre_of_mass_impact(t, yc, speed)
    d = np.sum(m * x0[:, 1]) / m.sum() * SQ2  # distance along the slope to y = 0
    t_star = (-v0 + math.sqrt(v0**2 + 2 * a * d)) / a
    assert t_i == pytest.approx(t_star, abs=a * dt**2 / (8 * v0))
    assert v_i == pytest.approx(v0 + a * t_star, rel=1e-4)
    assert math.isnan(sm.centre_of_mass_impact(t, yc + 1e4, speed)[1])


def test_flux_weighted_speed():
    m = np.array([2.0, 3.0, 5.0])
    v = np.array([40.0, 80.0, 110.0])
    y0 = np.array([300.0, 500.0, 700.0])
    w, dt = 20.0, 0.02
    t = np.arange(dt, 30, dt)
    y = y0[None, :] - v[None, :] * t[:, None]
    band = np.abs(y) <= w
    mdot = np.sum(band * m * v / (2 * w), axis=1)
    mdot_v = np.sum(band * m * v * v / (2 * w), axis=1)
    speed, crossed = sm.flux_weighted_speed(t, mdot, mdot_v)
    assert crossed == pytest.approx(m.sum(), rel=v.max() * dt / (2 * w))
    assert speed == pytest.approx(np.sum(m * v) / m.sum(), rel=v.max() * dt / (2 * w))


def test_froude_and_energy_budget():
    assert sm.froude(110.0, 122.0) == pytest.approx(3.18, abs=0.005)
    b = sm.energy_budget([0.0, 1.0, 3.0, 2.0], [0.0, 5.0, 8.0, 10.0])
    assert b["water_potential_energy_rise_max"] == 3.0
    assert b["slide_potential_energy_drop_then"] == 8.0
    assert b["water_to_slide_energy_ratio"] == pytest.approx(3 / 8)
    assert b["energy_bound_excess"] == pytest.approx(-0.0)
    assert sm.energy_budget([0.0, 6.0], [0.0, 5.0])["energy_bound_excess"] > 0


def test_atmosphere_outflow_across_a_signal_restart(tmp_path):
    flux, dt = 2.0, 0.1
    t = np.round(np.arange(1, 21) * dt, 12)  # the water-volume steps
    for start, rows in (("0", t[(t <= 1.0) & (np.abs(t - 1.0) > 1e-9)]), ("1", t[t > 1.0])):
        d = tmp_path / "postProcessing" / "atmosphereFlux" / start
        d.mkdir(parents=True)
        np.savetxt(
            d / "surfaceFieldValue.dat",
            np.c_[rows, np.full(len(rows), flux)],
            header="Time\tsum(alphaPhi0.water)",
        )
    out = post.atmosphere_outflow(str(tmp_path), t)
    assert len(out) == len(t)
    expected = flux * t
    expected[9] = flux * 0.9  # the stopped step's outflow counted with the next row
    np.testing.assert_allclose(out, expected, rtol=1e-12)
    # a run stopped by a signal at its end (2.1 s written, no flux row):
    # that step's outflow is unknown, every earlier one known
    known = post.outflow_known(str(tmp_path), np.append(t, 2.1))
    assert known[:-1].all() and not known[-1]


def test_thesis_packing(tmp_path, env):
    packing = str(tmp_path / "thesis_packing")
    setup.write_packing(packing, setup.MODES["thesis"]["grains"])
    run("blockMesh", packing, env)
    run("grainDeposit", packing, env)
    x, d, phi, thickness = setup.packed_block(packing)
    assert len(d) == 6015
    area = np.sum(math.pi / 4 * d**2)
    assert area == pytest.approx(98.5e6 / 2640, rel=1e-12)
    assert np.mean(d) / 2 == pytest.approx(1.35, rel=0.02)
    assert 0.75 < phi < 0.86, phi
    assert 40 < thickness < 60, thickness
    # distance of each centre from the slope x + y = 0 (normal (1, 1)/sqrt 2)
    assert np.all((x[:, 0] + x[:, 1]) / SQ2 >= d / 2), "a disc crosses the slope"
    # no overlaps: neighbours on a grid of side d_max
    cell = d.max()
    keys = np.floor(x / cell).astype(int)
    grid = {}
    for i, k in enumerate(map(tuple, keys)):
        grid.setdefault(k, []).append(i)
    worst = np.inf
    for i, (kx, ky) in enumerate(map(tuple, keys)):
        near = [j for a in (-1, 0, 1) for b in (-1, 0, 1) for j in grid.get((kx + a, ky + b), ())]
        near = np.array([j for j in near if j > i], dtype=int)
        if len(near):
            gap = np.linalg.norm(x[near] - x[i], axis=1) - 0.5 * (d[near] + d[i])
            worst = min(worst, gap.min())
    assert worst > 0, worst


def set_up_reduced(case, env, slide_speed):
    """setupCase.py CASE reduced with SLIDE_SPEED=slide_speed; the run."""
    script = os.path.join(os.path.dirname(setup.__file__), "setupCase.py")
    return subprocess.run(
        [sys.executable, script, case, "reduced"],
        env=env | {"SLIDE_SPEED": slide_speed},
        capture_output=True,
        text=True,
    )


def test_launched_slide_moves_down_the_slope(tmp_path, env):
    """SLIDE_SPEED=110 (Fritz et al.'s mean impact speed): setupCase.py
    writes grainDepositDict `initialVelocity` of magnitude 110 m/s along the
    left shore (orthogonal to its normal (1, 1)/sqrt 2, pointing down) and
    records the launch speed; a bad value stops it before anything is
    written."""
    case = str(tmp_path / "reduced")
    p = set_up_reduced(case, env, "110")
    assert p.returncode == 0, p.stderr
    text = open(os.path.join(case, "system", "grainDepositDict")).read()
    v = np.array(
        [float(c) for c in re.search(r"initialVelocity \((\S+) (\S+) (\S+)\)", text).groups()]
    )
    assert np.linalg.norm(v) == pytest.approx(110, rel=1e-9)
    assert abs(v[0] + v[1]) / SQ2 < 1e-6 and v[1] < 0
    assert json.load(open(os.path.join(case, "caseParameters.json")))["slide_launch_speed"] == 110
    bad = str(tmp_path / "bad")
    p = set_up_reduced(bad, env, "-5")
    assert p.returncode != 0 and "SLIDE_SPEED" in p.stderr and not os.path.exists(bad)
