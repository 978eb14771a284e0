#!/usr/bin/env python3
"""Falling cylinder post-processing: results.json and velocity.png.

usage: postProcess.py CASEDIR

From the grain written at every write time (lagrangian/grains, U):
- streamwise_velocity(t) = -U_y [m/s] (positive downwards), lateral_velocity(t)
  = U_x [m/s];
- terminal_velocity: the time average of the streamwise velocity over the
  last 40 % of the run (several shedding periods), compared with
  U_t = 2.501 cm/s of Namkoong et al. (2008) quoted in thesis 3.3.3 (Re = 156);
- shedding_frequency [Hz]: the frequency of the lateral velocity oscillation
  over the same window (mean removed, linear trend removed, zero crossings
  of the detrended signal; the oscillation of the streamwise velocity has
  twice this frequency).  Reference: Strouhal number St = f D / U_t; for a
  cylinder at Re = 156 St ~ 0.18-0.19 (Williamson 1996, Annu. Rev. Fluid
  Mech. 28:477, eq. St = 0.2175 - 5.1064/Re -> 0.185 at Re = 156).
"""
import os
import sys

import numpy as np

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
sys.path.insert(0, os.path.join(os.environ.get("NSCD_PROJECT_DIR", os.path.join(here, "../../..")), "src", "python"))
import nscdpost  # noqa: E402
import importlib.util  # noqa: E402

_spec = importlib.util.spec_from_file_location("cylinderSedimentation_setupCase",
                                               os.path.join(here, "setupCase.py"))
setupCase = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(setupCase)


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
    laminar shedding regime (49 < Re < 178) of an unbounded cylinder."""
    return 0.2175 - 5.1064 / re


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
        if idx.size >= 5:           # at least two full periods, else a drift
            # interpolated crossing times; half a period between crossings
            tc = ts[idx] - a[idx] * (ts[idx + 1] - ts[idx]) / (a[idx + 1] - a[idx])
            f = float(0.5 * (idx.size - 1) / (tc[-1] - tc[0]))
    return ut, f


def main():
    case = sys.argv[1] if len(sys.argv) > 1 else "case"
    t, x, u = grain_history(case)
    ustr, ulat = -u[0, :, 1], u[0, :, 0]
    ut, f = measure(t, ustr, ulat)
    ref = setupCase.UT_REF
    re = ut * setupCase.D / setupCase.NU
    res = {
        "time": t.tolist(),
        "streamwise_velocity": ustr.tolist(),
        "lateral_velocity": ulat.tolist(),
        "x": x[0, :, 0].tolist(),
        "y": x[0, :, 1].tolist(),
        "terminal_velocity": ut,
        "max_streamwise_velocity": float(ustr.max()),
        "terminal_velocity_reference": ref,
        "terminal_velocity_error": (ut - ref) / ref,
        "reynolds_number": re,
        "shedding_frequency": f,
        "strouhal_number": f * setupCase.D / ut if ut > 0 else 0.0,
        "strouhal_reference_williamson1996": strouhal_reference(ref * setupCase.D / setupCase.NU),
    }
    nscdpost.write_json("results.json", res)
    print(f"terminal velocity {100 * ut:.4f} cm/s (reference {100 * ref:.4f} cm/s, "
          f"{100 * (ut - ref) / ref:+.1f} %), Re = {re:.1f}, shedding frequency {f:.3f} Hz, "
          f"St = {res['strouhal_number']:.3f} (Williamson {res['strouhal_reference_williamson1996']:.3f})")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(t, ustr / ref, "C0-", label=r"$u_{str}/U_t$ (vansFoam)")
        ax.plot(t, ulat / ref, "C3-", label=r"$u_{lat}/U_t$ (vansFoam)")
        ax.axhline(1.0, color="C0", ls="--", label="$U_t$ = 2.501 cm/s (Namkoong et al. 2008)")
        ax.axhline(0.0, color="k", lw=0.5)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("velocity / $U_t$")
        ax.legend(fontsize=8)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig("velocity.png", dpi=120)
    except ImportError:
        print("matplotlib missing: no velocity.png")


if __name__ == "__main__":
    main()
