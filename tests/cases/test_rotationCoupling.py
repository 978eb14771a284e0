# SPDX-License-Identifier: GPL-3.0-or-later
"""vansFoam rotation coupling (couplingProperties rotationCoupling yes;
issue 7, resolved regime): the Brinkman penalisation of the semi-implicit
drag imposes v_p + omega_p x (x_c - x_p) in the cells a grain covers, and
the fluid torque T_p = sum_c (x_c - x_p) x f_pc of the same
overlap-distributed force is handed to NSCD as an external torque.

- A fixed disc (R = 5 mm, 16 cells per diameter) spinning at omega in a
  quiescent viscous fluid at Re = omega R d/nu = 0.005, 2D, in a square box
  of side L = 5 d: the steady torque per unit length against the Stokes
  rotlet T = -4 pi mu R^2 omega (Lamb 1932, art. 334; unbounded) corrected
  for a concentric circular wall of radius R_b, T = -4 pi mu omega R^2
  R_b^2/(R_b^2 - R^2) (Couette flow between cylinders), with R_b between
  the inscribed (L/2) and circumscribed (L/sqrt 2) radii of the box (the
  correction is 1.4-2.9 %); tolerance 10 % (diffuse interface: the
  penalised region's effective radius is R +- dx/2, i.e. +-6 % on R^2).
  The azimuthal fluid velocity at r = 1.06 R (first fluid cell), 1.5 R
  and 2 R (cell centres on the axes) against omega R^2/r, bounded by the
  same two Couette profiles, within 10 %.  Needs the SIMPLEC pressure
  coefficient rAtU that vansFoam uses when a fixed grain is resolved
  (pEqn.H, vansCloud.H "Resolved grains"); with 1/A the pressure inside
  the fixed penalised disc was undetermined (|p| 1.4e5 Pa) and drove a
  rim jet (2.0 x Couette at 1.06 R, 0.14 x at 2.06 R).
- A free disc, rho_s/rho_f = 1.01, 16 cells per diameter, released
  spinning in a closed box without gravity: at every step the drag
  angular-momentum rate lost by the fluid (from the fields K, K v**_0, K_p
  and U, about the origin) equals that gained by the grain (x_p x F_p + T_p)
  to round-off (1e-9 relative): Newton's third law for the torque; the spin
  decays monotonically over the first 0.04 s and the disc stays at rest
  (stable with the resolved solid flux of vansCloud, couplingProperties
  resolvedCellsPerDiameter 4, set for every case of this module; see
  vansCloud.H; without it the free disc diverged after 0.04 s).
- A free neutrally buoyant resolved disc in a simple shear G spins at
  G/2 (Stokes, Jeffery 1922) within 5 %, with the rigid interior of
  resolved free grains switched on (rigidViscosityRatio 1000: off by
  default with rotationCoupling, vansCloud.H "Resolved grains") and a
  Krylov U solver (written by setupCase.write_case): the penalty's
  transpose part lets the rigid region spin.  The other cases here run
  without the penalty.
- Angular momentum of grain + fluid (conservation law): a free disc
  released spinning in fluid at rest in a box 6 d wide; before the
  disturbance reaches the walls the total I omega + rho_f sum eps (r x U) V
  about the disc centre must stay at its initial value.  Without the
  rigid interior it does (0.9975, 0.988 at 0.01, 0.02 s); with it
  (rigidViscosityRatio 1000 and rotationCoupling) it does not: strict
  xfail (0.003, vansCloud.H "Resolved grains", rigid interior limit).
"""

import math
import os
import re

import nscdpost
import numpy as np
import pytest
from foamcase import add_fluid, make_box_case, run, tutorial_modules

pytestmark = pytest.mark.fast

(setupCase,) = tutorial_modules("vansFoam", "cylinderSedimentation", names=("setupCase",))


def set_angular_velocity(case, omega_z, time="0"):
    """Overwrite the z angular velocity [rad/s] of every grain in
    <case>/<time>/grainState.h5 in place (h5py; the FoamFile user block is
    left as it is)."""
    import h5py

    path = os.path.join(case, time, "grainState.h5")
    with h5py.File(path, "r+") as f:
        ds = f["/angularVelocities"]
        w = ds[()]
        w[:, 2] = omega_z
        ds[...] = w
    assert np.all(nscdpost.read_h5(path, "/angularVelocities")[:, 2] == omega_z)


def disc_case(
    case, env, rho_s, fixed, omega, end, dt, L, d, cells, nu, write_interval=None, eps_min=None
):
    make_box_case(
        case,
        (0, 0, 0),
        (L, L, L / cells),
        (cells, cells, 1),
        (0, 0, 0),
        {"disc": {"density": rho_s, "friction": 0.3}},
        grains=[(L / 2, L / 2, 0, d)],
        end_time=end,
        dt=dt,
        write_interval=write_interval or end,
    )
    if fixed:
        open(os.path.join(case, "system", "grainDepositDict"), "a").write("fixed yes;\n")
    add_fluid(
        case,
        1000.0,
        nu,
        max_dt=dt,
        max_co=0.5,
        n_correctors=2,
        extra_coupling="rotationCoupling yes;\nresolvedCellsPerDiameter 4;\n",
    )
    if eps_min is not None:
        cp = os.path.join(case, "constant", "couplingProperties")
        txt = open(cp).read()
        assert "epsMin 1e-8;" in txt
        open(cp, "w").write(txt.replace("epsMin 1e-8;", f"epsMin {eps_min};"))
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    set_angular_velocity(case, omega)


def couette_torque(mu, omega, R, Rb):
    return -4 * math.pi * mu * omega * R**2 * Rb**2 / (Rb**2 - R**2)


def couette_u(omega, R, Rb, r):
    return omega * R**2 / (Rb**2 - R**2) * (Rb**2 / r - r)


def spinning_disc(tmp_path, env):
    """The fixed spinning disc case, run once per session directory."""
    R, omega, mu = 0.005, 1.0, 10.0
    d = 2 * R
    L, cells = 5 * d, 80  # 16 cells per diameter
    case = str(tmp_path / "spin")
    # viscous time (L/2)^2/nu = 0.0625 s: steady after 0.4 s
    disc_case(case, env, 1010.0, True, omega, end=0.4, dt=0.05, L=L, d=d, cells=cells, nu=mu / 1000)
    p = run("vansFoam", case, env)
    return case, p.stdout, R, omega, mu, L, cells


@pytest.fixture(scope="module")
def spin(tmp_path_factory, env):
    return spinning_disc(tmp_path_factory.mktemp("rotation"), env)


def test_spinning_fixed_disc_torque(spin):
    case, out, R, omega, mu, L, cells = spin
    assert "rotation coupling on" in out
    assert "mean grain Reynolds number" in out
    # steady after the viscous time (L/2)^2/nu = 0.0625 s: the last two
    # steps agree to 1e-3 (measured 3e-5); last step measured -3.237e-3
    # N m/m, inside the Couette bounds (-3.206e-3, -3.272e-3).  (Before the
    # rAtU of resolved fixed grains, pEqn.H: 208 Courant-limited steps,
    # +-15 % step-to-step noise, mean -3.36e-3, +3 to +5 % of Couette.)
    tq = list(nscdpost.read_step_data(case, "rotationCoupling")["maxFluidTorque"])
    assert len(tq) >= 8  # dt 0.05 s to 0.4 s
    assert tq[-1] == pytest.approx(tq[-2], rel=1e-3), tq[-5:]
    T = -tq[-1]
    Tlast = nscdpost.read_vector_field(
        os.path.join(case, "0.4", "lagrangian", "grains", "torqueFluid")
    )[0][2]
    assert Tlast < 0 and abs(Tlast) == pytest.approx(tq[-1], rel=1e-12)
    # 2D: the torque is per unit depth, as the analytical one per unit length
    lo = couette_torque(mu, omega, R, L / 2)
    hi = couette_torque(mu, omega, R, L / math.sqrt(2))
    print("torque", T, "Couette", lo, hi, "rotlet", -4 * math.pi * mu * R**2 * omega)
    assert min(lo, hi) * 1.10 <= T <= max(lo, hi) * 0.90, (T, lo, hi)


def test_spinning_fixed_disc_velocity(spin):
    """Azimuthal velocity against the Couette profiles (concentric wall
    between L/2 and L/sqrt 2), 10 %.  Measured u/u_Couette(L/2),
    u/u_Couette(L/sqrt 2): r = 1.06 R 0.974, 0.971; 1.56 R 1.037, 1.005;
    2.06 R 1.055, 0.977.  Failed with 1/A in pEqn (before fixedResolved():
    2.02 at 1.06 R, 0.14 at 2.06 R, the rim jet of the undetermined
    pressure inside the disc)."""
    case, out, R, omega, mu, L, cells = spin
    # azimuthal velocity on the x axis through the centre, r ~ 1.06 R, 1.5 R, 2 R
    U = nscdpost.read_vector_field(os.path.join(case, "0.4", "U"))
    dx = L / cells
    j = cells // 2  # rows j - 1, j straddle the axis
    for r in (1.06 * R, 1.5 * R, 2 * R):
        i = int((L / 2 + r) / dx)
        uy = 0.5 * (U[j * cells + i][1] + U[(j - 1) * cells + i][1])
        rc = math.hypot((i + 0.5) * dx - L / 2, 0.5 * dx)
        uy *= rc / ((i + 0.5) * dx - L / 2)  # azimuthal component
        ua, ub = couette_u(omega, R, L / 2, rc), couette_u(omega, R, L / math.sqrt(2), rc)
        print("r/R", rc / R, "u", uy, "Couette", ua, ub, "rotlet", omega * R**2 / rc)
        assert min(ua, ub) * 0.90 <= uy <= max(ua, ub) * 1.10, (rc, uy, ua, ub)


@pytest.fixture(scope="module")
def spin_down(tmp_path_factory, env):
    """A free disc, rho_s/rho_f = 1.01, released spinning at 2 rad/s."""
    R, omega = 0.005, 2.0
    d = 2 * R
    L, cells = 3 * d, 48  # 16 cells per diameter
    case = str(tmp_path_factory.mktemp("spinDown") / "spinDown")
    # spin-down time I/(4 pi mu R^2) = rho_s R^2/(8 mu) = 3 ms ~ dt: stiff
    disc_case(
        case,
        env,
        1010.0,
        False,
        omega,
        end=0.05,
        dt=0.02,
        L=L,
        d=d,
        cells=cells,
        nu=1e-3,
        write_interval=0.01,
    )
    p = run("vansFoam", case, env)
    return case, p.stdout, omega


def test_free_disc_newton_third_law(spin_down):
    """At every step the drag angular-momentum rate lost by the fluid equals
    that gained by the grain, to round-off (1e-9 of the largest)."""
    case, out, omega = spin_down
    r = nscdpost.read_step_data(case, "rotationCoupling")
    lost, gained = r["fluidAngularMomentumRate"], r["grainAngularMomentumRate"]
    # 5 steps to 0.05 s (dt 0.02 s, shortened to hit the write times)
    assert len(lost) == len(gained) >= 4
    scale = max(abs(v) for v in lost)
    assert scale > 0
    for a, b in zip(lost, gained):
        assert abs(a - b) <= 1e-9 * scale, (a, b)


def grain_series(case, name, n):
    return [
        nscdpost.read_vector_field(
            os.path.join(case, f"{0.01 * k:g}", "lagrangian", "grains", name)
        )[0]
        for k in range(1, n + 1)
    ]


def test_free_disc_spin_down_decays(spin_down):
    """The first 0.04 s: the spin decays monotonically, never changes sign
    (measured 2 -> 0.44 -> 0.15 -> 0.068 -> 0.035 rad/s)."""
    case, out, omega = spin_down
    w = [omega] + [v[2] for v in grain_series(case, "omega", 4)]
    print("omega", w)
    assert all(0 < b < a for a, b in zip(w, w[1:])), w


def test_free_disc_stable(spin_down):
    """The free spinning disc stays (nearly) at rest: |v| < 1 % of the rim
    speed omega R over 0.05 s, and the spin never grows.  Failed before the
    resolved solid flux and the balanced grain weight of vansCloud (the
    translation blew up between 0.03 and 0.05 s, |v| 1e-3 -> 0.17 -> 1.8e2
    m/s, from the undetermined pressure inside the disc)."""
    case, out, omega = spin_down
    v = grain_series(case, "U", 5)
    w = [x[2] for x in grain_series(case, "omega", 5)]
    assert max(np.linalg.norm(x) for x in v) < 0.01 * omega * 0.005, v
    assert all(abs(x) < omega for x in w), w


def _patch_values(text, patch, n):
    """The n vectors of `value nonuniform List<vector>` of a patch in an
    OpenFOAM field file (as written by writeCellCentres)."""
    m = re.search(patch + r"\s*\{[^}]*?value\s+nonuniform\s+List<vector>\s*(\d+)\s*\(", text, re.S)
    assert m is not None and int(m.group(1)) == n, patch
    vecs = re.findall(r"\(([^()]+)\)", text[m.end() :])[:n]
    return np.array([[float(x) for x in v.split()] for v in vecs])


def test_free_disc_spins_in_shear(tmp_path, env):
    """A free, neutrally buoyant resolved disc in a simple shear u = (G y, 0)
    must spin at half the vorticity, omega_z = -G/2: the torque-free
    rotation of a circular cylinder in Stokes flow (Jeffery 1922, Proc. R.
    Soc. A 102:161, for an ellipse of aspect ratio 1; the disturbance is a
    stresslet, it does not change the spin).  D = 1 cm, D/h = 10, box 5 D
    wide whose four walls and initial field carry the undisturbed shear,
    G = 0.1 1/s, nu = 1e-3 m^2/s (Re = G R^2/nu = 0.0025), nu dt/h^2 = 5,
    rotationCoupling and the resolved scheme with its rigid interior
    (viscosity penalty rigidViscosityRatio 1000, vansCloud.H "Resolved
    grains").  Within 5 % at
    t = 0.1, 0.2, 0.3 s (spin-up time ~R^2/nu = 0.025 s) and the disc stays
    at the centre (|x| < 1e-3 D).  Measured (03:30 UTC 2026-11-22):
    0.9976, 0.9995, 1.0002 of G/2; the penalty's Laplacian alone (without
    its transpose part, UEqn.H) gave 0.008: the transpose part is what
    lets the rigid region spin.  ~10 s."""
    D, G, nu = 0.01, 0.1, 1e-3
    H, h = 5 * D, D / 10
    n = round(H / h)
    case = str(tmp_path / "shear")
    setupCase.write_case(
        case,
        (-H / 2, -H / 2),
        (H / 2, H / 2),
        (n, n),
        [(0.0, 0.0, D)],
        1000.0,
        1000.0,
        nu,
        gravity=(0, 0, 0),
        end_time=0.3,
        write_interval=0.1,
        max_co=100,
        max_dt=5 * h * h / nu,
        rotation=True,
    )
    setupCase.opt_in_resolved(case, "rigidViscosityRatio 1000;\n")
    run("blockMesh", case, env)
    run("postProcess", case, env, args=("-func", "writeCellCentres", "-time", "0"))
    ctxt = open(os.path.join(case, "0", "C")).read()
    cin = nscdpost.read_internal_field(os.path.join(case, "0", "C"))
    cw = _patch_values(ctxt, "walls", 4 * n)

    def shear_list(c):
        return (
            f"nonuniform List<vector> {len(c)} ("
            + " ".join(f"({G * y:.12g} 0 0)" for y in c[:, 1])
            + ")"
        )

    upath = os.path.join(case, "0", "U")
    ut = open(upath).read()
    ut, k1 = re.subn(r"internalField\s+[^;]+;", f"internalField {shear_list(cin)};", ut)
    ut, k2 = re.subn(
        r"walls\s*\{[^}]*\}", f"walls {{ type fixedValue; value {shear_list(cw)}; }}", ut
    )
    assert k1 == 1 and k2 == 1
    open(upath, "w").write(ut)
    run("grainDeposit", case, env)
    p = run("vansFoam", case, env)
    # the 2D closed-pore warning (vansCloud) is for packings of grains
    # smaller than the cells, not for one resolved disc (eps ~ 1e-8 inside)
    assert "closed pores" not in p.stdout + p.stderr
    for t, name in nscdpost.time_dirs(case):
        if t <= 0:
            continue
        gdir = os.path.join(case, name, "lagrangian", "grains")
        w = nscdpost.read_vector_field(os.path.join(gdir, "omega"))[0, 2]
        x = nscdpost.read_vector_field(os.path.join(gdir, "positions"))[0]
        print(f"t {t:g} s: omega_z/(-G/2) = {w / (-G / 2):.4f}, |x| = {np.hypot(x[0], x[1]):.2e} m")
        assert abs(w / (-G / 2) - 1) < 0.05, (t, w)
        assert np.hypot(x[0], x[1]) < 1e-3 * D, (t, x)


@pytest.mark.parametrize(
    "penalty",
    [
        0,
        pytest.param(
            1000,
            marks=pytest.mark.xfail(
                strict=True,
                reason=(
                    "rigid interior (rigidViscosityRatio 1000) with rotationCoupling: the explicit "
                    "transpose part of the viscosity penalty is not torque free when the blob's spin "
                    "changes within a step; total angular momentum 0.0027 of its initial value after "
                    "0.01 s in the 6 d box (measured 2026-11-22; a grain-based transpose part gave 3.05 in a 3 d box, vansCloud.H)"
                ),
            ),
        ),
    ],
    ids=["noPenalty", "rigidInterior"],
)
def test_free_disc_spin_conserves_angular_momentum(tmp_path, env, penalty):
    """Conservation of angular momentum, grain + fluid, about the disc
    centre: I omega + rho_f sum_c eps_c ((x_c - x_p) x U_c)_z V_c, with
    I = rho_s pi R^4 l/2 (disc of depth l).  A free disc (R = 5 mm,
    rho_s/rho_f = 1.01, 16 cells per diameter, nu = 1e-3 m^2/s) released
    spinning at 2 rad/s in fluid at rest, box 6 d wide (walls 2.5 d from
    the rim), dt = 0.01 s (the spin-down time rho_s R^2/(8 mu) = 3 ms is
    shorter: the spin goes to the fluid within the first step, which is
    what is checked).  The exchange is Newton's third law (test above);
    the fluid's own stress is symmetric, so the total may change only by
    the wall torque: within 1 % at 0.01 s and 2 % at 0.02 s (the viscous
    front sqrt(nu t) = 3.2, 4.5 mm is 2.5 d = 25 mm from the walls; at
    0.05 s the walls have taken 11 %).  Measured without the rigid
    interior: 0.9975, 0.9878 (half the box: 0.88, 0.68, the wall torque).
    The grain keeps 22 % of the angular momentum at 0.01 s (omega 0.45
    rad/s), so the test also fails if the grain's spin is lost.  ~10 s."""
    R, omega, rho_s, rho_f = 0.005, 2.0, 1010.0, 1000.0
    d = 2 * R
    L, cells = 6 * d, 96  # 16 cells per diameter
    case = str(tmp_path / "amSpin")
    disc_case(
        case,
        env,
        rho_s,
        False,
        omega,
        end=0.02,
        dt=0.01,
        L=L,
        d=d,
        cells=cells,
        nu=1e-3,
        write_interval=0.01,
    )
    open(os.path.join(case, "constant", "couplingProperties"), "a").write(
        f"rigidViscosityRatio {penalty};\n"
    )
    run("vansFoam", case, env)
    run("postProcess", case, env, args=("-func", "writeCellCentres", "-time", "0"))
    C = nscdpost.read_internal_field(os.path.join(case, "0", "C"))
    h = L / cells
    V = h**3  # one cell deep, depth l = h
    inertia = rho_s * math.pi * R**4 * h / 2  # disc of depth h
    I0 = inertia * omega
    r = C[:, :2] - L / 2
    ratios = []
    for t, name in nscdpost.time_dirs(case):
        if t <= 0:
            continue
        U = nscdpost.read_internal_field(os.path.join(case, name, "U"))
        eps = nscdpost.read_internal_field(os.path.join(case, name, "voidFraction"))
        gdir = os.path.join(case, name, "lagrangian", "grains")
        w = nscdpost.read_vector_field(os.path.join(gdir, "omega"))[0, 2]
        xp = nscdpost.read_vector_field(os.path.join(gdir, "positions"))[0]
        assert np.hypot(*(xp[:2] - L / 2)) < 1e-3 * d, xp
        Lf = rho_f * np.sum(eps * (r[:, 0] * U[:, 1] - r[:, 1] * U[:, 0])) * V
        Lg = inertia * w
        ratios.append((Lg + Lf) / I0)
        print(
            f"t {t:g} s: omega {w:.5f} rad/s, (L_grain + L_fluid)/L_0 = {ratios[-1]:.4f} "
            f"(grain {Lg / I0:.4f})"
        )
        if abs(t - 0.01) < 1e-9:
            assert Lg / I0 > 0.05, w
    assert len(ratios) == 2, ratios
    assert abs(ratios[0] - 1) < 0.01, ratios
    assert abs(ratios[1] - 1) < 0.02, ratios


def test_closed_pore_warning_only_for_fine_grains(tmp_path, env):
    """The 2D closed-pore warning of vansCloud (effectiveDiameterFactor 1 and
    a cell void fraction < 0.1 at the start, thesis 3.2.3) is printed for a
    dense packing of discs smaller than the cells (a hexagonal lattice of
    touching discs d = h/2: solid fraction pi/(2 sqrt 3) = 0.907, cell void
    fraction ~0.09), and not for cells that one grain covers more than half
    (the resolved disc of test_free_disc_spins_in_shear, eps ~1e-8 inside
    by design).  < 5 s."""
    h, nx = 0.004, 6
    d = h / 2 * 1.0005  # touching within 0.05 %
    grains = []
    for j in range(int(nx * h / (d * math.sqrt(3) / 2)) - 1):
        y = d / 2 + j * d * math.sqrt(3) / 2
        x0 = d / 2 + (d / 2 if j % 2 else 0)
        for i in range(int((nx * h - x0 - d / 2) / d) + 1):
            grains.append((x0 + i * d, y, h / 2, d))
    case = str(tmp_path / "finePack")
    make_box_case(
        case,
        (0, 0, 0),
        (nx * h, nx * h, h),
        (nx, nx, 1),
        (0, 0, 0),
        {"s": {"density": 2500.0, "friction": 0.3}},
        grains=grains,
        end_time=1e-3,
        dt=1e-3,
        write_interval=1e-3,
    )
    add_fluid(case, 1000.0, 1e-6, max_dt=1e-3)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert "closed pores" in out, out[-2000:]
