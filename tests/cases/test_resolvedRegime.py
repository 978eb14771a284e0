"""vansFoam in the resolved regime (issue 7, thesis sections 3.2.2, 3.3.3):
grains spanning many cells, eps -> epsMin inside them, the semi-implicit drag
(eq. 3.46-3.50) acting as a Brinkman volume penalisation.

- Fixed disc between two plane walls in Stokes flow (Re = 0.01), frame of the
  disc: uniform inflow U0, walls moving at U0.  Reference: Faxen (1946) for a
  cylinder translating midway between two parallel plane walls (quoted in
  Happel & Brenner 1965, and eq. 1 of Ben Richou, Ambari & Naciri 2004,
  Chem. Eng. Sci. 59:3215):
      F/(mu U0) = 4 pi / (-ln k - 0.9157 + 1.7244 k^2 - 1.7302 k^4
                          + 2.4056 k^6 - 4.5913 k^8),   k = D/H,
  here k = 0.2 (same confinement as the reference), F the drag per unit
  length = the grain's `Ffluid` (the integral of the coupling force over
  the grain's cells).  Within 10 % at D/h = 10, 14, 20, and the change
  between successive refinements shrinks (measured 19:40 UTC on 2026-11-21:
  F/F_Faxen = 0.986, 1.010, 1.0155 -> observed order ~4 from these three
  levels, not asymptotic: the result oscillates by ~2 % with the alignment of
  the disc on the grid, D/h = 5, 7 give 1.003, 0.978).
- Disc released from rest in still fluid: initial acceleration
  a0 = (rho_p - rho_f) g / (rho_p + C_A rho_f), C_A = 1 the added-mass
  coefficient of a circular cylinder (potential flow; Batchelor 1967,
  section 6.4; the walls W = 8 D away raise it by < 5 %), within 10 %.
  KNOWN FAILURE (xfail, strict): vansFoam gives a0 ~ (rho_p - rho_f) g/rho_p,
  no added mass (measured 0.098 m/s^2 against 0.049 m/s^2 at D/h = 10,
  dt = 1e-3 s), and a0 depends on dt and h: D/h = 10: 0.062 (dt 2e-4),
  0.128 (dt 5e-3); D/h = 15: 0.080, D/h = 20: 0.137 (dt 1e-3).  Values
  above (rho_p - rho_f) g/rho_p = 0.097 m/s^2 are impossible for a body
  released from rest (the fluid can only resist).
- Falling cylinder (thesis 3.3.3, Namkoong et al. 2008): terminal velocity
  within 5 % of U_t = 2.501 cm/s (Re = 156) on a reduced copy of the
  tutorial (see test docstring); the full tutorial (D/h = 15, maxDeltaT
  1e-3 s) gives 2.494 cm/s on its plateau (1.3-2.0 s).
"""
import math
import os

import numpy as np
import pytest

import nscdpost
from foamcase import run, tutorial_modules

setupCase, postProcess = tutorial_modules("vansFoam", "cylinderSedimentation")


def faxen_drag(k):
    """Faxen (1946) drag per unit length / (mu U) of a cylinder of diameter
    D translating midway between plane walls H apart, k = D/H < 0.5, Stokes
    flow (Happel & Brenner 1965; Ben Richou et al. 2004 eq. 1)."""
    return 4 * math.pi / (-math.log(k) - 0.9157 + 1.7244 * k**2 - 1.7302 * k**4
                          + 2.4056 * k**6 - 4.5913 * k**8)


def fixed_disc_drag(tmp_path, env, cells_per_d, D=0.01, H=0.05, L=0.12, U0=1e-3,
                    nu=1e-3, rho=1000.0, end=0.12):
    """Drag per unit length [N/m] on a fixed disc of diameter D centred in a
    channel H wide, L long (uniform inflow U0, walls moving at U0).  Steady
    after ~0.1 s (diffusion time (H/2)^2/nu = 0.6 s, but the flow starts
    uniform).  The time step is ~h^2: vansFoam with a fixed penalised disc
    goes unstable for nu dt/h^2 >~ 20 (measured), here nu dt/h^2 = 5."""
    h = D / cells_per_d
    case = str(tmp_path / f"disc{cells_per_d}")
    dt = 5 * h * h / nu
    setupCase.write_case(case, (-L / 2, -H / 2), (L / 2, H / 2), (round(L / h), round(H / h)),
                         [(0.0, 0.0, D)], 2 * rho, rho, nu, gravity=(0, 0, 0), end_time=end,
                         write_interval=end / 2, max_co=100, max_dt=dt, fixed=True, inflow=U0)
    for app in ("blockMesh", "grainDeposit", "vansFoam"):
        run(app, case, env)
    t, name = nscdpost.time_dirs(case)[-1]
    assert abs(t - end) < 1e-9
    F = nscdpost.read_vector_field(os.path.join(case, name, "lagrangian", "grains", "Ffluid"))
    return F[0, 0] / (rho * nu * U0)


def test_fixed_disc_between_walls_faxen(tmp_path, env):
    ref = faxen_drag(0.2)                       # 16.53
    lam = [fixed_disc_drag(tmp_path, env, c) for c in (10, 14, 20)]
    print("F/(mu U) =", lam, "Faxen", ref)
    for v in lam:
        assert abs(v / ref - 1) < 0.10, (lam, ref)
    d1, d2 = abs(lam[1] - lam[0]), abs(lam[2] - lam[1])
    assert d2 < d1, (lam, "refinement does not converge")
    print("observed order (three levels, ratio sqrt 2):", math.log(d1 / d2) / math.log(math.sqrt(2)))


@pytest.mark.xfail(strict=True, reason="vansFoam resolved regime lacks the added mass: a0 = "
                   "(rho_p - rho_f) g/rho_p measured (issue 7 report of engineer D)")
def test_released_disc_added_mass(tmp_path, env):
    """Disc (D = 5 mm, rho_p/rho_f = 1.01, water-like nu = 8e-7) released
    from rest at the centre of a 0.04 x 0.08 m box, D/h = 10, dt = 1e-3 s:
    mean acceleration over the first 0.02 s (the Basset history force is
    O(sqrt(nu t)/D) ~ 3 % of the added-mass force there)."""
    case = str(tmp_path / "released")
    setupCase.cylinder_case(case, end_time=0.02, cells_per_d=10, height=0.08,
                            write_interval=0.02, max_dt=1e-3, y0=0.0)
    for app in ("blockMesh", "grainDeposit", "vansFoam"):
        run(app, case, env)
    t, x, u = postProcess.grain_history(case)
    a = -u[0, -1, 1] / t[-1]
    ref = (setupCase.RHO_S - setupCase.RHO_F) * 9.81 / (setupCase.RHO_S + setupCase.RHO_F)
    print(f"initial acceleration {a:.4f} m/s^2, added-mass reference {ref:.4f}, "
          f"without added mass {(setupCase.RHO_S - setupCase.RHO_F) * 9.81 / setupCase.RHO_S:.4f}")
    assert abs(a / ref - 1) < 0.10, (a, ref)


def test_falling_cylinder_terminal_velocity(tmp_path, env):
    """Reduced copy of tutorials/vansFoam/cylinderSedimentation: the same
    fluid, cylinder and box width (confinement W/D = 8 as in the tutorial),
    box 0.12 m high instead of 0.32 m (the cylinder falls ~4.5 cm in 2 s: the
    length the tutorial needs to reach U_t is what matters, the bottom stays
    > 9 D away), D/h = 8 instead of 15, maxDeltaT 2e-3 s.  Terminal velocity
    = mean streamwise velocity over the last 40 % of 2 s (postProcess.measure,
    t >= 1.2 s: the full tutorial is on its plateau from 1.3 s to 2.0 s, before
    the lateral drift of the wake instability), within 5 % of U_t = 2.501 cm/s
    (Namkoong et al. 2008, thesis 3.3.3).  Measured: 2.595 cm/s (+3.8 %);
    the same case at maxDeltaT 5e-3 s, 3 s: 2.86 cm/s (+14 %): the resolved
    light grain is time-step sensitive (see the added-mass test)."""
    case = str(tmp_path / "cyl")
    setupCase.cylinder_case(case, end_time=2.0, cells_per_d=8, height=0.12, write_interval=0.05,
                            max_dt=2e-3)
    for app in ("blockMesh", "grainDeposit", "vansFoam"):
        run(app, case, env)
    t, x, u = postProcess.grain_history(case)
    ut, f = postProcess.measure(t, -u[0, :, 1], u[0, :, 0])
    print(f"terminal velocity {ut:.5f} m/s, reference {setupCase.UT_REF}, shedding {f:.3f} Hz")
    assert x[0, -1, 1] > -0.06 + 2 * setupCase.D       # still clear of the bottom
    assert abs(ut / setupCase.UT_REF - 1) < 0.05, ut


def test_dkt_kissing(tmp_path, env):
    """Drafting-kissing-tumbling, reduced copy of
    tutorials/vansFoam/draftingKissingTumbling: D/h = 6 instead of 12.5 and
    the box cut to y in [2, 8] cm (at D/h = 6 on the full box the pair
    touches at y ~ 4.1-4.3 cm, t = 1.8 s, measured), run to 1.75 s.
    Asserts that the trailing disc catches up (kissing: gap < h) and not
    before t = 0.3 s, a kinematic bound: the trailing disc must gain 0.2 cm
    (one diameter) on the leading one; if it fell without drag or added mass
    ((rho_p - rho_f) g/rho_p = 9.7 cm/s^2) and the leading one at half that
    rate, the gap would close only after sqrt(4 x 0.2 cm / 9.7 cm/s^2) =
    0.29 s.  vansFoam at maxDeltaT 4e-3 s kicked the pair together at
    0.21 s (measured at D/h = 6), this test catches that.  The comparison
    with a published kissing time (within 20 %) is NOT made: no verified
    number (see the issue 7 report); at D/h = 6 on the full box, maxDeltaT
    1e-3 s, kissing (gap < h) at 1.55 s, contact at 1.80 s (measured)."""
    dkt, dktPost = tutorial_modules("vansFoam", "draftingKissingTumbling")
    case = str(tmp_path / "dkt")
    h = dkt.D / 6
    dkt.cyl.write_case(case, (0.0, 0.02), (dkt.W, dkt.H), (round(dkt.W / h), round(0.06 / h)),
                       [(x, y, dkt.D) for x, y in dkt.START], dkt.RHO_P, dkt.RHO_F, dkt.NU,
                       end_time=1.75, write_interval=0.05, max_co=0.5, max_dt=1e-3)
    for app in ("blockMesh", "grainDeposit", "vansFoam"):
        run(app, case, env)
    t, x, u = postProcess.grain_history(case)
    kiss, tumble, gap = dktPost.dkt_measure(t, x, dkt.D, h)
    print(f"DKT (D/h = 6): kissing at {kiss} s, tumbling at {tumble} s, min gap {gap.min():.2e} m")
    assert kiss is not None, gap
    assert kiss > 0.3, kiss
