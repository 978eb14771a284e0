#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Drafting-kissing-tumbling of two discs (thesis section 3.3.4; Feng, Hu &
Joseph 1994, J. Fluid Mech. 261:95; Glowinski, Pan, Hesla, Joseph & Periaux
2001, J. Comput. Phys. 169:363): channel 2 x 8 cm, fluid rho = 1 g/cm^3,
eta = 0.01 g/(cm s), discs rho_p = 1.01 g/cm^3, D = 0.2 cm, released from
rest with centres at y = 7.2 cm and 6.8 cm.  The upper disc is put slightly
off the centre line (x = 0.999 cm against 1 cm), the perturbation Glowinski
et al. (2001) used to break the symmetry; without it the pair would fall
kissing along the axis.  SI units in the case.

usage: setupCase.py CASEDIR [ENDTIME] [CELLS_PER_D] [ROTATION yes|no] [MAXDT] [SCHEME] [OFFSET]
  (default 4 s, D/h = 12.5 as in thesis 3.3.4: 125 x 500 cells, rotation no,
  maxDeltaT 1e-3 s, SCHEME resolved, OFFSET 1e-5 m: the upper disc's
  distance [m] to the -x side of the centre line.)
  SCHEME resolved: couplingProperties `resolvedCellsPerDiameter 4;`, the
  resolved-regime scheme of vansCloud.H (grain velocity out of the pressure
  solve, added mass C_A = 1); SCHEME default: no keyword (the unresolved
  scheme for every grain).  Measured at D/h = 12.5: with the
  default scheme the pair is unstable at maxDeltaT 1e-3 and 5e-4 s from the
  start, and at 2.5e-4 s it blows up when the gap closes to ~3 h (t = 1.147
  s: max grain Reynolds number 0.018 -> 50 within 0.03 s), with or without
  rotation coupling; a single disc too is unstable at 1e-3 s.  That is the
  instability of a partitioned coupling whose added mass is wrong (twice C_A
  = 1 for one disc, tests/cases/test_resolvedRegime.py) and grows as the
  gap to another grain or a wall closes, for these light grains
  (rho_p/rho_f = 1.01).  With SCHEME resolved the same restart from
  t = 1.14 s stays smooth, and the whole run is stable at 1e-3 s.
"""

import os
import sys

import nscdpost

here = os.path.dirname(os.path.abspath(__file__))


# write_case() of the falling-cylinder tutorial
cyl = nscdpost.load_module(
    "cylinderSedimentation_setupCase",
    os.path.join(here, "..", "cylinderSedimentation", "setupCase.py"),
)

W, H = 0.02, 0.08  # [m]
D = 0.002  # [m]
RHO_F, RHO_P = 1000.0, 1010.0
NU = 1e-6  # [m^2/s] = 0.01 g/(cm s) / 1 g/cm^3
OFFSET = 1e-5  # [m] the upper disc's offset to -x (Glowinski et al. 2001)
START = [(0.010 - OFFSET, 0.072), (0.010, 0.068)]  # [m] upper (1), lower (2)


def dkt_case(
    case,
    end_time=4.0,
    cells_per_d=12.5,
    write_interval=0.01,
    rotation=False,
    max_dt=1e-3,
    resolved=False,
    offset=OFFSET,
):
    """Write the DKT case (see the module docstring); resolved: add
    `resolvedCellsPerDiameter 4;` to constant/couplingProperties; offset [m]:
    the upper disc's distance to the -x side of the centre line (> 0).
    Returns the number of cells."""
    if not offset > 0:
        raise ValueError(f"setupCase.py: the offset must be > 0 m, not {offset!r}")
    h = D / cells_per_d
    nx, ny = round(W / h), round(H / h)
    cyl.write_case(
        case,
        (0.0, 0.0),
        (W, H),
        (nx, ny),
        [(0.010 - offset, START[0][1], D), (*START[1], D)],
        RHO_P,
        RHO_F,
        NU,
        end_time=end_time,
        write_interval=write_interval,
        max_co=0.5,
        max_dt=max_dt,
        rotation=rotation,
    )
    if resolved:
        cyl.opt_in_resolved(case)
    return nx * ny


def main():
    case = sys.argv[1]
    end = float(sys.argv[2]) if len(sys.argv) > 2 else 4.0
    cpd = float(sys.argv[3]) if len(sys.argv) > 3 else 12.5
    rot = len(sys.argv) > 4 and sys.argv[4] in ("yes", "on", "true", "1")
    max_dt = float(sys.argv[5]) if len(sys.argv) > 5 else 1e-3
    scheme = sys.argv[6] if len(sys.argv) > 6 else "resolved"
    offset = float(sys.argv[7]) if len(sys.argv) > 7 else OFFSET
    if scheme not in ("resolved", "default"):
        sys.exit(f"setupCase.py: SCHEME must be resolved or default, not {scheme!r}")
    if not offset > 0:
        sys.exit(f"setupCase.py: OFFSET (7th argument) must be > 0 m, not {offset!r}")
    n = dkt_case(
        case, end, cpd, rotation=rot, max_dt=max_dt, resolved=scheme == "resolved", offset=offset
    )
    print(
        f"{case}: {n} cells, D/h = {cpd:g}, endTime {end:g} s, rotationCoupling {rot}, "
        f"maxDeltaT {max_dt:g} s, scheme {scheme}, offset {offset:g} m"
    )


if __name__ == "__main__":
    main()
