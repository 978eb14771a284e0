#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark: grid convergence of the drag on a fixed disc between plane walls
in Stokes flow, vansFoam resolved regime (thesis 3.2.2, 3.3.3).

The case is the one of tests/cases/test_resolvedRegime.py
(`fixed_disc_drag`: disc D = 0.01 m centred in a channel H = 0.05 m,
k = D/H = 0.2, L = 0.12 m, uniform inflow U0 = 1e-3 m/s, walls moving at U0,
nu = 1e-3 m^2/s, Re = U0 D/nu = 0.01, t_end = 0.12 s, dt = 5 h^2/nu), reused
by importing that module (no copy).  Reference: Faxen (1946) drag of a
cylinder midway between plane walls (Happel & Brenner 1965; Ben Richou,
Ambari & Naciri 2004, Chem. Eng. Sci. 59:3215, eq. 1), `faxen_drag(0.2)` =
16.53 (F per unit length / (mu U0)).

The drag of a penalised (volume-fraction) disc depends on where the disc sits
inside a cell: at a fixed D/h it swings by ~2 % with the sub-cell position
(measured, see the test's docstring).  For each D/h this script therefore
averages F over N_OFF sub-cell offsets of the disc centre, along the cell
diagonal: (s h, s' h), s = 0, 1/4, 1/2, 3/4 and s' = s wrapped to [-1/2, 1/2)
(0.75 h in y is grid-equivalent to -0.25 h but keeps the disc within h/2 of
the channel axis; the drag changes by O((e/H)^2) < 1e-4 with an eccentricity
e <= h/2).  The offset is applied by shifting the grain list that
fixed_disc_drag hands to setupCase.write_case (the mesh is unchanged).

Outputs tests/bench/results/faxenConvergence.json:
  cells_per_diameter, drag per offset, mean, spread (max - min) / mean,
  error |F - F_Faxen| / F_Faxen of the mean, observed order of the error
  (least squares of log err vs log h) and of the successive differences
  (Richardson: fit F(h) = F_inf + C h^p over all levels, p and F_inf), and
  wall time; plus tests/bench/faxenConvergence/faxenConvergence.png.
Thesis (3.3.3) reports about h^1.65 for its terminal-velocity study.

usage: tests/bench/faxenConvergence/faxenConvergence.py [D/h ...] [--offsets N] [--end T]
       (default D/h = 8 12 16 24 32, 4 offsets, end 0.12 s; about 11 min on
       one loaded core of the 2-vCPU VM).  Assumes ./Allwmake has run.
       t_end = 0.12 s is steady: D/h = 8 centred gives 16.6686 at 0.12 s and
       16.6613 at 0.48 s (-0.04 %, measured 2026-11-21).
"""

import argparse
import json
import math
import os
import pathlib
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "cases"))

import conftest  # noqa: E402  (paths + foam_env)
import nscdpost  # noqa: E402
import nscdrender  # noqa: E402
import test_resolvedRegime as trr  # noqa: E402


class _ShiftedSetup:
    """Proxy of the cylinderSedimentation setupCase module whose write_case
    shifts every grain centre by (dx, dy) [m]; everything else delegated."""

    def __init__(self, mod, dx, dy):
        self._mod, self._dx, self._dy = mod, dx, dy

    def __getattr__(self, name):
        return getattr(self._mod, name)

    def write_case(self, case, lo, hi, cells, grains, *args, **kw):
        grains = [(x + self._dx, y + self._dy, d) for x, y, d in grains]
        return self._mod.write_case(case, lo, hi, cells, grains, *args, **kw)


def offsets(n):
    """n sub-cell offsets (fractions of h) along the cell diagonal."""
    out = []
    for i in range(n):
        s = i / n
        out.append((s, s - 1.0 if s >= 0.5 + 1e-12 else s))
    return out


def disc_drag(workdir, env, cpd, sx, sy, end, D=0.01, tries=2):
    """F/(mu U0) of fixed_disc_drag with the disc centre moved by (sx, sy) h.
    A failed run is retried once in a fresh directory (applications rebuilt
    by others while a run is in flight crash at exit, see the preamble)."""
    h = D / cpd
    orig = trr.setupCase
    trr.setupCase = _ShiftedSetup(orig, sx * h, sy * h)
    try:
        for k in range(tries):
            d = pathlib.Path(workdir) / f"c{cpd:g}_{sx:.3f}_{sy:.3f}_try{k}"
            d.mkdir(parents=True, exist_ok=True)
            try:
                return trr.fixed_disc_drag(d, env, cpd, end=end)
            except AssertionError as e:
                if k + 1 == tries:
                    raise
                print(f"run failed, retrying: {str(e).splitlines()[0]}", flush=True)
    finally:
        trr.setupCase = orig


def fit_power(h, y):
    """Least-squares slope p of log y = log C + p log h."""
    p, logc = np.polyfit(np.log(h), np.log(y), 1)
    return float(p), float(math.exp(logc))


def fit_richardson(h, f):
    """Fit F(h) = F_inf + C h^p (all levels, least squares; p by a 1-D scan
    over [0.2, 4], nscdpost.power_law_fit).  Returns (p, F_inf, C, rms)."""
    return nscdpost.power_law_fit(h, f, np.linspace(0.2, 4.0, 3801))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("cpd", nargs="*", type=float, default=[8, 12, 16, 24, 32])
    ap.add_argument("--offsets", type=int, default=4)
    ap.add_argument("--end", type=float, default=0.12)
    ap.add_argument(
        "--out", default=os.path.join(ROOT, "tests", "bench", "results", "faxenConvergence.json")
    )
    a = ap.parse_args()
    env = conftest.foam_env()
    ref = trr.faxen_drag(0.2)
    D = 0.01
    levels = []
    t0 = time.time()
    with tempfile.TemporaryDirectory() as work:
        for cpd in a.cpd:
            vals = []
            t1 = time.time()
            for sx, sy in offsets(a.offsets):
                v = disc_drag(work, env, cpd, sx, sy, a.end)
                vals.append(v)
                print(
                    f"D/h = {cpd:g}, offset ({sx:+.2f}, {sy:+.2f}) h: F/(mu U) = {v:.4f}",
                    flush=True,
                )
            m = float(np.mean(vals))
            levels.append(
                {
                    "cells_per_diameter": cpd,
                    "h": D / cpd,
                    "offsets_h": offsets(a.offsets),
                    "drag": vals,
                    "mean": m,
                    "spread": float((max(vals) - min(vals)) / m),
                    "error_vs_faxen": abs(m - ref) / ref,
                    "wall_seconds": time.time() - t1,
                }
            )
            print(
                f"D/h = {cpd:g}: mean {m:.4f} (Faxen {ref:.4f}, {100 * (m - ref) / ref:+.2f} %), "
                f"spread {100 * levels[-1]['spread']:.2f} %",
                flush=True,
            )
    h = np.array([lv["h"] for lv in levels])
    f = np.array([lv["mean"] for lv in levels])
    err = np.abs(f - ref)
    p_err, _ = fit_power(h, err) if np.all(err > 0) else (float("nan"), 0.0)
    diffs = np.abs(np.diff(f))
    hm = np.sqrt(h[:-1] * h[1:])
    p_diff = fit_power(hm, diffs)[0] if len(diffs) >= 2 and np.all(diffs > 0) else float("nan")
    p_r, f_inf, c_r, rms = fit_richardson(h, f) if len(f) >= 3 else (float("nan"),) * 4
    res = {
        "benchmark": "faxenConvergence",
        "case": "tests/cases/test_resolvedRegime.py fixed_disc_drag (k = D/H = 0.2, Re = 0.01, "
        f"t_end = {a.end} s), disc centre averaged over {a.offsets} sub-cell offsets",
        "reference": "Faxen (1946), Happel & Brenner (1965); Ben Richou et al. (2004) eq. 1: "
        "F/(mu U) = 4 pi / (-ln k - 0.9157 + 1.7244 k^2 - 1.7302 k^4 + 2.4056 k^6 "
        "- 4.5913 k^8)",
        "faxen_drag": ref,
        "levels": levels,
        "observed_order_error_vs_faxen": p_err,
        "observed_order_successive_differences": p_diff,
        "richardson_fit": {
            "order": p_r,
            "F_inf": f_inf,
            "C": c_r,
            "rms": rms,
            "F_inf_vs_faxen": (f_inf - ref) / ref if f_inf == f_inf else None,
        },
        "thesis_order": 1.65,
        "wall_seconds_total": time.time() - t0,
    }
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as fo:
        json.dump(res, fo, indent=2, sort_keys=True)
        fo.write("\n")
    print(
        f"observed order: |F - F_Faxen| ~ h^{p_err:.2f}, successive differences ~ h^{p_diff:.2f}, "
        f"Richardson fit p = {p_r:.2f}, F_inf = {f_inf:.4f} ({100 * (f_inf - ref) / ref:+.2f} % "
        f"vs Faxen)\n-> {a.out}"
    )
    plt = nscdrender.pyplot("png")
    if plt is not None:
        fig, ax = plt.subplots(1, 2, figsize=(9, 3.8))
        for lv in levels:
            ax[0].plot([lv["cells_per_diameter"]] * len(lv["drag"]), lv["drag"], "C0.", alpha=0.5)
        ax[0].plot(a.cpd, f, "C0o-", label=f"vansFoam, mean of {a.offsets} offsets")
        ax[0].axhline(ref, color="k", ls="--", label=f"Faxen (1946) {ref:.2f}")
        if f_inf == f_inf:
            ax[0].axhline(f_inf, color="C3", ls=":", label=f"Richardson $F_\\infty$ = {f_inf:.2f}")
        ax[0].set_xlabel("D/h")
        ax[0].set_ylabel(r"$F/(\mu U)$")
        ax[0].legend(fontsize=8)
        ax[1].loglog(a.cpd, err / ref, "C0o-", label=f"|F - F_Faxen|/F_Faxen, p = {p_err:.2f}")
        if len(diffs):
            ax[1].loglog(
                D / hm, diffs / ref, "C2s-", label=f"successive differences, p = {p_diff:.2f}"
            )
        x = np.array(a.cpd)
        ax[1].loglog(x, (err[0] / ref) * (x / x[0]) ** -1.65, "k:", label="slope -1.65 (thesis)")
        ax[1].set_xlabel("D/h")
        ax[1].legend(fontsize=7)
        for axx in ax:
            axx.grid(alpha=0.3, which="both")
        fig.suptitle("Fixed disc between walls, k = 0.2, Re = 0.01 (vansFoam resolved regime)")
        fig.tight_layout()
        fig.savefig(os.path.join(HERE, "faxenConvergence.png"), dpi=120)


if __name__ == "__main__":
    main()
