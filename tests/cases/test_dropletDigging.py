# SPDX-License-Identifier: GPL-3.0-or-later
"""dropletDigging tutorial (issue 8; thesis section 4.3, Table 4.2): the
reduced copy (tutorials/vansFoam/dropletDigging, its own setupCase.py and
postProcess.py; 1 mm porous grains, grainPorosity so that the bed's solid
fraction is 0.4 as in thesis 4.3.2) run for a short time at three bed
temperatures, 300, 400 and 600 C (one in each of the thesis' regimes,
section 4.3.3).

(a) Energy budget (conservation law; issue 8 asks 1e-4 relative): between
    the end of the first and of the last step,
      Delta(E_gas + E_grains) + L (m_1 - m_N)
        = heat through walls and outlet (gas) + wall-grain contact heat
          + enthalpy rho Cp T_d Vdot dt of the vapour released at T_d,
    E from vansFoam's "heat:" line, the terms from its "heat budget:" line
    and droplet.dat (postProcess.energy_budget), relative to the heat
    L (m_1 - m_N) the droplet took (measured ~1e-11); and the droplet's heat
    Q_f + Q_p equals the solver's own source integral (two integrations of
    the same sink; measured 1.5e-13, asserted 1e-6).
(b) Conduction (Fourier's law, eq. 4.16 L mdot = Q_f + Q_p): at the first
    contact (first step, everything at T_bed, vapour source lagged, so the
    flow does not depend on T) the energy equation is linear in
    T - T_bed with the source proportional to T_d - T_bed: mdot_1/(T_bed - T_d)
    is the same at every bed temperature.  Measured spread 1.3e-4 relative
    between 300 and 600 C (a weak, unexplained nonlinearity of the first
    step; the levels differ by a factor 2.5), asserted 1e-3.  Over the first
    0.05 s the droplet loses mass faster on a hotter bed (monotone in T_bed;
    measured 1.94, 2.77, 4.23e-6 kg/s at 300, 400, 600 C with cohesion minAge 5
    (1.78, 2.51, 3.58e-6 with minAge 0) since the porous
    grains have their density (1-n) rho_s and contact conduction its Table
    4.2 E and nu; 1.92, 2.65, 3.68e-6 with the deposit's solid density and
    no contact conduction, the liquid pressure on the grains; 2.02,
    2.79, 3.97e-6 with the former hydrostatic buoyancy).
(c) The three regimes (thesis Figure 4.13: no digging below ~350 C, maximum
    depth near 400 C, droplet held near the surface above ~500 C): strict
    xfail with the numbers measured on the reduced bed (`./Allrun reduced
    1.0`, liquid pressure on the grains: the grains inside the droplet feel the liquid's
    pressure -S/V, src/dropletCoupling/README.md): in 1 s the droplet sinks
    to 15.4, 12.1, 9.3 mm at 300, 400, 600 C (bed top 20.8 mm; before, with
    the hydrostatic buoyancy, it reached the bottom at 0.66, 0.79, 0.95 s),
    monotonically less on a hotter bed; the fluidisation number
    U_vapour/U_mf is 0.08-0.16 instead of ~0.2-4 for the 55 um bed of
    Table 4.2, and the droplet's seepage through the packing (~d^2, 1 mm
    grains) is far faster than the thesis' digging.  Here (0.1 s) the depth is 4.33,
    3.97, 3.47 mm, decreasing with T_bed (2026-11-25, cohesion minAge 5; 3.9,
    3.6, 3.0 mm with minAge 0).
(d) The similarity scaling of the tutorial (setupCase.similarity_factors,
    Allrun SIMILARITY=<d_ref>): gas and liquid viscosity x (d/d_ref)^2 keep
    Ergun's U_mf of the Table 4.2 bed in its Carman-Kozeny range (Ergun
    1952), and the dictionaries carry the scaled values.
(e) Null test without evaporation (bed at T_d = 100 C): eq. 4.16 gives
    mdot = 0 (no superheat) and a bed at rest stays at rest (contact
    tolerance bound); without vapour thrust the droplet sinks at least as
    deep as on the 300 C bed.  It does sink: nothing keeps grains out of
    the droplet (no capillary force in eq. 4.17), so the liquid seeps
    through a packing that does not move (docs/validation/dropletDigging.md,
    "contact-tolerance study"): the reason regime (i) is missing.
(f) With the capillary entry barrier (dropletProperties surfaceTension,
    docs/validation/vapourDroplet.md "Capillary entry barrier") the droplet at T_d
    rests on the bed and the grains carry its weight (statics).
"""

import json
import os
import re

import nscdpost
import numpy as np
import pytest
from foamcase import run, tutorial_modules

pytestmark = pytest.mark.slow

TEMPS = (300.0, 400.0, 600.0)
END = 0.1  # s (~300 steps each)


@pytest.fixture(scope="module")
def sweep(tmp_path_factory, env):
    setup, post = tutorial_modules("vansFoam", "dropletDigging")
    root = str(tmp_path_factory.mktemp("dropletDigging"))
    setup.deposit(1e-3, root=root)
    dep = os.path.join(root, "deposit")
    run("blockMesh", dep, env)
    run("grainDeposit", dep, env)
    cases = {}
    for T in TEMPS:
        case = os.path.join(root, f"T{T:g}")
        setup.setup(case, T, END, root=root, porosity="auto", write_interval=END / 2)
        run("blockMesh", case, env)
        run("vansFoam", case, env)
        cases[T] = case
    return setup, post, cases, root


def test_energy_budget_closes(sweep):
    setup, post, cases, root = sweep
    for T, case in cases.items():
        b = post.energy_budget(case)
        print(
            f"T_bed {T:g} C: droplet heat {b['droplet_heat']:.4e} J, energy defect "
            f"{b['relative']:.2e} relative, source mismatch {b['source_mismatch']:.2e}"
        )
        assert b["droplet_heat"] > 0
        assert b["relative"] < 1e-4  # issue 8
        assert b["source_mismatch"] < 1e-6


def test_energy_budget_through_restart(sweep, env):
    """(a') The budget of (a) over a run continued from a write (the digging
    runs are extended this way: a later endTime, startFrom latestTime): the
    400 C case restarted from its 0.05 s write to 0.1 s.  The heatBudget.dat
    rows of the two runs (nscdpost.heat_history, ordered by their start
    times, the first cut at the restart) and the two droplet.dat parts join into
    one step sequence, and the energy of droplet + gas + grains + walls
    closes over 0-0.1 s within 1e-4 of the droplet's heat (issue 8; measured
    ~1e-10, the state written with 12 digits): the restart loses no energy
    and the post-processing reads all of the run."""
    import shutil

    setup, post, cases, root = sweep
    case = os.path.join(root, "T400_restart")
    shutil.copytree(cases[400.0], case)
    shutil.rmtree(os.path.join(case, "0.1"))
    os.rename(os.path.join(case, "log.vansFoam"), os.path.join(case, "log.vansFoam.first"))
    run("vansFoam", case, env)  # writes log.vansFoam: the continuation
    h = nscdpost.heat_history(case)
    d = post.read_droplet(case)
    first, rest = (
        np.loadtxt(os.path.join(case, "postProcessing", "heatBudget", t, "heatBudget.dat"), ndmin=2)
        for t in ("0", "0.05")
    )
    first, rest = {"time": first[:, 0]}, {"time": rest[:, 0]}
    assert abs(rest["time"][0] - 0.05) < 0.01 and abs(h["time"][-1] - END) < 1e-9
    assert np.all(np.diff(h["time"]) > 0)
    assert len(rest["time"]) < len(h["time"]) < len(first["time"]) + len(rest["time"])
    # the log prints times with timePrecision (6) digits
    assert len(h["time"]) == len(d) and np.allclose(h["time"], d[:, 0], rtol=1e-5)
    b = post.energy_budget(case)
    print(
        f"restarted at 0.05 s: {len(h['time'])} joined steps, droplet heat "
        f"{b['droplet_heat']:.4e} J, energy defect {b['relative']:.2e} relative"
    )
    assert b["relative"] < 1e-4
    assert b["source_mismatch"] < 1e-6


def test_forces_obey_eq_4_17(sweep):
    """The droplet's written forces (droplet.dat: S, F_p, F_c, m, v;
    postProcess.force_balance, thesis Figure 4.18) obey its equation of
    motion, eq. 4.17, m du_y/dt = -m g + F_f + F_p, step by step: rms
    residual < 1 % of m_0 g (measured 4-7e-15 here, where the droplet's
    equation is solved in one piece; 5e-4 with the capillary barrier, whose
    impulse comes from the NSCD step: the 600 C D-run of the README).  It
    checks the output, not the solver: a sign or column error in
    droplet.dat, or a force left out of it, breaks this; Figure 4.18 and
    the support shares of the README are drawn from these columns.  Gas +
    grains carry the weight on average over the last 0.03 s within 20 %
    (measured 1.02-1.06: the droplet is still braking)."""
    setup, post, cases, root = sweep
    for T, case in sorted(cases.items()):
        f = post.force_balance(post.read_droplet(case))
        print(
            f"T_bed {T:g} C: eq. 4.17 rms residual {f['momentum_residual']:.2e} m_0 g, "
            f"support at the end: gas {f['support']['fluid']:.2f}, grains "
            f"{f['support']['grains']:.2f}"
        )
        assert f["momentum_residual"] < 1e-2
        assert abs(f["support"]["fluid"] + f["support"]["grains"] - 1) < 0.2


def test_front_rear_walls_heat_the_bed(sweep, env):
    """(a'') The Hele-Shaw cell's front and rear walls at T_bed as a heat
    bath of the grains (setupCase.front_rear_walls: tau = (rho c)_bed
    l^2/(12 k_eff) = 0.30 s, Zehner-Schluender k_eff = 0.23 W/(m K) for
    Table 4.2; grainProperties frontRearWalls, src/grainCloud), the 400 C
    reduced case: the energy budget of (a) still closes within 1e-4 (the
    walls' heat enters through the log's "grain walls" term, nscd
    StepReport::exchangeHeat), the walls put heat in (sum > 0: the droplet
    cools the grains below T_bed) and the grains end warmer than without
    the walls (their heat makes up part of what the droplet takes)."""
    setup, post, cases, root = sweep
    tau = setup.front_rear_walls(True)
    k = setup.zehner_schlunder(setup.K_P, setup.KAPPA, 1 - setup.PHI_BED)
    # closed form of the tau above (Table 4.2 numbers): 0.2312 W/(m K), 0.3010 s
    assert abs(k - 0.2312) < 1e-3 and abs(tau - 0.3010) < 1e-3
    assert setup.front_rear_walls(False) is None
    case = os.path.join(root, "T400_walls")
    setup.setup(case, 400.0, END, root=root, porosity="auto", write_interval=END / 2, walls=True)
    run("blockMesh", case, env)
    log = run("vansFoam", case, env).stdout
    assert "front and rear walls (Hele-Shaw cell) at 673.15 K" in log
    b = post.energy_budget(case)
    lg, ref = post.read_heat(case), post.read_heat(cases[400.0])
    walls = lg["budget"][:, 3].sum()
    T_end, T_ref = lg["grain_T"][-1], ref["grain_T"][-1]
    print(
        f"front/rear walls: energy defect {b['relative']:.2e}, wall heat {walls:.3e} J "
        f"(without: {ref['budget'][:, 3].sum():.3e} J), mean grain T {T_end:.3f} K "
        f"(without: {T_ref:.3f} K)"
    )
    assert b["relative"] < 1e-4 and b["source_mismatch"] < 1e-6
    assert walls > ref["budget"][:, 3].sum()
    assert T_end > T_ref


def test_mass_loss_grows_with_bed_temperature(sweep):
    setup, post, cases, root = sweep
    first, early = [], []
    for T, case in sorted(cases.items()):
        d = post.read_droplet(case)
        assert len(d) > 50
        first.append(d[0, post.COL["mdot"]] / (T + 273.15 - setup.T_D))
        sel = d[:, 0] <= 0.05
        early.append((d[0, post.COL["m"]] - d[sel, post.COL["m"]][-1]) / d[sel, 0][-1])
    first, early = np.array(first), np.array(early)
    print("mdot_1/(T_bed - T_d) [kg/(s K)]:", first, "mean mdot over 0.05 s [kg/s]:", early)
    assert np.all(first > 0)
    assert np.ptp(first) < 1e-3 * first.mean()  # measured 1.3e-4
    assert np.all(np.diff(early) > 0)


def test_droplet_without_evaporation(sweep, env):
    """(e) The reduced bed at T_bed = T_d = 100 C, 0.1 s (engineer X,
    README "Measured, contact-tolerance study"):
    - eq. 4.16, L mdot = Q_f + Q_p with every temperature at T_d: |mdot|
      stays at round-off, < 1e-3 of the 300 C first-step mdot (measured
      max |mdot| 7e-10 kg/s against ~2e-6, ratio ~4e-4);
    - a bed at rest stays at rest: grains in the lower half of the bed move
      between the writes at 0.05 and 0.1 s by a median < 1e-2 d (bound: the
      NSCD per-step tolerance 1e-4 d_min, src/nscd/README.md, accumulated
      over ~100 steps; measured 3e-4 d);
    - the vapour thrust is upward: without evaporation the droplet is at
      least as deep at 0.1 s as on the 300 C bed (measured 4.8 vs 3.7 mm)."""
    setup, post, cases, root = sweep
    case = os.path.join(root, "T100")
    setup.setup(case, 100.0, END, root=root, porosity="auto", write_interval=END / 2)
    run("blockMesh", case, env)
    run("vansFoam", case, env)
    null, hot = post.read_droplet(case), post.read_droplet(cases[300.0])
    mdot_null, mdot_hot = np.max(np.abs(null[:, post.COL["mdot"]])), hot[0, post.COL["mdot"]]
    print(f"max |mdot| at T_d: {mdot_null:.3e} kg/s, 300 C first step {mdot_hot:.3e} kg/s")
    assert mdot_hot > 0 and mdot_null < 1e-3 * mdot_hot

    def positions(time_name):
        """Grain centres (x, y) [m] at a write time, ordered by grainId."""
        g = nscdpost.read_grains(case, time_name)
        return g["x"][np.argsort(g["grainId"]), :2]

    x0, x1 = positions("0.05"), positions("0.1")
    info = json.load(open(os.path.join(case, "case.json")))
    lower = (x0[:, 1] < 0.5 * info["bed_top"]) & (x1[:, 1] < 0.5 * info["bed_top"])
    move = np.median(np.linalg.norm(x1[lower] - x0[lower], axis=1)) / info["grain_diameter"]
    dn, dh = null[-1, post.COL["depth"]], hot[-1, post.COL["depth"]]
    print(
        f"lower-half grains ({lower.sum()}): median displacement 0.05-0.1 s {move:.2e} d; "
        f"depth at {END} s: T_d {1e3 * dn:.2f} mm, 300 C {1e3 * dh:.2f} mm"
    )
    assert lower.sum() > 50 and move < 1e-2
    assert dn >= dh


def test_capillary_barrier_holds_droplet(sweep, env):
    """(f) Capillary entry barrier (src/dropletCoupling/README.md, nscd
    System::Droplet): the droplet of (e) at T_d with surfaceTension 58.91
    mN/m (water at 100 C, IAPWS R1-76(2014)).  A grain enters the droplet
    only if pushed by more than 2 sigma = 0.118 N/m (2D, per unit depth),
    2.6 times the droplet's weight per depth (0.046 N/m), so the droplet
    rests on the bed instead of sinking through it as in (e):
    - depth at 0.1 s < 0.5 d (measured 0.13 mm = 0.14 d; without the
      barrier 4.8 mm, test (e));
    - statics of eq. 4.17 at rest: over 0.05-0.1 s the capillary force of
      the grains carries the apparent weight (m - rho_f V_f) g, the mean
      of F_c + F_pen + F_p + F_w within 1 % of it (measured -0.05 %, the
      residual is the droplet's jitter at the contact tolerance) and F_c
      alone within 2 % (measured -0.05 %).  The droplet starts resting on
      the bed (setupCase.resting_height)."""
    setup, post, cases, root = sweep
    case = os.path.join(root, "T100_sigma")
    setup.setup(
        case,
        100.0,
        END,
        root=root,
        porosity="auto",
        write_interval=END / 2,
        sigma=setup.SIGMA_WATER,
    )
    run("blockMesh", case, env)
    run("vansFoam", case, env)
    d = post.read_droplet(case)
    C = post.COL
    info = json.load(open(os.path.join(case, "case.json")))
    late = d[:, C["t"]] > 0.05
    m = d[late, C["m"]]
    weight = np.mean((m - setup.RHO * m / setup.RHO_L) * 9.81)
    fc = np.mean(d[late, C["Fc_y"]])
    total = np.mean(
        d[late, C["Fc_y"]] + d[late, C["Fpen_y"]] + d[late, C["Fp_y"]] + d[late, C["Fw_y"]]
    )
    depth = d[-1, C["depth"]]
    print(
        f"depth at {END} s: {1e3 * depth:.3f} mm ({depth / info['grain_diameter']:.2f} d); "
        f"F_c/W {fc / weight:.5f}, (F_c + F_pen + F_p + F_w)/W {total / weight:.5f}"
    )
    assert depth < 0.5 * info["grain_diameter"]
    assert abs(total / weight - 1) < 1e-2
    assert abs(fc / weight - 1) < 2e-2


@pytest.mark.xfail(
    strict=True,
    reason=(
        "not reproduced (README.md, docs/validation/dropletDigging.md 'Findings'): "
        "on the reduced 1 mm bed the droplet seeps in at every T_bed, less when "
        "hotter (depth at 0.1 s 4.33, 3.97, 3.47 mm at 300/400/600 C, cohesion "
        "minAge 5); on the similarity-scaled 0.2 mm bed with the measured U_mf it "
        "sinks 2.4 / 2.0 mm in 3 s at 300 / 400 C, filling with grains, no chimney; "
        "on the thesis' 55 um bed (dropletDigging.md item 11) the order turns by 1.6 s "
        "(depth 2.54 / 2.89 / 2.06 mm at 300/400/600 C, 400 C sinking 1.7 mm/s by "
        "taking grains in, 600 C stopped), runs not yet at 3 s"
    ),
)
def test_three_regimes(sweep):
    """Thesis Figure 4.13 / section 4.3.3: the depth at 400 C exceeds the
    depths at 300 C and 600 C by more than a grain diameter."""
    setup, post, cases, root = sweep
    depth = {T: post.read_droplet(c)[-1, post.COL["depth"]] for T, c in cases.items()}
    print("depth [m] at t = %g s:" % END, depth)
    d = 1e-3
    assert depth[400.0] > depth[300.0] + d and depth[400.0] > depth[600.0] + d


def test_cohesion_is_ten_grain_weights_per_unit_depth():
    """Units of Table 4.2's F_c^0 = 7.5e-4 (thesis eq. 4.18) in 2D.  The
    thesis' grain code is 2D per unit depth (MigFlow 1.4, scontact.py: disc
    volume pi r^2), and F_c^0 is then 10.0 weights per unit depth of the
    55 um disc of 3200 kg/m^3 (Table 4.2: 7.46e-5 N/m), a granular Bond number
    of 10; read as a force on a grain of length l it would be 74 times the
    largest capillary force of two 55 um water-wetted spheres (2 pi R sigma,
    sigma = 58.91 mN/m at 100 C, IAPWS R1-76), which no contact can carry.
    setupCase writes F_c^0 as the per-unit-depth force (the slow
    test_similarity_scaling_keeps_umf checks the dictionary).  < 1 s."""
    setup, _ = tutorial_modules("vansFoam", "dropletDigging")
    weight = setup.RHO_P * 9.81 * np.pi / 4 * setup.D_GRAIN_TABLE**2  # N/m
    bond = setup.F_C0 / weight
    capillary = 2 * np.pi * setup.D_GRAIN_TABLE / 2 * setup.SIGMA_WATER  # N
    print(
        f"F_c^0 = {setup.F_C0} N/m = {bond:.3f} disc weights; as a force on a grain: "
        f"{setup.F_C0 / capillary:.1f} x 2 pi R sigma"
    )
    assert abs(bond - 10) < 0.1, bond
    assert setup.F_C0 / capillary > 10


def test_similarity_scaling_keeps_umf(sweep, tmp_path):
    """(d) The scaled bed's U_mf equals the 55 um bed's: Ergun's law
    (postProcess.ergun_umf, Ergun 1952) at the thesis' bed (eps = 0.607,
    rho_s = 3200 kg/m^3, weight fraction 0.4) for d = 0.18567 mm (the 0.2 mm
    bed's mean) with the gas viscosity x s against d = 55 um with 2e-5 Pa s:
    within 0.5 % (Carman-Kozeny range, the inertial term is ~5e-4 of the
    pressure gradient there; measured +0.13 %), while unscaled the 0.2 mm
    bed's U_mf is ~s = 11.4 x larger (so the check can fail).  And setup()
    writes gas nu x s, liquidViscosity x s and the cohesion x d/d_ref
    (here on the 1 mm bed of the sweep, mean d 0.947 mm: s = 296.7),
    unscaled by default.  < 1 s."""
    setup, post = sweep[0], sweep[1]
    root = sweep[3]
    d, dref = 1.8567e-4, 55e-6
    f = setup.similarity_factors(d, dref)
    assert abs(f["s"] - (d / dref) ** 2) < 1e-12 and abs(f["c"] - d / dref) < 1e-12
    with pytest.raises(ValueError):
        setup.similarity_factors(d, 0.0)
    u_ref = post.ergun_umf(dref, 0.607, 3200.0, mu=2e-5, weight_fraction=0.4)
    u_sim = post.ergun_umf(d, 0.607, 3200.0, mu=2e-5 * f["s"], weight_fraction=0.4)
    u_raw = post.ergun_umf(d, 0.607, 3200.0, mu=2e-5, weight_fraction=0.4)
    print(f"U_mf: 55 um {u_ref:.5f}, scaled {u_sim:.5f}, unscaled {u_raw:.5f} m/s")
    assert abs(u_sim / u_ref - 1) < 5e-3, (u_sim, u_ref)
    assert u_raw / u_ref > 0.9 * f["s"], (u_raw, u_ref)

    def entry(case, dictionary, pattern):
        txt = open(os.path.join(case, "constant", dictionary)).read()
        return float(re.search(pattern, txt).group(1))

    plain, scaled = str(tmp_path / "plain"), str(tmp_path / "scaled")
    setup.setup(plain, 400.0, 0.01, root=root, porosity="auto")
    setup.setup(scaled, 400.0, 0.01, root=root, porosity="auto", similarity=dref)
    ratio_nu = entry(scaled, "transportProperties", r"\bnu\s+([0-9.eE+-]+);") / entry(
        plain, "transportProperties", r"\bnu\s+([0-9.eE+-]+);"
    )
    ratio_mu = entry(scaled, "dropletProperties", r"liquidViscosity\s+([0-9.eE+-]+);") / entry(
        plain, "dropletProperties", r"liquidViscosity\s+([0-9.eE+-]+);"
    )
    ratio_fc = entry(scaled, "couplingProperties", r"force\s+([0-9.eE+-]+);") / entry(
        plain, "couplingProperties", r"force\s+([0-9.eE+-]+);"
    )
    print(
        f"1 mm bed scaled to 55 um: nu x {ratio_nu:.2f}, mu_l x {ratio_mu:.2f}, F_c x {ratio_fc:.3f}"
    )
    assert abs(ratio_nu - ratio_mu) < 1e-6 * ratio_nu
    assert abs(ratio_fc**2 - ratio_nu) < 1e-5 * ratio_nu
    # 2D cohesion per unit depth, unscaled: Table 4.2's F_c^0 itself [N/m]
    assert abs(entry(plain, "couplingProperties", r"force\s+([0-9.eE+-]+);") - setup.F_C0) < 1e-12
    assert ratio_nu > 100  # 1 mm / 55 um: s ~ 330
    assert (
        abs(entry(plain, "dropletProperties", r"liquidViscosity\s+([0-9.eE+-]+);") - 2.82e-4)
        < 1e-12
    )


def assert_env_error(monkeypatch, settings, env, name):
    """settings() with the environment variables env set raises a ValueError
    naming the variable `name`."""
    for key, value in env.items():
        monkeypatch.setenv(key, value)
    with pytest.raises(ValueError, match=name):
        settings()


def test_contact_compliance_settings(tmp_path, monkeypatch):
    """setupCase's CONTACT_COMPLIANCE / CONTACT_RELAXATION (the settings that
    settle the 55 um bed, docs/validation/contactCompliance.md) reach
    constant/grainProperties as the grains' relativeCompliance and the
    contactSolver's relaxation, CONTACT_COMPLIANCE_ABSOLUTE as their
    compliance; unset, the dictionary has none (the hard law); a negative
    compliance, both compliances, or a factor outside (0, 2) is a ValueError
    naming the variable.  Consistency check of the script only.  < 1 s."""
    setup, _ = tutorial_modules("vansFoam", "dropletDigging")
    monkeypatch.delenv("CONTACT_COMPLIANCE", raising=False)
    monkeypatch.delenv("CONTACT_RELAXATION", raising=False)
    setup.mesh_and_grains(str(tmp_path / "hard"), 1e-3)
    txt = open(tmp_path / "hard" / "constant" / "grainProperties").read()
    assert "relativeCompliance" not in txt and "relaxation" not in txt
    monkeypatch.setenv("CONTACT_COMPLIANCE", "2e-3")
    monkeypatch.setenv("CONTACT_RELAXATION", "1.5")
    setup.mesh_and_grains(str(tmp_path / "soft"), 1e-3)
    txt = open(tmp_path / "soft" / "constant" / "grainProperties").read()
    assert "relativeCompliance 0.002;" in txt and "relaxation 1.5;" in txt
    assert_env_error(
        monkeypatch, setup.contact_compliance, {"CONTACT_COMPLIANCE": "-1"}, "CONTACT_COMPLIANCE"
    )
    assert_env_error(
        monkeypatch,
        setup.contact_compliance,
        {"CONTACT_COMPLIANCE": "0", "CONTACT_RELAXATION": "2"},
        "CONTACT_RELAXATION",
    )
    monkeypatch.setenv("CONTACT_RELAXATION", "1.5")
    monkeypatch.setenv("CONTACT_COMPLIANCE", "0")
    monkeypatch.setenv("CONTACT_COMPLIANCE_ABSOLUTE", "5.5e-5")
    setup.mesh_and_grains(str(tmp_path / "absolute"), 1e-3)
    txt = open(tmp_path / "absolute" / "constant" / "grainProperties").read()
    assert " compliance 5.5e-05;" in txt and "relativeCompliance" not in txt
    assert_env_error(
        monkeypatch,
        setup.contact_compliance_absolute,
        {"CONTACT_COMPLIANCE_ABSOLUTE": "-1"},
        "CONTACT_COMPLIANCE_ABSOLUTE",
    )
    assert_env_error(
        monkeypatch,
        setup.contact_compliance_absolute,
        {"CONTACT_COMPLIANCE_ABSOLUTE": "1e-5", "CONTACT_COMPLIANCE": "2e-3"},
        "CONTACT_COMPLIANCE",
    )


def test_minimum_fluidisation_velocity(sweep, env, tmp_path, monkeypatch):
    """U_mf measured in vansFoam (umf.py, issue 54 item 1) on the sweep's 1 mm
    bed, similarity-scaled to 55 um: the inlet velocity ramps up to 30 mm/s
    (~3 U_mf) in 1.5 s.  Independent reference: once fluidised the gas
    carries the bed, so the bed's pressure drop equals its buoyant weight per
    unit area (momentum balance; Kunii & Levenspiel, Fluidization
    Engineering, 2nd ed., 1991, section 3.2) within 5 % over U > 1.5 U_mf
    (measured 1.021 of W/A).  Cross-check against a different correlation:
    U_mf within a factor 2 of Ergun's (Ergun 1952) at the bed's gas fraction
    0.6 (measured 9.87 against 17.1 mm/s: the 2D porous discs on cells of
    d/3 are less permeable than Ergun's spheres; on the 0.2 mm bed 1.76 x
    more, docs/validation/dropletDigging.md).  Consistency check: the
    velocity where dp first reaches 0.95 W/A is 0.95 U_mf within 10 % (the
    fixed-bed branch is linear).
    Contact compliance 2e-3 (6 sweeps a step).  ~20 s."""
    (umf,) = tutorial_modules("vansFoam", "dropletDigging", names=("umf",))
    monkeypatch.setenv("CONTACT_COMPLIANCE", "2e-3")
    monkeypatch.setenv("CONTACT_RELAXATION", "1.5")
    case = str(tmp_path / "umf")
    umf.setup(case, sweep[3], similarity=55e-6, u_max=0.03)
    run("blockMesh", case, env)
    run("vansFoam", case, env)
    r = umf.measure(case)
    print({k: v for k, v in r.items() if k not in ("U", "dp")})
    assert abs(r["plateau"] - 1) < 0.05, r["plateau"]
    assert 0.5 < r["U_mf"] / r["U_mf_ergun"] < 2, (r["U_mf"], r["U_mf_ergun"])
    assert abs(r["U_first_dp_095_weight"] / (0.95 * r["U_mf"]) - 1) < 0.1


def test_cohesion_settings(monkeypatch):
    """setupCase's COHESION_MIN_AGE / COHESION_FACTOR: minAge 5 and factor 1
    by default (the thesis, section 4.3.2: cohesive once a contact persists
    for several steps); a negative minAge or a factor <= 0 is a ValueError
    naming the variable.  Consistency check of the script only.  < 1 s."""
    setup, _ = tutorial_modules("vansFoam", "dropletDigging")
    monkeypatch.delenv("COHESION_MIN_AGE", raising=False)
    monkeypatch.delenv("COHESION_FACTOR", raising=False)
    assert setup.cohesion_settings() == (5, 1.0)
    monkeypatch.setenv("COHESION_FACTOR", "100")
    assert setup.cohesion_settings() == (5, 100.0)
    assert_env_error(
        monkeypatch, setup.cohesion_settings, {"COHESION_FACTOR": "0"}, "COHESION_FACTOR"
    )
    assert_env_error(
        monkeypatch,
        setup.cohesion_settings,
        {"COHESION_FACTOR": "1", "COHESION_MIN_AGE": "-1"},
        "COHESION_MIN_AGE",
    )


def test_droplet_offset_setting(monkeypatch):
    """setupCase's DROPLET_X_OFFSET (the perturbed starts of
    tests/bench/dropletDiggingSpread.py): 0 by default, the value in metres
    when set; a non-finite or non-numeric offset is a ValueError naming the
    variable.  Consistency check of the script only.  < 1 s."""
    setup, _ = tutorial_modules("vansFoam", "dropletDigging")
    monkeypatch.delenv("DROPLET_X_OFFSET", raising=False)
    assert setup.droplet_offset() == 0.0
    monkeypatch.setenv("DROPLET_X_OFFSET", "-2.75e-5")
    assert setup.droplet_offset() == -2.75e-5
    for bad in ("nan", "2 mm"):
        assert_env_error(
            monkeypatch, setup.droplet_offset, {"DROPLET_X_OFFSET": bad}, "DROPLET_X_OFFSET"
        )


def test_height_above_the_initial_surface():
    """postProcess.initial_surface / above_surface (the `ejected` and
    `highest_above_surface` diagnostics): a bed of two layers of touching
    discs of diameter d (surface = top layer's centre + d/2 in every column,
    geometry), a grain 6 d above that surface and one resting on it; a
    column left empty takes its neighbours' height.  Consistency check of
    the script against the construction.  < 1 s."""
    _, post = tutorial_modules("vansFoam", "dropletDigging")
    d, width = 1e-3, 0.02
    xs = (np.arange(20) + 0.5) * d
    xs = xs[(xs < 0.006) | (xs > 0.008)]  # the column 6-8 mm (of width 2 d) empty
    layers = [
        np.column_stack((xs, np.full_like(xs, (k + 0.5) * d), np.zeros_like(xs))) for k in (0, 1)
    ]
    g = {"x": np.vstack(layers), "d": np.full(2 * len(xs), d)}
    surface = post.initial_surface(g, width)
    top = 2 * d
    assert np.allclose(surface[1], top, rtol=0, atol=1e-12)
    h = post.above_surface(
        surface, np.array([0.0055, 0.0105, 0.00625]), np.array([top + 6 * d, top + 0.5 * d, top])
    )
    assert np.allclose(h, [6 * d, 0.5 * d, 0.0], atol=1e-12)
    assert np.sum(h > 5 * d) == 1
