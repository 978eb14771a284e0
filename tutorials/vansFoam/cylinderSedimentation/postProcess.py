#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Falling cylinder post-processing: results.json and velocity.png.

usage: postProcess.py CASEDIR      (postProcess.py --selftest: check the frequency extraction)

From the grain written at every write time (lagrangian/grains, U):
- streamwise_velocity(t) = -U_y [m/s] (positive downwards), lateral_velocity(t)
  = U_x [m/s];
- plateau_velocity: the mean over the steadiest 0.8 s (plateau_velocity());
- terminal_velocity: the time average of the streamwise velocity over the
  last 40 % of the run (several shedding periods), compared with
  U_t = 2.501 cm/s of Namkoong et al. (2008) quoted in thesis 3.3.3 (Re = 156);
- shedding_frequency [Hz]: the frequency of the lateral velocity oscillation
  (shedding_analysis): over the developed part of the run (from the first
  time |U_x| reaches 20 % of its maximum, the wake instability having grown
  from the seed), the lateral velocity minus its moving average over the
  reference period is cut at its zero crossings; f = (number of half
  periods / 2) / (time between the first and the last crossing), reported
  with the number of periods used (at least 2, else 0: a drift, no
  oscillation).  Cross-checks: the FFT peak of the same signal (Hann window)
  and the streamwise velocity, which oscillates at 2 f.
  Reference: no Strouhal number of the freely falling cylinder of Namkoong,
  Yoo & Choi (2008) could be verified (their Fig. of u_lat(t) is what the
  thesis Fig. 3.19 compares with); the fallback is the fixed, unbounded
  cylinder at the same Re = U_t D/nu = 156: Williamson's parallel-shedding
  fit St = 0.2175 - 5.1064/Re = 0.1848 (Williamson 1996, Annu. Rev. Fluid
  Mech. 28:477) and Williamson & Brown (1998, J. Fluids Struct. 12:1073)
  St = 0.2665 - 1.018/sqrt(Re) = 0.1850, i.e. f = St U_t/D = 0.925 Hz.  The
  walls (W/D = 8) and the freedom of the cylinder shift it by some percent.
"""

import json
import os
import sys

import nscdpost
import nscdrender
import numpy as np

here = os.path.dirname(os.path.abspath(__file__))

setupCase = nscdpost.load_module(
    "cylinderSedimentation_setupCase", os.path.join(here, "setupCase.py")
)


def grain_history(case):
    """(t [s], x [N, nt, 3] m, U [N, nt, 3] m/s) of all grains at the write times."""
    t, x, u = [], [], []
    for time, name in nscdpost.time_dirs(case):
        g = nscdpost.read_grains(case, name)
        t.append(time)
        x.append(g["x"])
        u.append(g["U"])
    return np.array(t), np.transpose(np.array(x), (1, 0, 2)), np.transpose(np.array(u), (1, 0, 2))


def strouhal_reference(re):
    """Williamson (1996) fit St(Re) = 0.2175 - 5.1064/Re of the parallel
    laminar shedding regime (49 < Re < 178) of an unbounded fixed cylinder."""
    return 0.2175 - 5.1064 / re


def strouhal_williamson_brown(re):
    """Williamson & Brown (1998, J. Fluids Struct. 12:1073) fit
    St(Re) = 0.2665 - 1.018/sqrt(Re), unbounded fixed cylinder."""
    return 0.2665 - 1.018 / np.sqrt(re)


def _zero_crossings(t, a, hysteresis=0.25):
    """Interpolated times [s] where the sampled signal a(t) changes sign, with
    a Schmitt trigger: a crossing counts once a has gone beyond
    +-hysteresis * max|a| on the other side (noise near zero is ignored)."""
    eps = hysteresis * float(np.max(np.abs(a)))
    out, state, last = [], 0, None
    for i in range(a.size):
        if i > 0 and np.signbit(a[i]) != np.signbit(a[i - 1]):
            last = t[i - 1] - a[i - 1] * (t[i] - t[i - 1]) / (a[i] - a[i - 1])
        side = 1 if a[i] > eps else (-1 if a[i] < -eps else 0)
        if side and side != state:
            if state and last is not None:
                out.append(last)
            state = side
    return np.array(out)


def _fft_peak(t, a):
    """Frequency [Hz] of the largest spectral peak of a(t) (uniform resampling,
    Hann window, zero padding x8, DC excluded); 0 for < 8 samples."""
    if t.size < 8:
        return 0.0
    n = t.size
    tu = np.linspace(t[0], t[-1], n)
    au = np.interp(tu, t, a)
    au = (au - au.mean()) * np.hanning(n)
    m = 8 * n
    spec = np.abs(np.fft.rfft(au, m))
    fr = np.fft.rfftfreq(m, tu[1] - tu[0])
    k = 1 + int(np.argmax(spec[1:]))
    return float(fr[k])


def shedding_analysis(t, ulat, ustr, f_guess, onset=0.2, hysteresis=0.25):
    """Shedding frequency of a falling cylinder from its lateral velocity.

    t [nt] s, ulat, ustr [nt] m/s (lateral, streamwise velocity at the write
    times); f_guess [Hz]: the expected frequency, only used for the length of
    the moving average removed from ulat (one period 1/f_guess: it removes a
    slow drift, not the oscillation).  The analysed window starts at the first
    time |ulat| >= onset * max|ulat| (the developed instability).
    Returns a dict: shedding_frequency [Hz] (zero crossings; 0 when fewer than
    two full periods are found), periods (number of periods used),
    window_start, window_end [s], crossings [s], fft_frequency [Hz] of ulat,
    streamwise_fft_frequency_half [Hz] (FFT peak of ustr / 2: the drag
    oscillates at twice the shedding frequency), oscillation_amplitude [m/s]
    (half the peak-to-peak of the analysed signal).  A crossing counts once
    the signal has gone beyond +-hysteresis * max|signal| (sampling noise and
    the residual of a smooth drift are not oscillations).
    """
    out = {
        "shedding_frequency": 0.0,
        "periods": 0.0,
        "window_start": None,
        "window_end": float(t[-1]),
        "crossings": [],
        "fft_frequency": 0.0,
        "streamwise_fft_frequency_half": 0.0,
        "oscillation_amplitude": 0.0,
    }
    amax = np.max(np.abs(ulat))
    if amax <= 0 or t.size < 8:
        return out
    i0 = int(np.nonzero(np.abs(ulat) >= onset * amax)[0][0])
    ts, ul, us = t[i0:], ulat[i0:], ustr[i0:]
    out["window_start"] = float(ts[0])
    if ts.size < 8:
        return out
    dt = float(np.median(np.diff(ts)))
    w = max(1, int(round(1.0 / (f_guess * dt))))
    if w + 8 > ts.size:  # shorter than one period + 8 samples: linear trend
        a = ul - np.polyval(np.polyfit(ts, ul, 1), ts)
    else:  # centred moving average over one period, full windows only
        ma = np.convolve(ul, np.ones(w) / w, mode="valid")
        k0 = (w - 1) // 2
        ts, ul, us = ts[k0 : k0 + ma.size], ul[k0 : k0 + ma.size], us[k0 : k0 + ma.size]
        a = ul - ma
    out["oscillation_amplitude"] = float(0.5 * (a.max() - a.min()))
    out["window_start"], out["window_end"] = float(ts[0]), float(ts[-1])
    tc = _zero_crossings(ts, a, hysteresis)
    out["crossings"] = tc.tolist()
    if tc.size >= 5:  # at least two full periods
        out["periods"] = 0.5 * (tc.size - 1)
        out["shedding_frequency"] = float(out["periods"] / (tc[-1] - tc[0]))
    out["fft_frequency"] = _fft_peak(ts, a)
    out["streamwise_fft_frequency_half"] = 0.5 * _fft_peak(ts, us - np.mean(us))
    return out


def measure(t, ustr, ulat, window=0.4):
    """Terminal velocity [m/s] (mean of ustr over the last `window` fraction
    of t) and shedding frequency [Hz] of ulat over that window (zero
    crossings of the detrended signal; 0 when it does not oscillate)."""
    sel = t >= t[0] + (1 - window) * (t[-1] - t[0])
    ts, us, ul = t[sel], ustr[sel], ulat[sel]
    ut = float(np.mean(us))
    f = 0.0
    if ts.size > 4:
        a = ul - np.polyval(np.polyfit(ts, ul, 1), ts)
        s = np.signbit(a)
        idx = np.nonzero(s[1:] != s[:-1])[0]
        if idx.size >= 5:  # at least two full periods, else a drift
            # interpolated crossing times; half a period between crossings
            tc = ts[idx] - a[idx] * (ts[idx + 1] - ts[idx]) / (a[idx + 1] - a[idx])
            f = float(0.5 * (idx.size - 1) / (tc[-1] - tc[0]))
    return ut, f


def selftest():
    """Check shedding_analysis on synthetic signals sampled like the tutorial
    (every 0.05 s, 8 s): a 0.9 Hz oscillation growing from t = 1 s to 3 s on a
    slow drift plus noise must give 0.9 Hz within 2 % with >= 3 periods; a
    monotone drift (the 15 c/D, 3 s run of 2026-11-21) must give 0."""
    t = np.arange(0.0, 8.0 + 1e-9, 0.05)
    rng = np.random.default_rng(1)
    grow = np.clip((t - 1.0) / 2.0, 0.0, 1.0)
    for drift in (0.001, 0.01):
        ul = (
            0.004 * np.sin(2 * np.pi * 0.9 * t) * grow
            + drift * t / 8
            + 1e-5 * rng.standard_normal(t.size)
        )
        us = 0.025 + 0.001 * np.sin(2 * np.pi * 1.8 * t) * grow
        r = shedding_analysis(t, ul, us, 0.925)
        assert abs(r["shedding_frequency"] / 0.9 - 1) < 0.02 and r["periods"] >= 3, r
    ul = 0.009 * np.tanh(np.maximum(t - 1.0, 0.0))
    r = shedding_analysis(t, ul, 0.025 + 0 * t, 0.925)
    assert r["shedding_frequency"] == 0.0, r
    print("shedding_analysis selftest passed")


def plateau_velocity(t, ustr, width=0.8, after=0.5):
    """Mean streamwise velocity [m/s] over the `width`-s window (starting
    after `after` s) where it varies least (smallest standard deviation),
    and the window start [s]: the terminal velocity of a run whose end is
    spoiled (e.g. the drift to a wall); (0, None) if the run is too short."""
    best = (np.inf, 0.0, None)
    for i in np.nonzero(t >= after)[0]:
        sel = (t >= t[i]) & (t <= t[i] + width + 1e-9)
        if t[i] + width > t[-1] + 1e-9 or sel.sum() < 3:
            break
        sd = float(np.std(ustr[sel]))
        if sd < best[0]:
            best = (sd, float(np.mean(ustr[sel])), float(t[i]))
    return best[1], best[2]


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--selftest":
        return selftest()
    case = sys.argv[1] if len(sys.argv) > 1 else "case"
    t, x, u = grain_history(case)
    ustr, ulat = -u[0, :, 1], u[0, :, 0]
    ut, _ = measure(t, ustr, ulat)
    ref = setupCase.UT_REF
    re = ut * setupCase.D / setupCase.NU
    re_ref = ref * setupCase.D / setupCase.NU
    st_ref = float(strouhal_reference(re_ref))
    f_ref = st_ref * ref / setupCase.D
    sh = shedding_analysis(t, ulat, ustr, f_ref)
    f = sh["shedding_frequency"]
    nx, _, walls, _ = setupCase.mesh_layout(case)
    res = {
        "time": t.tolist(),
        "streamwise_velocity": ustr.tolist(),
        "lateral_velocity": ulat.tolist(),
        "x": x[0, :, 0].tolist(),
        "y": x[0, :, 1].tolist(),
        "cells_per_diameter": setupCase.D / (setupCase.WIDTH / nx),
        "walls_from_axis_in_D": walls / setupCase.D,
        "rotation_coupling": "rotationCoupling yes"
        in open(os.path.join(case, "constant", "couplingProperties")).read(),
        "scheme": (
            "resolved"
            if "resolvedCellsPerDiameter"
            in open(os.path.join(case, "constant", "couplingProperties")).read()
            else "default"
        ),
        "terminal_velocity": ut,
        "max_streamwise_velocity": float(ustr.max()),
        "terminal_velocity_reference": ref,
        "terminal_velocity_error": (ut - ref) / ref,
        "plateau_velocity": plateau_velocity(t, ustr)[0],
        "plateau_window_start": plateau_velocity(t, ustr)[1],
        "reynolds_number": re,
        "shedding_frequency": f,
        "shedding_periods_used": sh["periods"],
        "shedding_window": [sh["window_start"], sh["window_end"]],
        "shedding_frequency_fft": sh["fft_frequency"],
        "shedding_lateral_amplitude": sh["oscillation_amplitude"],
        "shedding_frequency_from_streamwise_fft": sh["streamwise_fft_frequency_half"],
        "strouhal_number": f * setupCase.D / ut if ut > 0 else 0.0,
        "strouhal_reference_williamson1996": st_ref,
        "strouhal_reference_williamson_brown1998": float(strouhal_williamson_brown(re_ref)),
        "shedding_frequency_reference": f_ref,
        "shedding_frequency_reference_source": "fixed unbounded cylinder at Re = 156, St = 0.2175 - 5.1064/Re (Williamson 1996), "
        "f = St U_t/D; no verified value of Namkoong et al. (2008) for the free cylinder",
    }
    if os.path.exists("shedding.json"):  # fixedShedding.py post: the fixed-cylinder companion
        fixed = json.load(open("shedding.json"))
        res.update({k: v for k, v in fixed.items() if not isinstance(v, list)})
    nscdpost.write_json("results.json", res)
    print(
        f"terminal velocity {100 * ut:.4f} cm/s (reference {100 * ref:.4f} cm/s, "
        f"{100 * (ut - ref) / ref:+.1f} %), Re = {re:.1f}"
    )
    print(
        f"shedding frequency {f:.3f} Hz over {sh['periods']:.1f} periods from "
        f"t = {sh['window_start']} s (FFT {sh['fft_frequency']:.3f} Hz, streamwise/2 "
        f"{sh['streamwise_fft_frequency_half']:.3f} Hz), St = {res['strouhal_number']:.3f}; "
        f"reference St {st_ref:.3f}, f {f_ref:.3f} Hz"
    )
    plt = nscdrender.pyplot("velocity.png")
    if plt is not None:
        fig, ax = plt.subplots(figsize=(7, 4))
        ax.plot(t, ustr / ref, "C0-", label=r"$u_{str}/U_t$ (vansFoam)")
        ax.plot(t, ulat / ref, "C3-", label=r"$u_{lat}/U_t$ (vansFoam)")
        ax.axhline(1.0, color="C0", ls="--", label="$U_t$ = 2.501 cm/s (Namkoong et al. 2008)")
        ax.axhline(0.0, color="k", lw=0.5)
        if sh["window_start"] is not None:
            ax.axvspan(
                sh["window_start"],
                sh["window_end"],
                color="0.9",
                zorder=0,
                label="shedding analysis window",
            )
            # reference oscillation: the period 1/f_ref drawn from the first crossing
            if sh["crossings"]:
                t0 = sh["crossings"][0]
                tr = np.linspace(t0, t[-1], 400)
                amp = np.max(np.abs(ulat[t >= sh["window_start"]])) / ref
                ax.plot(
                    tr,
                    amp * np.sin(2 * np.pi * f_ref * (tr - t0)) * np.sign(ulat[-1] or 1),
                    "C3:",
                    lw=0.8,
                    label=f"period of St = {st_ref:.3f} (Williamson 1996), {f_ref:.3f} Hz",
                )
        ax.set_title(
            f"D/h = {res['cells_per_diameter']:.3g}: "
            + (
                f"f = {f:.3f} Hz ({sh['periods']:.1f} periods)"
                if f > 0
                else "no lateral oscillation (< 2 periods)"
            )
            + f", reference {f_ref:.3f} Hz"
            + (
                f"; fixed cylinder {res['fixed_cylinder_shedding_frequency']:.3f} Hz"
                if "fixed_cylinder_shedding_frequency" in res
                else ""
            ),
            fontsize=9,
        )
        nscdrender.save_plot(fig, ax, "velocity.png", "t [s]", "velocity / $U_t$", legend_size=7)


if __name__ == "__main__":
    main()
