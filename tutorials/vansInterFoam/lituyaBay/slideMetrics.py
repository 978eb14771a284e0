# SPDX-License-Identifier: GPL-3.0-or-later
"""Impact, run-up and energy measures of the lituyaBay slide (thesis section
5.3), as plain functions of arrays so that tests can feed them synthetic
data with known answers; postProcess.py applies them to a run.

- Impact speed three ways: the front (postProcess.front_froude, the 10 %
  lowest grains), the mass-flux-weighted speed of the grains crossing the
  still-water level (`flux_weighted_speed`, from the per-step massFlux and
  speedMassFlux of the grainCentreOfMass function object), and the speed of
  the slide's centre of mass as it crosses the still-water level y = 0
  (`centre_of_mass_impact`, per step).  Fritz et al. (2001) quote the
  slide's mean speed at impact, 110 m/s: the frictionless drop of the centre
  of mass, sqrt(2 g 605 m) = 109 m/s.
- Froude number at impact (thesis 3.18): F = v_s / sqrt(g h), h the bay
  depth at the impact site (H = 122 m).
- Run-up as a water layer (`shore_layer`, `layer_runup`): the thickness of
  water normal to the right shore, int alpha dxi along the inward normal,
  averaged over bins of the along-shore coordinate; the run-up is the
  highest shore point reached by an unbroken layer at least 1 m thick from
  the shore's toe up.
- Energy: the water's potential-energy rise must not exceed the slide's
  potential-energy drop (`energy_budget`).
"""

import math

import numpy as np

G = 9.81


def froude(v, h):
    """Froude number at impact F = v / sqrt(g h) (thesis 5.3.1: 110 m/s in
    h = 122 m gives 3.18)."""
    return float(v / math.sqrt(G * h))


def centre_of_mass_impact(t, yc, speed, level=0.0):
    """(t_i, v_i): the first downward crossing of level by the centre-of-mass
    height yc(t) and the centre-of-mass speed there, both interpolated
    linearly between the two samples that bracket it; (nan, nan) if yc never
    goes below level."""
    t, yc, speed = (np.asarray(a, float) for a in (t, yc, speed))
    below = np.nonzero(yc <= level)[0]
    if len(below) == 0:
        return float("nan"), float("nan")
    i = below[0]
    if i == 0:
        return float(t[0]), float(speed[0])
    f = (yc[i - 1] - level) / (yc[i - 1] - yc[i])
    return float(t[i - 1] + f * (t[i] - t[i - 1])), float(
        speed[i - 1] + f * (speed[i] - speed[i - 1])
    )


def flux_weighted_speed(t, mdot, mdot_speed):
    """(v, m): the mass-flux-weighted speed int mdot|v| dt / int mdot dt of the
    grains crossing the flux plane and the crossed mass int mdot dt, from
    the per-step band sums of grainCentreOfMass (rectangle rule with the
    step's dt, the values at the end of each step)."""
    t = np.asarray(t, float)
    dt = np.diff(np.concatenate([[0.0], t]))
    m = float(np.sum(np.asarray(mdot) * dt))
    mv = float(np.sum(np.asarray(mdot_speed) * dt))
    return (mv / m if m > 0 else float("nan")), m


def shore_layer(C, alpha, V, toe, depth=1.0, ds=5.0, xi_max=200.0):
    """(s, h): the water layer on a 45 deg shore rising to the right from
    toe = (x, y): for bins of width ds of the along-shore distance s from the
    toe, h = sum alpha V f / (ds depth) over the cells whose centre lies
    within xi_max of the shore along its inward normal (-1, 1)/sqrt 2, f the
    share of the cell in the bin (the cell spread evenly over its extent
    e = sqrt(V/depth) along s: binning the centres alone aliases the bins
    with the cell rows by +-15 %); i.e. int_0^xi_max alpha dxi along the
    normal, averaged over the bin.  s are the bin centres."""
    C = np.asarray(C, float)
    rel = C[:, :2] - np.asarray(toe, float)
    s = (rel[:, 0] + rel[:, 1]) / math.sqrt(2)
    xi = (rel[:, 1] - rel[:, 0]) / math.sqrt(2)
    keep = (xi >= 0) & (xi <= xi_max)
    s, V = s[keep], np.asarray(V, float)[keep]
    water = np.clip(np.asarray(alpha, float)[keep], 0, 1) * V
    e = np.sqrt(V / depth)
    a, b = s - e / 2, s + e / 2
    nbin = max(1, int(math.ceil(b.max() / ds))) if len(b) else 1
    h = np.zeros(nbin)
    k0 = np.floor(a / ds).astype(int)
    for j in range(int(math.ceil(e.max() / ds)) + 1 if len(e) else 0):
        k = k0 + j
        share = np.clip(np.minimum(b, (k + 1) * ds) - np.maximum(a, k * ds), 0, None) / e
        ok = (k >= 0) & (k < nbin) & (share > 0)
        h += np.bincount(k[ok], weights=water[ok] * share[ok], minlength=nbin)
    return (np.arange(nbin) + 0.5) * ds, h / (ds * depth)


def layer_runup(s, h, min_thickness=1.0):
    """Highest along-shore distance s (bin centre) reached by an unbroken
    layer h >= min_thickness from the toe up (below the still-water line the
    bay's water makes the layer); None if the toe's bin is dry.  At rest it
    is within a bin of the still-water shoreline (the layer's thickness along
    the 45 deg normal at distance u below the shoreline is u)."""
    wet = np.asarray(h) >= min_thickness
    if len(wet) == 0 or not wet[0]:
        return None
    n = len(wet) if wet.all() else int(np.argmin(wet))
    return float(np.asarray(s)[n - 1])


def energy_budget(water_rise, slide_drop):
    """The water's potential-energy rise dE_w(t) against the slide's drop
    dE_s(t) [J per metre], sampled at the same times: the maximum rise, the
    slide's drop at that time and at the end, and the largest excess
    max_t (dE_w - dE_s) / dE_s(end) (<= 0: the bound holds)."""
    w, s = np.asarray(water_rise, float), np.asarray(slide_drop, float)
    i = int(np.argmax(w))
    return {
        "water_potential_energy_rise_max": float(w[i]),
        "slide_potential_energy_drop_then": float(s[i]),
        "slide_potential_energy_drop_end": float(s[-1]),
        "water_to_slide_energy_ratio": float(w[i] / s[i]) if s[i] > 0 else float("nan"),
        "energy_bound_excess": float(np.max(w - s) / s[-1]) if s[-1] > 0 else float("nan"),
    }
