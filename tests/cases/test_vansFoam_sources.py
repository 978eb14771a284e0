# SPDX-License-Identifier: GPL-3.0-or-later
"""vansFoam fvOptions, wall heat flux and heat budget (thesis
section 4.2.1, eq. 4.14).

- Hele-Shaw friction (fvOption heleShawFriction, f_l = -gamma u,
  gamma = 12 mu/p^2, thesis eq. 4.14 and its ref. [56]): a 2D channel, no
  grains, slip side walls, driven by a kinematic pressure difference dp over
  the length L reaches the uniform plane-Poiseuille gap-averaged (Darcy)
  velocity u = (dp/L) p^2/(12 nu) (dp kinematic; = (dP/dx) p^2/(12 mu) with
  the dynamic pressure P) within 1e-6 relative.
- Front/rear wall heat (thesis eq. 4.14, q_l = lambda (T_w - T)) as the
  standard scalarSemiImplicitSource on T (volumeMode specific,
  Su = lambda T_w/(rho Cp), Sp = -lambda/(rho Cp)): a fluid at rest in an
  adiabatic box relaxes to T_w.  OpenFOAM v1912 builds the source as
  Su + fvm::SuSp(Sp, T), which treats a negative Sp explicitly (fvmSup.C),
  so the discrete solution is the explicit-Euler recursion
  T^{n+1} - T_w = (1 - k dt)(T^n - T_w), k = lambda/(rho Cp): checked to
  1e-9 relative, and against exp(-k t) within the first-order error
  (k dt)/2 k t (< 1 %); the logged source heat equals rho Cp V dT (1e-9).
- convectiveHeatFlux (Newton/Robin wall, q_w = h (T_inf - T), thesis 4.2.1):
  steady 1D conduction through a fluid slab at rest (eps = 1) between a wall
  at T_1 and the convective wall: T(x) = T_1 - q x/kappa,
  q = (T_1 - T_inf)/(L/kappa + 1/h), interface temperature
  T(L) = (T_1 + Bi T_inf)/(1 + Bi), Bi = h L/kappa (e.g. Incropera,
  Fundamentals of Heat and Mass Transfer, section 3.1, plane wall with
  convection): cell temperatures, the wall face temperature and the logged
  patch heat rates within 1e-6 (of T_1 - T_inf, resp. of q A).
- Heat budget (issue 5: "fluid + grain + wall-flux budget closes to 1e-6
  relative"): closed 2D box, hot grains settling in water, one
  convectiveHeatFlux wall, one fixed-temperature wall, a fixed-temperature
  grain wall (contact conduction, thesis eq. 4.2), a semiImplicitSource on T
  and the Hele-Shaw friction: E(t) - E(0) (E = fluid rho Cp sum(eps T V) +
  grain sum(m c T), the "heat:" line) equals the time integral of the
  logged budget (fluid boundary + advected + sources + grain walls + fixed
  grains) within 1e-6 of the heat exchanged between fluid and grains.
- Parallel (mpirun -np 2) the same case gives the serial grain mean
  temperature history within 1e-8 relative (skipped without mpirun).
- Keyword errors: missing / non-positive gap, missing / negative h: the
  run stops with a FatalIOError naming the file, the keyword and the fix.
"""

import math
import os
import re
import shutil

import nscdpost
import pytest
from foamcase import (
    add_fluid,
    heat_cell_case,
    log_message,
    make_box_case,
    read_internal,
    run,
    run_parallel,
    write,
)
from test_vansFoam_heat import add_heat, heat_lines, set_materials

pytestmark = pytest.mark.fast

FACES = {"bottom": "(1 5 4 0)", "left": "(0 4 7 3)", "right": "(2 6 5 1)", "top": "(3 7 6 2)"}


def set_patches(case, kinds):
    """Replace the boundary of a 2D make_box_case mesh: kinds maps
    bottom/left/right/top to a polyPatch type (wall, patch)."""
    bm = os.path.join(case, "system", "blockMeshDict")
    txt = open(bm).read()
    bnd = "".join(f"{n} {{ type {t}; faces ({FACES[n]}); }}\n" for n, t in kinds.items())
    bnd += "frontAndBack { type empty; faces ((0 3 2 1) (4 5 6 7)); }\n"
    txt = re.sub(r"boundary \(.*\);", "boundary (\n" + bnd + ");", txt, flags=re.S)
    open(bm, "w").write(txt)


def field(case, name, dims, internal, patches):
    cls = "volVectorField" if internal.startswith("(") else "volScalarField"
    body = "".join(f"    {n} {{ {v} }}\n" for n, v in patches.items())
    write(
        os.path.join(case, "0", name),
        cls,
        name,
        f"dimensions {dims};\ninternalField uniform {internal};\n"
        f"boundaryField {{\n{body}    frontAndBack {{ type empty; }}\n}}\n",
    )


def set_control(case, **kw):
    cd = os.path.join(case, "system", "controlDict")
    txt = open(cd).read()
    for k, v in kw.items():
        if re.search(rf"\b{k}\s+[^;]*;", txt):
            txt = re.sub(rf"\b{k}\s+[^;]*;", f"{k} {v};", txt)
        else:
            txt += f"{k} {v};\n"
    open(cd, "w").write(txt)


def no_grains(case):
    write(
        os.path.join(case, "system", "grainDepositDict"),
        "dictionary",
        "grainDepositDict",
        "material grains;\nmethod list;\ngrains ();\n",
    )


def read_patch_value(path, patch):
    txt = open(path).read()
    block = re.search(patch + r"\s*\{(.*?)\}", txt.split("boundaryField", 1)[1], re.S).group(1)
    m = re.search(r"value\s+nonuniform\s+List<scalar>\s*\d+\s*\((.*?)\)", block, re.S)
    if m:
        return [float(v) for v in m.group(1).split()]
    return [float(re.search(r"value\s+uniform\s+(\S+);", block).group(1))]


def budget_lines(case):
    """Per step: dict of the heat budget's terms [J] and the budget patches'
    rates [W] (heatBudget.dat, nscdpost.heat_history)."""
    h = nscdpost.heat_history(case)
    keys = ("boundary", "advected", "sources", "grainWalls", "fixedGrains")
    return [
        dict(zip(keys, v), total=float(sum(v)), patches=p)
        for v, p in zip(h["budget"].tolist(), h["patches"])
    ]


def fv_options(case, body):
    write(os.path.join(case, "constant", "fvOptions"), "dictionary", "fvOptions", body)


# --------------------------------------------------------------------------- Hele-Shaw


def hele_shaw_channel(case, env, gap="gap 1e-3;"):
    L, H, depth = 0.1, 0.02, 0.001
    make_box_case(
        case,
        (0, 0, 0),
        (L, H, depth),
        (20, 4, 1),
        (0, 0, 0),
        {"grains": {"density": 2500, "friction": 0.3}},
        grains=[],
        end_time=2.0,
        dt=0.02,
        write_interval=2.0,
    )
    no_grains(case)
    add_fluid(case, 1000.0, 1e-6, max_co=0.5, max_dt=0.02)
    set_patches(case, {"left": "patch", "right": "patch", "bottom": "wall", "top": "wall"})
    fs = os.path.join(case, "system", "fvSolution")
    txt = open(fs).read().replace("pRefCell 0; pRefValue 0;", "")
    txt = txt.replace("tolerance 1e-9; relTol 0.01;", "tolerance 1e-13; relTol 0;")
    txt = txt.replace("tolerance 1e-9; relTol 0; }", "tolerance 1e-13; relTol 0; }")
    open(fs, "w").write(txt)
    field(
        case,
        "U",
        "[0 1 -1 0 0 0 0]",
        "(0 0 0)",
        {
            "left": "type zeroGradient;",
            "right": "type zeroGradient;",
            "bottom": "type slip;",
            "top": "type slip;",
        },
    )
    field(
        case,
        "p",
        "[0 2 -2 0 0 0 0]",
        "0",
        {
            "left": "type fixedValue; value uniform 0.012;",
            "right": "type fixedValue; value uniform 0;",
            "bottom": "type zeroGradient;",
            "top": "type zeroGradient;",
        },
    )
    fv_options(case, f"friction {{ type heleShawFriction; selectionMode all; {gap} }}\n")
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    return L


def test_hele_shaw_darcy_velocity(tmp_path, env):
    """Uniform channel flow with the Hele-Shaw friction of thesis eq. 4.14:
    steady momentum balance 0 = -dp/dx - (12 nu/p^2) u (kinematic p, no
    grains, slip side walls: no shear), so u = (dp/L) p^2/(12 nu)
    = 0.12 x 1e-6/12e-6 = 0.01 m/s for dp = 0.012 m^2/s^2, L = 0.1 m,
    p = 1 mm, nu = 1e-6 m^2/s.  Within 1e-6 relative in every cell (the
    transient decays as (1 + 12 nu/p^2 dt)^-n, 1e-10 after 100 steps)."""
    case = str(tmp_path / "hs")
    L = hele_shaw_channel(case, env)
    log = run("vansFoam", case, env).stdout
    assert "heleShawFriction friction: gap 0.001 m" in log
    U = open(os.path.join(case, "2", "U")).read()
    m = re.search(r"internalField\s+nonuniform\s+List<vector>\s*\d+\s*\((.*?)\)\s*;", U, re.S)
    ux = [float(v[0]) for v in re.findall(r"\(\s*(\S+)\s+(\S+)\s+(\S+)\s*\)", m.group(1))]
    u_ref = 0.012 / L * 1e-3**2 / (12 * 1e-6)
    err = max(abs(u - u_ref) / u_ref for u in ux)
    print(
        f"u_ref {u_ref:.6g} m/s, cells {len(ux)}, u {min(ux):.12g}..{max(ux):.12g}, "
        f"max rel. error {err:.2e}"
    )
    assert len(ux) == 80
    assert err < 1e-6


@pytest.mark.parametrize(
    "gap,expect",
    [
        ("", "Missing keyword 'gap'"),
        ("gap -0.01;", "Keyword 'gap'"),
        ("gap 1e-3; gapp 2;", "Unknown keyword 'gapp'"),
    ],
)
def test_hele_shaw_keyword_errors(tmp_path, env, gap, expect):
    """Bad heleShawFriction input stops vansFoam with a FatalIOError naming
    constant/fvOptions, the keyword and the fix."""
    case = str(tmp_path / "hs")
    hele_shaw_channel(case, env, gap=gap)
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert expect in out
    assert "constant/fvOptions" in out
    assert "FOAM FATAL IO ERROR" in out
    if "Unknown" not in expect:
        assert "Fix:" in out


# --------------------------------------------------------------------------- heat

RHO, NU, CP, KAPPA = 1000.0, 1e-6, 4186.0, 0.6


def resting_fluid_box(case, env, L, H, nx, ny, end, dt, T_bc, T0, kinds):
    depth = 0.001
    make_box_case(
        case,
        (0, 0, 0),
        (L, H, depth),
        (nx, ny, 1),
        (0, 0, 0),
        {"grains": {"density": 2500, "friction": 0.3}},
        grains=[],
        end_time=end,
        dt=dt,
        write_interval=end,
    )
    no_grains(case)
    set_materials(
        case,
        "grains { density 2500; friction 0.3; conductivity 1; heatCapacity 800; }",
        "initialTemperature 300;\n",
    )
    add_fluid(case, RHO, NU)
    set_patches(case, kinds)
    set_control(case, adjustTimeStep="no")
    noslip = {n: "type noSlip;" for n in kinds}
    field(case, "U", "[0 1 -1 0 0 0 0]", "(0 0 0)", noslip)
    field(
        case,
        "p",
        "[0 2 -2 0 0 0 0]",
        "0",
        {n: "type fixedFluxPressure; value uniform 0;" for n in kinds},
    )
    add_heat(case, CP, KAPPA, "", T0)
    field(case, "T", "[0 0 0 1 0 0 0]", str(T0), T_bc)
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    return depth


def test_semi_implicit_source_relaxation(tmp_path, env):
    """q_l = lambda (T_w - T) of thesis eq. 4.14 through the standard v1912
    scalarSemiImplicitSource (volumeMode specific, Su = lambda T_w/(rho Cp),
    Sp = -lambda/(rho Cp)) on a uniform fluid at rest (no grains, adiabatic
    walls): dT/dt = k (T_w - T), k = lambda/(rho Cp) = 1 1/s.  v1912's
    Su + fvm::SuSp(Sp, T) makes a negative Sp explicit, so the discrete
    solution is T^{n+1} - T_w = (1 - k dt)(T^n - T_w): checked to 1e-9
    relative; against the exact exp(-k t) within 1 % (first order,
    (k dt)/2 k t = 0.5 % at t = 1 s, dt = 0.01 s).  The logged source heat of
    every step equals rho Cp V (T^{n+1} - T^n) within 1e-9 relative."""
    case = str(tmp_path / "relax")
    T0, Tw, k, dt = 350.0, 290.0, 1.0, 0.01
    lam = k * RHO * CP
    depth = resting_fluid_box(
        case,
        env,
        0.02,
        0.02,
        2,
        2,
        1.0,
        dt,
        {n: "type zeroGradient;" for n in ("left", "right", "bottom", "top")},
        T0,
        {n: "wall" for n in ("left", "right", "bottom", "top")},
    )
    fv_options(
        case,
        "frontRearWallHeat\n{\n type scalarSemiImplicitSource; selectionMode all;\n"
        " volumeMode specific;\n"
        f" injectionRateSuSp {{ T ({lam * Tw / (RHO * CP):.17g} {-lam / (RHO * CP):.17g}); }}\n}}\n",
    )
    run("vansFoam", case, env)
    steps = heat_lines(case)
    budget = budget_lines(case)
    assert len(steps) == len(budget) == 100
    V = 0.02 * 0.02 * depth
    worst_discrete = worst_exact = worst_src = 0
    T_prev = T0
    for n, ((t, _Tg, Tf, _Q, _E), b) in enumerate(zip(steps, budget), start=1):
        discrete = Tw + (T0 - Tw) * (1 - k * dt) ** n
        exact = Tw + (T0 - Tw) * math.exp(-k * t)
        worst_discrete = max(worst_discrete, abs(Tf - discrete) / (T0 - Tw))
        worst_exact = max(worst_exact, abs(Tf - exact) / (exact - Tw))
        dE = RHO * CP * V * (Tf - T_prev)
        worst_src = max(worst_src, abs(b["sources"] - dE) / abs(dE))
        T_prev = Tf
    print(
        f"T(1 s) = {steps[-1][2]:.10g} K, discrete recursion error {worst_discrete:.2e}, "
        f"vs exp(-kt) {worst_exact:.2e} of T - T_w, source heat vs rho Cp V dT {worst_src:.2e}"
    )
    assert worst_discrete < 1e-9
    assert worst_exact < 0.01
    assert worst_src < 1e-9


def test_convective_wall_slab(tmp_path, env):
    """Steady conduction through a fluid slab at rest, eps = 1, between a
    wall at T_1 = 350 K (x = 0, fixedValue) and a convectiveHeatFlux wall at
    x = L (h = 350 W m^-2 K^-1, T_inf = 290 K), adiabatic top/bottom:
    q = (T_1 - T_inf)/(L/kappa + 1/h), T(x) = T_1 - q x/kappa,
    T(L) = (T_1 + Bi T_inf)/(1 + Bi), Bi = h L/kappa = 5.833 (L = 1 cm,
    kappa = 0.6 W/(m K)).  The finite-volume solution of a linear profile
    is exact, so the cell values, the wall face value and the logged patch
    heat rates (+q A in at x = 0, -q A at x = L) match within 1e-6 (of
    T_1 - T_inf and q A).  Implicit Euler with dt = 1000 s, 40 steps
    (diffusion time L^2/alpha = 700 s)."""
    case = str(tmp_path / "slab")
    L, H, nx = 0.01, 0.002, 10
    T1, Tinf, h = 350.0, 290.0, 350.0
    depth = resting_fluid_box(
        case,
        env,
        L,
        H,
        nx,
        1,
        40000,
        1000,
        {
            "left": f"type fixedValue; value uniform {T1};",
            "right": f"type convectiveHeatFlux; h {h}; Tinf {Tinf}; value uniform {Tinf};",
            "bottom": "type zeroGradient;",
            "top": "type zeroGradient;",
        },
        Tinf,
        {"left": "wall", "right": "wall", "bottom": "wall", "top": "wall"},
    )
    run("vansFoam", case, env)
    Bi = h * L / KAPPA
    q = (T1 - Tinf) / (L / KAPPA + 1 / h)
    Ti = (T1 + Bi * Tinf) / (1 + Bi)
    assert abs(Ti - (T1 - q * L / KAPPA)) < 1e-12 * T1
    T = read_internal(os.path.join(case, "40000", "T"))
    assert len(T) == nx
    dx = L / nx
    err_cells = max(abs(Tc - (T1 - q * (i + 0.5) * dx / KAPPA)) for i, Tc in enumerate(T)) / (
        T1 - Tinf
    )
    Tb = read_patch_value(os.path.join(case, "40000", "T"), "right")
    err_face = max(abs(v - Ti) for v in Tb) / (T1 - Tinf)
    b = budget_lines(case)[-1]
    A = H * depth
    err_hot = abs(b["patches"]["left"][0] - q * A) / (q * A)
    err_cold = abs(b["patches"]["right"][0] + q * A) / (q * A)
    print(
        f"Bi {Bi:.4g}, T(L) {Ti:.10g} K (face {Tb[0]:.10g}), q {q:.6g} W/m^2; errors: cells {err_cells:.2e},"
        f" face {err_face:.2e}, heat in at x=0 {err_hot:.2e}, out at x=L {err_cold:.2e}"
    )
    assert err_cells < 1e-6
    assert err_face < 1e-6
    assert err_hot < 1e-6 and err_cold < 1e-6


@pytest.mark.parametrize(
    "bc,expect",
    [
        ("Tinf 290;", "Missing keyword 'h'"),
        ("h -1; Tinf 290;", "Keyword 'h'"),
        ("h 10; Tinf 290; kappa 1;", "Unknown keyword 'kappa'"),
    ],
)
def test_convective_wall_keyword_errors(tmp_path, env, bc, expect):
    """Bad convectiveHeatFlux input: FatalIOError naming 0/T, the keyword and the fix."""
    case = str(tmp_path / "slab")
    resting_fluid_box(
        case,
        env,
        0.01,
        0.002,
        4,
        1,
        2,
        1,
        {
            "left": "type fixedValue; value uniform 300;",
            "right": f"type convectiveHeatFlux; {bc} value uniform 300;",
            "bottom": "type zeroGradient;",
            "top": "type zeroGradient;",
        },
        300,
        {"left": "wall", "right": "wall", "bottom": "wall", "top": "wall"},
    )
    p = run("vansFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0
    assert "FOAM FATAL IO ERROR" in out and expect in out
    log_message(out, r"0/T")
    if "Unknown" not in expect:
        assert "Fix:" in out


# --------------------------------------------------------------------------- budget


def budget_box(case, env, end=0.05):
    """Closed 2D box (0.04 x 0.06 m, 9 x 13 cells): 16 hot grains (350 K), 8
    resting on the bottom wall, in water at 300 K; left wall convective
    (h = 350, T_inf = 290 K), right wall fixedValue 320 K, bottom/top
    adiabatic for the fluid; the bottom wall at 330 K for the grains
    (contact conduction); q_l = lambda (T_w - T) with lambda = 4e5 W m^-3
    K^-1, T_w = 290 K; Hele-Shaw friction p = 3 mm; Boussinesq on."""
    r = 1.5e-3
    rhop, cp = 1500.0, 800.0
    Tf0, T0 = 300.0, 350.0
    depth = 0.003
    grains = [
        (0.005 + (2 * i + 1) * r * 1.0001, (2 * j + 1) * r * 1.0001 + (0.02 if j else 0), 0, 2 * r)
        for j in range(2)
        for i in range(8)
    ]
    heat_cell_case(case, grains, rhop, depth, end)
    set_materials(
        case,
        f"grains {{ density {rhop}; friction 0.3; conductivity 1; heatCapacity {cp};"
        " youngModulus 1e8; poissonRatio 0.3; }",
        f"initialTemperature {T0};\nwallTemperatures {{ bottom 330; }}\n",
    )
    kinds = {n: "wall" for n in ("left", "right", "bottom", "top")}
    add_fluid(case, RHO, NU)
    set_patches(case, kinds)
    field(case, "U", "[0 1 -1 0 0 0 0]", "(0 0 0)", {n: "type noSlip;" for n in kinds})
    field(
        case,
        "p",
        "[0 2 -2 0 0 0 0]",
        "0",
        {n: "type fixedFluxPressure; value uniform 0;" for n in kinds},
    )
    add_heat(case, CP, KAPPA, "", Tf0, "beta 2e-4;\nTRef 300;\n")
    field(
        case,
        "T",
        "[0 0 0 1 0 0 0]",
        str(Tf0),
        {
            "left": "type convectiveHeatFlux; h 350; Tinf 290; value uniform 300;",
            "right": "type fixedValue; value uniform 320;",
            "bottom": "type zeroGradient;",
            "top": "type zeroGradient;",
        },
    )
    lam, Tw = 4e5, 290.0
    fv_options(
        case,
        "friction { type heleShawFriction; selectionMode all; gap 0.003; }\n"
        "frontRearWallHeat\n{\n type scalarSemiImplicitSource; selectionMode all;\n"
        " volumeMode specific;\n"
        f" injectionRateSuSp {{ T ({lam * Tw / (RHO * CP):.17g} {-lam / (RHO * CP):.17g}); }}\n}}\n",
    )
    # utilities (decomposePar) need the library of convectiveHeatFlux
    set_control(case, libs='("libvansCoupling.so")')
    run("blockMesh", case, env)
    run("grainDeposit", case, env)
    n = len(grains)
    Vp = math.pi * r * r * depth
    E0 = RHO * CP * Tf0 * (0.04 * 0.06 * depth - n * Vp) + n * rhop * Vp * cp * T0
    return E0


def test_heat_budget_closes(tmp_path, env):
    """Global energy balance of a closed run with walls (issue 5): with
    E = rho Cp sum(eps T V) + sum(m c T) (the 'heat:' line) and the logged
    step budget B = fluid boundary + advected + sources + grain walls +
    fixed grains (the discrete fluxes of TEqn with the end-of-step T, and
    the NSCD wall heat), E(t_n) - E(0) = sum_{k<=n} B_k within 1e-6 of the
    heat exchanged between fluid and grains sum |Q|, at every step.  Every
    budget term must be active (non-zero)."""
    case = str(tmp_path / "budget")
    E0 = budget_box(case, env)
    run("vansFoam", case, env)
    steps = heat_lines(case)
    budget = budget_lines(case)
    assert len(steps) == len(budget) >= 20
    cum = 0.0
    worst = 0.0
    for (_t, _Tg, _Tf, _Q, E), b in zip(steps, budget):
        cum += b["total"]
        worst = max(worst, abs(E - E0 - cum))
    Qx = sum(abs(s[3]) for s in steps)
    tot = {k: sum(b[k] for b in budget) for k in ("boundary", "advected", "sources", "grainWalls")}
    left = sum(b["patches"]["left"][0] for b in budget) * 1e-3
    right = sum(b["patches"]["right"][0] for b in budget) * 1e-3
    print(
        f"E0 {E0:.10g} J, E_end - E0 {steps[-1][4] - E0:.6g} J, exchanged sum|Q| {Qx:.6g} J; "
        f"boundary {tot['boundary']:.6g} J (left/convective {left:.6g}, right/fixed {right:.6g}), "
        f"advected {tot['advected']:.3g} J, sources {tot['sources']:.6g} J, grain walls "
        f"{tot['grainWalls']:.6g} J; max |E - E0 - sum B| {worst:.3e} J = {worst / Qx:.2e} of sum|Q|"
    )
    assert tot["sources"] < 0 and left < 0 and right > 0 and tot["grainWalls"] < 0
    assert abs(tot["advected"]) < 1e-9 * Qx  # closed box: no flux through walls
    assert worst < 1e-6 * Qx


@pytest.mark.mpi
def test_parallel_heat_matches_serial(tmp_path, env):
    """The budget case (heat, convective wall, fvOptions, grains) on 2 ranks
    (decomposePar, mpirun -np 2 -parallel) gives the serial grain mean
    temperature history within 1e-8 relative at every step; the parallel
    budget closes like the serial one (1e-6 of sum |Q|).  The fluid
    solutions differ by the solver tolerances only (p to 1e-12, T to 1e-14
    here), far below 1e-8 of T."""
    serial = str(tmp_path / "serial")
    E0 = budget_box(serial, env, end=0.03)
    fs = os.path.join(serial, "system", "fvSolution")
    txt = open(fs).read().replace("tolerance 1e-9; relTol 0.01;", "tolerance 1e-12; relTol 0;")
    open(fs, "w").write(txt.replace("tolerance 1e-9; relTol 0; }", "tolerance 1e-12; relTol 0; }"))
    par = str(tmp_path / "parallel")
    shutil.copytree(serial, par)
    run("vansFoam", serial, env)
    run_parallel("vansFoam", par, env)
    hs, hp = heat_lines(serial), heat_lines(par)
    assert len(hs) == len(hp) >= 15
    assert all(abs(a[0] - b[0]) < 1e-12 for a, b in zip(hs, hp))
    rel = max(abs(a[1] - b[1]) / a[1] for a, b in zip(hs, hp))
    dT = max(abs(a[1] - hs[0][1]) for a in hs)
    relchg = max(abs(a[1] - b[1]) for a, b in zip(hs, hp)) / dT
    bp = budget_lines(par)
    cum, worst = 0.0, 0.0
    for s, b in zip(hp, bp):
        cum += b["total"]
        worst = max(worst, abs(s[4] - E0 - cum))
    Qx = sum(abs(s[3]) for s in hp)
    print(
        f"grain mean T serial {hs[-1][1]:.12g} parallel {hp[-1][1]:.12g} K: max rel. difference "
        f"{rel:.2e} (of T), {relchg:.2e} of the grain temperature change; parallel budget "
        f"{worst / Qx:.2e} of sum|Q|"
    )
    assert rel < 1e-8
    assert worst < 1e-6 * Qx
