#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Vortex shedding of the penalised cylinder held fixed in the frame of the
falling cylinder (companion of the falling-cylinder tutorial).

The free falling cylinder of this tutorial (thesis 3.3.3) drifts to a wall
instead of oscillating about the axis (see the note in results.json and
the README), so its lateral velocity gives no shedding frequency.
This case measures the shedding frequency of the same resolved (volume
penalised) cylinder with the lateral motion suppressed: the frame of a
cylinder falling at U_t = 2.501 cm/s between fixed walls 8 D apart, i.e. a
fixed disc (grainDeposit `fixed yes`) in a uniform inflow U_t with the walls
moving at U_t (setupCase.write_case `inflow`), Re = U_t D/nu = 156, same
fluid, D and width as the tutorial (or WIDTH_IN_D diameters wide, e.g. 24 for
the walls 12 D from the axis of the falling runs away from the thesis box);
8 D upstream, 24 D downstream.  The disc
is put D/50 off the axis to seed the wake instability.

The lift (y component of the grain's `Ffluid`, the integral of the coupling
force over its cells, written every 0.05 s) is analysed by
postProcess.shedding_analysis (zero crossings over the developed part, number
of periods, FFT cross-check; the drag oscillates at twice the frequency).
Reference: the fixed unbounded cylinder at Re = 156, St = 0.2175 - 5.1064/Re =
0.185 (Williamson 1996) and St = 0.2665 - 1.018/sqrt(Re) = 0.185 (Williamson &
Brown 1998); the blockage D/W = 1/8 raises St by some percent. The mean drag
coefficient over the last lift period (developed shedding; the analysis
window still holds the growth of the shedding) is set beside the
two-dimensional computations of Henderson (1995, Phys. Fluids 7, 2102) in the periodic regime,
1.350 at Re = 100 and 1.341 at Re = 200 (docs/validation/resolvedGrains.md).

usage: fixedShedding.py setup CASEDIR [CELLS_PER_D [ENDTIME [WIDTH_IN_D]]]
       (default 15, 8 s, the tutorial's width 8 D)
       fixedShedding.py post CASEDIR      -> shedding.json, shedding.png (cwd)
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
post = nscdpost.load_module(
    "cylinderSedimentation_postProcess", os.path.join(here, "postProcess.py")
)

UPSTREAM, DOWNSTREAM = 8, 24  # [D]
SEED = 1.0 / 50  # [D] lateral offset of the disc


def setup(case, cells_per_d=15.0, end_time=8.0, width_in_d=None):
    """Write the fixed-cylinder case, width_in_d diameters wide (None: the
    tutorial's width); returns the number of cells."""
    D = setupCase.D
    W = setupCase.WIDTH if width_in_d is None else width_in_d * D
    h = D / cells_per_d
    lo, hi = (-UPSTREAM * D, -W / 2), (DOWNSTREAM * D, W / 2)
    cells = (round((hi[0] - lo[0]) / h), round(W / h))
    setupCase.write_case(
        case,
        lo,
        hi,
        cells,
        [(0.0, SEED * D, D)],
        setupCase.RHO_S,
        setupCase.RHO_F,
        setupCase.NU,
        gravity=(0, 0, 0),
        end_time=end_time,
        write_interval=0.05,
        max_co=0.5,
        max_dt=2e-3,
        fixed=True,
        inflow=setupCase.UT_REF,
    )
    return cells[0] * cells[1]


def analyse(case):
    """Shedding frequency of the lift on the fixed disc: dict for shedding.json."""
    t, F = [], []
    for time, name in nscdpost.time_dirs(case):
        path = os.path.join(case, name, "lagrangian", "grains", "Ffluid")
        if time > 0 and os.path.isfile(path):
            t.append(time)
            F.append(nscdpost.read_vector_field(path)[0])
    if not t:
        decomposed = os.path.isdir(os.path.join(case, "processor0"))
        sys.exit(
            f"fixedShedding.py post: no write time of {case} holds the grains' "
            "lagrangian/grains/Ffluid"
            + (
                "; a decomposed run writes them in processor*/: run "
                f"`reconstructPar -case {case} -fields '(none)'` first"
                if decomposed
                else "; run the case (vansFoam) past its first write times"
            )
        )
    t, F = np.array(t), np.array(F)
    U, D, nu = setupCase.UT_REF, setupCase.D, setupCase.NU
    re = U * D / nu
    st_ref = float(post.strouhal_reference(re))
    sh = post.shedding_analysis(t, F[:, 1], F[:, 0], st_ref * U / D)
    f = sh["shedding_frequency"]
    rhoU2D = 0.5 * setupCase.RHO_F * U * U * D
    sel = t >= (sh["window_start"] if sh["window_start"] is not None else t[-1])
    # one block, nx along the flow; the y extent is the distance of the walls
    nx, ncells, _, width = setupCase.mesh_layout(case)
    ny = ncells // nx
    # the last full lift period: the last three of the analysis' crossings
    tc = sh["crossings"]
    last = (t >= tc[-3]) & (t <= tc[-1]) if len(tc) >= 3 else np.zeros(len(t), bool)
    cd_last = float(np.mean(F[last, 0]) / rhoU2D) if last.any() else None
    return (
        t,
        F,
        sh,
        {
            "fixed_cylinder_reynolds_number": re,
            "fixed_cylinder_cells_per_diameter": D / (width / ny),
            "fixed_cylinder_width_in_diameters": width / D,
            "fixed_cylinder_shedding_frequency": f,
            "fixed_cylinder_shedding_periods_used": sh["periods"],
            "fixed_cylinder_shedding_window": [sh["window_start"], sh["window_end"]],
            "fixed_cylinder_shedding_frequency_fft": sh["fft_frequency"],
            "fixed_cylinder_drag_fft_frequency_half": sh["streamwise_fft_frequency_half"],
            "fixed_cylinder_strouhal_number": f * D / U,
            "fixed_cylinder_mean_drag_coefficient": float(np.mean(F[sel, 0]) / rhoU2D),
            "fixed_cylinder_drag_coefficient_last_period": cd_last,
            "fixed_cylinder_lift_coefficient_amplitude": sh["oscillation_amplitude"] / rhoU2D,
            "strouhal_reference_williamson1996": st_ref,
            "strouhal_reference_williamson_brown1998": float(post.strouhal_williamson_brown(re)),
        },
    )


def main():
    if len(sys.argv) < 3 or sys.argv[1] not in ("setup", "post"):
        sys.exit(__doc__)
    case = sys.argv[2]
    if sys.argv[1] == "setup":
        cpd = float(sys.argv[3]) if len(sys.argv) > 3 else 15.0
        end = float(sys.argv[4]) if len(sys.argv) > 4 else 8.0
        wid = float(sys.argv[5]) if len(sys.argv) > 5 else None
        n = setup(case, cpd, end, wid)
        print(f"{case}: fixed cylinder, {n} cells, D/h = {cpd:g}, endTime {end:g} s")
        return
    t, F, sh, res = analyse(case)
    with open("shedding.json", "w") as fo:
        json.dump(
            dict(res, time=t.tolist(), lift=F[:, 1].tolist(), drag=F[:, 0].tolist()),
            fo,
            indent=2,
            sort_keys=True,
        )
        fo.write("\n")
    st, sr = res["fixed_cylinder_strouhal_number"], res["strouhal_reference_williamson1996"]
    if sh["periods"] == 0:
        print(
            f"fixed cylinder: no developed shedding by t = {t[-1]:g} s (fewer than two full lift "
            f"periods past the onset; lift amplitude {res['fixed_cylinder_lift_coefficient_amplitude']:.3g} "
            "C_L): run longer (fixedShedding.py setup ... ENDTIME); a finer mesh seeds the "
            "instability less and sheds later"
        )
    print(
        f"fixed cylinder Re = {res['fixed_cylinder_reynolds_number']:.1f}: shedding "
        f"{res['fixed_cylinder_shedding_frequency']:.4f} Hz over {sh['periods']:.1f} periods "
        f"(FFT {sh['fft_frequency']:.4f} Hz, drag/2 {sh['streamwise_fft_frequency_half']:.4f} Hz), "
        f"St = {st:.4f} vs {sr:.4f} (Williamson 1996) ({100 * (st - sr) / sr:+.1f} %), "
        f"C_D = {res['fixed_cylinder_mean_drag_coefficient']:.3f}"
    )
    plt = nscdrender.pyplot("shedding.png")
    if plt is not None:
        rhoU2D = 0.5 * setupCase.RHO_F * setupCase.UT_REF**2 * setupCase.D
        fig, ax = plt.subplots(figsize=(7, 3.6))
        ax.plot(t, F[:, 1] / rhoU2D, "C3", label="$C_L$ (lift of the penalised disc)")
        ax.plot(t, F[:, 0] / rhoU2D, "C0", label="$C_D$")
        if sh["window_start"] is not None:
            ax.axvspan(
                sh["window_start"], sh["window_end"], color="0.9", zorder=0, label="analysis window"
            )
        ax.set_title(
            f"fixed cylinder, Re = 156, D/h = {res['fixed_cylinder_cells_per_diameter']:.3g}: "
            f"St = {st:.3f} ({sh['periods']:.1f} periods); Williamson (1996) {sr:.3f}",
            fontsize=9,
        )
        nscdrender.save_plot(fig, ax, "shedding.png", "t [s]", legend_size=7)


if __name__ == "__main__":
    main()
