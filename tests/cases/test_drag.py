# SPDX-License-Identifier: GPL-3.0-or-later
"""The drag models against references independent of the code.

Each test names its reference; none re-derives the formula under test, except
the checks labelled "consistency check" (the coded law itself, to tell a
coding error from a deviation of the law).

- Lone sphere (eps -> 1), 3D, one grain in a box of h/d = 10: the slip
  velocity at terminal speed against the standard drag curve of
  Brown & Lawler (2003, J. Environ. Eng. 129, 222-231, their eq. 19, a fit of
  480 measurements), C_d = 24/Re (1 + 0.150 Re^0.681) + 0.407/(1 + 8710/Re),
  at Re_t = 0.1, 1, 10, 100 and 1000.
  Gidaspow (Wen & Yu, i.e. Schiller & Naumann at eps = 1): within 5 %.
  DallavalleDiFelice: Dallavalle's C_d = (0.63 + 4.8/sqrt(Re))^2 lies above the
  standard curve, by 4 % at Re 0.1 and up to 40 % at Re 1000; the terminal
  slip is therefore 1-13 % below Brown & Lawler's (known deviation, asserted
  within [0.85, 1.0]) and equals Dallavalle's own law within 2 % (consistency).
- Lab-frame terminal velocity of the same sphere at h/d = 1, 2, 4, 8: an
  unresolved grain drags the fluid of its own cells along (self-induced
  velocity), so its lab-frame speed exceeds the slip.  Reported; within 5 %
  of the quiescent-fluid terminal speed for h/d >= 4.  With
  `undisturbedVelocity steadyOseen` (Balachandar, Liu & Lakhote 2019,
  J. Comput. Phys. 376, 160-185, steady Oseen form): within 5 % for
  h/d >= 2 (h/d = 2 alone in the fast tier); over-corrected at h/d = 1
  (known deviation, asserted within [0.75, 0.90]).  An unknown word is a
  FatalIOError naming the file, the keyword and the allowed words, and so
  is steadyOseen on a 2D mesh.
- Fixed bed of spheres (simple cubic lattice, eps = 1 - pi/6 = 0.476) at
  Re_p ~ 1: pressure drop against Ergun (1952), an independent correlation.
  Gidaspow's dense branch is Ergun's law: within 5 %.  Di Felice's voidage
  function was fitted on expanded beds; at eps = 0.476 it gives 0.83 Ergun's
  drop at Re_p = 1 (known deviation, asserted within [0.75, 0.90]).
- Homogeneous liquid-fluidised bed (Richardson & Zaki 1954, Chem. Eng. Sci. 3,
  65-73; "The sedimentation of a suspension of uniform spheres under
  conditions of viscous flow"), U/v_t = eps^n: a fixed lattice of spheres of
  void fraction eps carries, in a fluidised bed, the drag eps (rho_p - rho) g
  per unit grain volume (model A force balance: fluid 0 = -eps dp/dy -
  eps rho g - phi f, grains 0 = -phi dp/dy + phi f - phi rho_p g).  The
  superficial velocity at which the lattice feels that drag is the velocity
  that fluidises the bed at eps.  It is measured (two runs per eps, log-
  interpolated) and compared with Richardson & Zaki's n (1954) within 10 %
  and with Garside & Al-Dibouni's n = (5.1 + 0.27 Re_t^0.9)/(1 + 0.1 Re_t^0.9)
  (1977, Ind. Eng. Chem. Process Des. Dev. 16, 206-214): Di Felice's chi fits
  n = 4.7/2.35, so U is above Garside & Al-Dibouni's by 5-20 % at
  eps = 0.5-0.85 (known deviation, asserted within 25 %).
"""

import math
import os

import correlations
import nscdpost
import pytest
from correlations import (
    cd_brown_lawler,
    cd_dallavalle,
    ergun_gradient,
    n_garside_al_dibouni,
    n_richardson_zaki,
)
from foamcase import add_fluid, fixed_lattice_bed, gmsh_box, make_box_case, run, run_fatal_io

G = 9.81
RHO, RHOP, D = 1000.0, 2500.0, 1e-3


def terminal_slip(cd, d, nu):
    return correlations.terminal_velocity(cd, d, nu, RHO, RHOP)


def nu_for_reynolds(Re):
    """Kinematic viscosity giving the Brown & Lawler terminal Reynolds number
    Re for a glass sphere of d = 1 mm in a fluid of density 1000."""
    w = math.sqrt(4.0 / 3.0 * G * D * (RHOP - RHO) / (RHO * cd_brown_lawler(Re)))
    return w * D / Re


# -- lone sphere ---------------------------------------------------------------
def settle_one(case, env, model, nu, hd=10, end=0.3, undisturbed="none", mesh="hex"):
    """One sphere of diameter D released near the top of a box of cells of
    size h = hd D (couplingProperties undisturbedVelocity `undisturbed`;
    mesh "tet": gmsh tetrahedra of size at most h instead of blockMesh's
    hexahedra); returns (slip, lab-frame velocity, mean fall speed over the
    last third)."""
    h = hd * D
    # at least 16 d wide and 60 d tall (4 x 20 cells at h/d = 10)
    nx, ny = max(4, int(round(16 / hd))), max(20, int(round(60 / hd)))
    lx, ly = nx * h, ny * h
    make_box_case(
        case,
        (0, 0, 0),
        (lx, ly, lx),
        (nx, ny, nx),
        (0, -G, 0),
        {"glass": {"density": RHOP, "friction": 0.4}},
        grains=[(lx / 2 + 0.3 * h, ly - 15 * D, lx / 2 + 0.3 * h, D)],
        end_time=end,
        dt=1e-3,
        write_interval=end / 3,
        two_d=False,
    )
    add_fluid(case, RHO, nu, drag=model, extra_coupling=f"undisturbedVelocity {undisturbed};\n")
    if mesh == "tet":
        gmsh_box(case, env, (0, 0, 0), (lx, ly, lx), h)
    else:
        run("blockMesh", case, env)
    run("grainDeposit", case, env)
    run("vansFoam", case, env)
    # mixture volume conservation at solver tolerance (last PISO corrector
    # of each step: pFinal, relTol 0, tolerance 1e-9; continuityErrors.dat)
    errs = nscdpost.read_step_data(case, "continuityErrors")["sumLocal"]
    assert len(errs) and max(errs) < 1e-8
    (t0, name0), (t, name) = nscdpost.time_dirs(case)[-2:]
    v = nscdpost.read_grains(case, name)["U"][0]
    u = nscdpost.read_vector_field(os.path.join(case, name, "lagrangian", "grains", "Ufluid"))[0]
    # lab-frame speed averaged over the last third: the instantaneous one
    # varies by a few % as the sphere crosses the cell faces at h/d ~ 2
    fall = (
        nscdpost.read_grains(case, name0)["x"][0][1] - nscdpost.read_grains(case, name)["x"][0][1]
    )
    return u[1] - v[1], -v[1], fall / (t - t0)


@pytest.mark.fast
@pytest.mark.parametrize("Re", [0.1, 1, 10, 100, 1000])
@pytest.mark.parametrize("model", ["Gidaspow", "DallavalleDiFelice"])
def test_lone_sphere_terminal_slip(tmp_path, env, model, Re):
    nu = nu_for_reynolds(Re)
    slip, lab, _ = settle_one(str(tmp_path / "c"), env, model, nu)
    ref = terminal_slip(cd_brown_lawler, D, nu)
    print(
        f"{model} Re_t {Re}: slip {slip:.5g} m/s, lab {lab:.5g} m/s, "
        f"Brown & Lawler {ref:.5g} m/s, slip/ref {slip / ref:.4f}"
    )
    if model == "Gidaspow":
        assert slip == pytest.approx(ref, rel=0.05)
    else:
        # known deviation of Dallavalle's C_d from the standard curve
        assert 0.85 * ref <= slip <= 1.0 * ref
        # consistency check: the coded law's own terminal slip
        assert slip == pytest.approx(terminal_slip(cd_dallavalle, D, nu), rel=0.02)


@pytest.mark.fast
def test_lone_sphere_on_tets(tmp_path, env):
    """A lone sphere at Re_t = 10 (Gidaspow) settling through gmsh tetrahedra
    of size at most 10 d: its mean fall speed over the last third of the
    run within 5 % of the hexahedral mesh's and of Brown & Lawler's terminal
    velocity (the independent reference); measured 0.978 of Brown & Lawler
    (hex 1.000; tets of 5 d and 20 d: 0.985, 1.013).  The instantaneous slip
    of the gathered fluid velocity varies more on tets, whose sizes and
    shapes vary under the sphere (0.93 at the last write; 1.02 and 1.14 at
    5 d and 20 d): within 10 %."""
    nu = nu_for_reynolds(10)
    ref = terminal_slip(cd_brown_lawler, D, nu)
    hexa = settle_one(str(tmp_path / "hex"), env, "Gidaspow", nu)
    tet = settle_one(str(tmp_path / "tet"), env, "Gidaspow", nu, mesh="tet")
    print(
        f"lone sphere Re_t 10, / Brown & Lawler: mean fall speed tet {tet[2] / ref:.4f}, "
        f"hex {hexa[2] / ref:.4f}; slip tet {tet[0] / ref:.4f}, hex {hexa[0] / ref:.4f}"
    )
    assert tet[2] == pytest.approx(hexa[2], rel=0.05)
    assert tet[2] == pytest.approx(ref, rel=0.05)
    assert tet[0] == pytest.approx(ref, rel=0.10)


@pytest.mark.slow
@pytest.mark.parametrize("undisturbed", ["none", "steadyOseen"])
def test_lone_sphere_lab_frame_velocity(tmp_path, env, undisturbed):
    """Lab-frame terminal speed vs h/d at Re_t = 10 (Gidaspow, whose lone-
    sphere law is within 1 % of Brown & Lawler there), without and with the
    self-induced velocity correction."""
    nu = nu_for_reynolds(10)
    ref = terminal_slip(cd_brown_lawler, D, nu)
    lab, mean = {}, {}
    for hd in (1, 2, 4, 8):
        _, lab[hd], mean[hd] = settle_one(
            str(tmp_path / f"hd{hd}"), env, "Gidaspow", nu, hd=hd, undisturbed=undisturbed
        )
    print(
        f"undisturbedVelocity {undisturbed}, "
        "lab-frame terminal speed / Brown & Lawler: "
        + ", ".join(f"h/d {hd}: {v / ref:.3f}" for hd, v in lab.items())
        + "; mean over the last 0.1 s: "
        + ", ".join(f"h/d {hd}: {v / ref:.3f}" for hd, v in mean.items())
    )
    if undisturbed == "none":
        for hd in (4, 8):
            assert lab[hd] == pytest.approx(ref, rel=0.05)
    else:
        for hd in (2, 4, 8):
            assert lab[hd] == pytest.approx(ref, rel=0.05)
            assert mean[hd] == pytest.approx(ref, rel=0.05)
        # known deviation: at h/d = 1 (kernel width ~0.6 d) the point-force
        # model over-estimates the self-induced velocity, 0.80 measured
        assert 0.75 * ref <= lab[1] <= 0.90 * ref


@pytest.mark.fast
def test_lone_sphere_undisturbed_velocity_correction(tmp_path, env):
    """undisturbedVelocity steadyOseen (Balachandar, Liu & Lakhote 2019):
    the lab-frame terminal speed at h/d = 2, Re_t = 10, where the gathered
    velocity makes it 10.5 % too fast, within 5 % of Brown & Lawler's (the
    band of the h/d >= 4 runs without correction, and of Gidaspow's own
    lone-sphere law against Brown & Lawler, < 1 % at Re 10)."""
    nu = nu_for_reynolds(10)
    ref = terminal_slip(cd_brown_lawler, D, nu)
    slip, lab, mean = settle_one(
        str(tmp_path / "c"), env, "Gidaspow", nu, hd=2, undisturbed="steadyOseen"
    )
    print(
        f"steadyOseen h/d 2 Re_t 10: lab / Brown & Lawler {lab / ref:.4f} "
        f"(mean over the last 0.1 s {mean / ref:.4f}), gathered slip / ref {slip / ref:.4f}"
    )
    assert lab == pytest.approx(ref, rel=0.05)
    assert mean == pytest.approx(ref, rel=0.05)


@pytest.mark.fast
def test_undisturbed_velocity_unknown_word(tmp_path, env):
    case = str(tmp_path / "bad")
    make_box_case(
        case,
        (0, 0, 0),
        (0.004, 0.008, 0.004),
        (2, 4, 2),
        (0, -G, 0),
        {"glass": {"density": RHOP, "friction": 0.4}},
        grains=[(0.002, 0.004, 0.002, D)],
        end_time=0.001,
        dt=1e-3,
        two_d=False,
    )
    add_fluid(case, RHO, 1e-6, drag="Gidaspow", extra_coupling="undisturbedVelocity Balachandar;\n")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    out = run_fatal_io("vansFoam", case, env)
    assert "undisturbedVelocity Balachandar" in out and "couplingProperties" in out
    assert "none" in out and "steadyOseen" in out


@pytest.mark.fast
def test_undisturbed_velocity_is_3d_only(tmp_path, env):
    """steadyOseen is the disturbance of a point force in 3D: a 2D mesh is a
    FatalIOError saying so."""
    case = str(tmp_path / "twoD")
    make_box_case(
        case,
        (0, 0, 0),
        (0.04, 0.08, 0.004),
        (4, 8, 1),
        (0, -G, 0),
        {"glass": {"density": RHOP, "friction": 0.4}},
        grains=[(0.02, 0.04, 0.002, 0.004)],
        end_time=0.001,
        dt=1e-3,
    )
    add_fluid(case, RHO, 1e-6, extra_coupling="undisturbedVelocity steadyOseen;\n")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    out = run_fatal_io("vansFoam", case, env)
    assert "undisturbedVelocity steadyOseen" in out and "2D" in out


# -- fixed beds ------------------------------------------------------------------
def lattice_drag(case, env, model, Us, s, nu, layers=8):
    """Fixed simple cubic lattice of spheres of diameter D, spacing s (one
    per cell), `layers` cells deep, between empty inlet and outlet regions;
    uniform superficial inflow Us.  Returns (eps, pressure gradient inside
    the bed [Pa/m], drag per unit grain volume [N/m^3]).  The gradient is
    taken between the centres of the second and the second-to-last layer,
    away from the void-fraction jumps at the bed's faces (an homogeneous
    bed, as Ergun's and Richardson-Zaki's)."""
    nx, ny = 3, 3 * layers
    p = fixed_lattice_bed(
        case, env, s, D, nx, ny, range(layers, 2 * layers), Us, RHO, nu, drag=model
    )
    j0, j1 = layers + 1, 2 * layers - 2
    grad = RHO * (p[:, j0, :].mean() - p[:, j1, :].mean()) / ((j1 - j0) * s)  # kinematic p
    eps = 1 - math.pi * D**3 / (6 * s**3)
    return eps, grad, eps * grad / (1 - eps)


@pytest.mark.fast
@pytest.mark.parametrize("model", ["Gidaspow", "DallavalleDiFelice"])
def test_fixed_bed_against_ergun(tmp_path, env, model):
    nu, Us, s = 1e-6, 1e-3, D * 1.0001
    eps, grad, _ = lattice_drag(str(tmp_path / model), env, model, Us, s, nu)
    ref = ergun_gradient(eps, Us, D, RHO * nu, RHO)
    print(
        f"{model}: eps {eps:.4f}, Re_p {Us * D / nu:.3g}, dp/dy {grad:.6g} Pa/m, "
        f"Ergun {ref:.6g} Pa/m, ratio {grad / ref:.4f}"
    )
    if model == "Gidaspow":
        assert grad == pytest.approx(ref, rel=0.05)
    else:
        assert 0.75 * ref <= grad <= 0.90 * ref


@pytest.mark.slow
def test_fluidised_bed_expansion(tmp_path, env):
    """DallavalleDiFelice; glass spheres d = 1 mm in water (Re_t ~ 130)."""
    model, nu = "DallavalleDiFelice", 1e-6
    vt = terminal_slip(cd_dallavalle, D, nu)  # the model's own v_t
    Ret = vt * D / nu
    weight = (RHOP - RHO) * G  # buoyant weight per grain volume
    rows = []
    for s_over_d in (1.03, 1.12, 1.25, 1.45):
        s = s_over_d * D
        eps = 1 - math.pi * D**3 / (6 * s**3)
        U1 = vt * eps ** n_richardson_zaki(Ret)
        f = {}
        for U in (U1, 1.15 * U1):
            _, _, f[U] = lattice_drag(str(tmp_path / f"s{s_over_d}_{U:.4g}"), env, model, U, s, nu)
        (Ua, fa), (Ub, fb) = sorted(f.items())
        a = math.log(fb / fa) / math.log(Ub / Ua)
        U = Ua * (eps * weight / fa) ** (1 / a)  # drag = eps (rho_p - rho) g
        rows.append((eps, U / vt, eps ** n_richardson_zaki(Ret), eps ** n_garside_al_dibouni(Ret)))
    print(
        f"Re_t {Ret:.4g}, v_t {vt:.5g} m/s;  eps, U/v_t: measured, Richardson-Zaki 1954, "
        "Garside-Al-Dibouni 1977\n"
        + "\n".join(f"  {e:.4f}  {u:.4f}  {rz:.4f}  {gad:.4f}" for e, u, rz, gad in rows)
    )
    for _eps, u, rz, gad in rows:
        assert u == pytest.approx(rz, rel=0.10)
        assert gad <= u <= 1.25 * gad
