# SPDX-License-Identifier: GPL-3.0-or-later
"""grainFoam contact conduction through the OpenFOAM path (thesis
section 4.1.1, eq. 4.1-4.3): grainProperties `wallTemperatures` -> the nscd
walls of the named patches -> steady conduction through a static column.

Case (2D, discs per unit depth): a vertical column of N equal frictionless
discs (d = 1 mm) stands on the floor (patch `bottom`, T_hot = 400 K) and is
pushed against the right wall (patch `right`, T_cold = 300 K) by a tilted
gravity g = (g_x, -g_y); left and top (patch `walls`) are adiabatic (not
listed). Frictionless and static, the contact impulses are known in closed
form (dt = time step, m = rho pi d^2/4):
    floor:                 r_n = N m g_y dt
    grain k - grain k+1:   r_n = (N - k) m g_y dt      (k = 1 bottom .. N-1)
    grain k - right wall:  r_n = m g_x dt
Conductances written here from eq. 4.2-4.3 as nscd implements them (L = 1
per unit depth; k_s = k for equal grains; a wall has infinite radius and
Young modulus: d* = d, 1/E* = (1 - nu^2)/E; two grains: d* = d/2,
1/E* = 2 (1 - nu^2)/E):
    H = 4 k_s (r_n d* / (2 pi E* dt))^(1/4)
Steady state: the ladder network  H_f (T_hot - T_1) + sum_j H_kj (T_j - T_k)
+ H_w (T_cold - T_k) = 0  (tridiagonal, solved with numpy). Checked:
  - grain temperatures (lagrangian field T) within 1e-3 (T_hot - T_cold),
  - heat rate through the hot floor (log, per patch) = H_f (T_hot - T_1)
    within 1 %, equal and opposite to the rate through the right wall (1 %),
  - total wall heat of the step ~ 0 (steady) and the mean grain T in the log.
"""

import math
import os

import nscdpost
import numpy as np
import pytest
from foamcase import make_box_case, replace_in, run

pytestmark = pytest.mark.fast

N = 5
D = 1e-3
RHO, E, NU, K, C = 2500.0, 6e10, 0.22, 1.4, 0.01  # small c: fast transient
GX, GY = 3.0, 9.81
T_HOT, T_COLD, T0 = 400.0, 300.0, 300.0
DT = 1e-3


def conductance(rn, dt, wall):
    dstar = D if wall else D / 2
    estar = E / (1 - NU**2) if wall else E / (2 * (1 - NU**2))
    return 4 * K * (rn * dstar / (2 * math.pi * estar * dt)) ** 0.25


def steady_profile(bath=None):
    """Steady grain temperatures of the ladder network and the heat rates
    through the floor and the right wall [W/m]; bath = (G, T_w): every grain
    also exchanges G (T_w - T_k) with the front and rear walls
    (grainProperties frontRearWalls, G = m c/tau)."""
    m = RHO * math.pi * D**2 / 4
    Hf = conductance(N * m * GY * DT, DT, True)
    Hw = conductance(m * GX * DT, DT, True)
    Hg = [conductance((N - k) * m * GY * DT, DT, False) for k in range(1, N)]
    A = np.zeros((N, N))
    b = np.zeros(N)
    A[0, 0] += Hf
    b[0] += Hf * T_HOT
    for k in range(N):
        A[k, k] += Hw
        b[k] += Hw * T_COLD
    for k, H in enumerate(Hg):
        A[k, k] += H
        A[k + 1, k + 1] += H
        A[k, k + 1] -= H
        A[k + 1, k] -= H
    if bath:
        A += bath[0] * np.eye(N)
        b += bath[0] * bath[1]
    T = np.linalg.solve(A, b)
    return T, Hf * (T_HOT - T[0]), Hw * (T_COLD - T).sum()


def column_case(tmp_path, env, name, deposit_material=None, extra_props=""):
    """The column case, deposited; deposit_material: the grainProperties
    material line grainDeposit sees (default: the test's own), replaced by
    the test's own afterwards (a state reused with edited properties);
    extra_props: more grainProperties entries for the run."""
    W, Hbox = 4 * D, (N + 2) * D
    r = D / 2
    case = str(tmp_path / name)
    grains = [(W - r, r + k * D, 0.0, D) for k in range(N)]
    make_box_case(
        case,
        (0, 0, 0),
        (W, Hbox, D),
        (4, N + 2, 1),
        (GX, -GY, 0),
        {"glass": {"density": RHO, "friction": 0.0}},
        grains=grains,
        end_time=0.6,
        dt=DT,
        write_interval=0.6,
        two_d=True,
        contact_tolerance=1e-10,
    )
    replace_in(
        os.path.join(case, "system", "blockMeshDict"),
        (
            "walls { type wall; faces ((1 5 4 0) (0 4 7 3) (2 6 5 1) (3 7 6 2)); }",
            "bottom { type wall; faces ((1 5 4 0)); }\n"
            "right { type wall; faces ((2 6 5 1)); }\n"
            "walls { type wall; faces ((0 4 7 3) (3 7 6 2)); }",
        ),
    )
    gp = os.path.join(case, "constant", "grainProperties")
    base = open(gp).read()
    own = (
        f"density {RHO}; friction 0.0; youngModulus {E}; poissonRatio {NU};"
        f" conductivity {K}; heatCapacity {C}; }}"
    )
    # a regex entry for the floor, a plain name for the right wall
    extra = f'initialTemperature {T0};\nwallTemperatures {{ "bot.*" {T_HOT}; right {T_COLD}; }}\n'
    mat = f"density {RHO}; friction 0.0; }}"
    assert mat in base
    open(gp, "w").write(base.replace(mat, deposit_material or own) + extra)
    run("blockMesh", case, env)
    dep = run("grainDeposit", case, env).stdout
    open(gp, "w").write(base.replace(mat, own) + extra + extra_props)
    return case, dep


def check_column(case, log):
    assert "wall patch bottom at 400 K (1 walls)" in log
    assert "wall patch right at 300 K (1 walls)" in log
    heat = nscdpost.read_step_data(case, "grainHeat")
    assert len(heat["Time"]) == 600
    Tm, Qstep, qb, qr = (
        heat[k][-1] for k in ("grainMeanT", "wallHeat", "bottom_rate", "right_rate")
    )

    T_exp, q_hot, q_cold = steady_profile()
    assert q_hot > 0 and abs(q_hot + q_cold) < 1e-9 * q_hot
    g = nscdpost.read_grains(case, "0.6")
    order = np.argsort([x[1] for x in g["x"]])
    T_sim = nscdpost.read_scalar_field(os.path.join(case, "0.6", "lagrangian", "grains", "T"))[
        order
    ]
    assert np.abs(T_sim - T_exp).max() < 1e-3 * (T_HOT - T_COLD)
    assert abs(qb - q_hot) < 0.01 * q_hot
    assert abs(qr - q_cold) < 0.01 * q_hot
    assert abs(Qstep) < 1e-3 * q_hot * DT
    assert abs(Tm - T_exp.mean()) < 1e-3 * (T_HOT - T_COLD)
    # static: the grains did not move
    r = D / 2
    y = np.sort([x[1] for x in g["x"]])
    assert np.allclose(y, [r + k * D for k in range(N)], atol=1e-3 * r)


def test_column_steady_conduction(tmp_path, env):
    case, _ = column_case(tmp_path, env, "column")
    check_column(case, run("grainFoam", case, env).stdout)


def test_state_takes_edited_materials(tmp_path, env):
    """A state written with other materials (here grainDeposit with density
    1000 and no youngModulus: contact conduction off, which grainCloud warns
    about) takes constant/grainProperties' materials when a run starts from
    it (as tutorials/vansFoam/dropletDigging reuses one deposit with another
    grain density): grain masses recomputed, so the impulses, the eq. 4.2
    conductances and the steady heat rate are those of density 2500 (the
    rate scales as rho^(1/4): density 1000 would be 20 % low, the state's
    materials unchanged would give no conduction at all)."""
    case, dep = column_case(
        tmp_path, env, "edited", deposit_material="density 1000; friction 0.0; conductivity 1.4; }"
    )
    assert "no youngModulus: contact conduction" in dep
    log = run("grainFoam", case, env).stdout
    assert (
        "grainCloud: material glass (id 0) of constant/grainProperties replaces the one"
        " in 0/grainState.h5: density 1000 -> 2500, youngModulus 0 -> 60000000000, poissonRatio"
        " 0 -> 0.22, heatCapacity 0 -> 0.01 (grain masses recomputed)"
    ) in log, log[-3000:]
    check_column(case, log)
    # the state written by the run holds the new materials: a restart is exact
    assert "replaces" not in run("grainFoam", case, env).stdout


def test_state_material_count_mismatch(tmp_path, env):
    """Materials are matched by order: a grainProperties listing another number
    of materials than the state is refused with the file and the fix."""
    case, _ = column_case(tmp_path, env, "count")
    gp = os.path.join(case, "constant", "grainProperties")
    txt = open(gp).read()
    i = txt.index("materials")
    j = txt.index("{", i) + 1
    open(gp, "w").write(txt[:j] + " sand { density 2600; friction 0.5; } " + txt[j:])
    p = run("grainFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0 and "FOAM FATAL" in out
    for w in ("holds 1 materials", "lists 2", "grainProperties", "re-run grainDeposit"):
        assert w in out, out[-2000:]


def test_column_front_rear_walls(tmp_path, env):
    """grainProperties frontRearWalls (src/grainCloud: the front and rear
    walls of a 2D Hele-Shaw cell as a heat bath, Q_i = (m_i c_i/tau)(T_w -
    T_i), implicit): the column of test_column_steady_conduction with
    T_w = 350 K and tau chosen so that G = m c/tau equals the floor's
    contact conductance.  Reference: the ladder network with G (T_w - T_k)
    on every node (steady_profile(bath)), solved with numpy:
    - grain temperatures within 1e-3 (T_hot - T_cold),
    - the log's "front/rear walls = Q J" of the last step (nscd
      StepReport::exchangeHeat) equals dt sum G (T_w - T_k) within 1 % of
      the floor's rate, and floor + right wall + bath ~ 0 (steady);
    - a relaxationTime <= 0 is a FatalIOError naming the keyword."""
    m = RHO * math.pi * D**2 / 4
    G = conductance(N * m * GY * DT, DT, True)
    tau, Tw = m * C / G, 350.0
    props = f"frontRearWalls {{ temperature {Tw}; relaxationTime {tau:.17g}; }}\n"
    case, _ = column_case(tmp_path, env, "bath", extra_props=props)
    log = run("grainFoam", case, env).stdout
    assert f"front and rear walls (Hele-Shaw cell) at {Tw:g} K" in log
    heat = nscdpost.read_step_data(case, "grainHeat")
    assert len(heat["Time"]) == 600
    Qwall, Qbath, qb, qr = (
        heat[k][-1] for k in ("wallHeat", "frontRearHeat", "bottom_rate", "right_rate")
    )
    T_exp, q_hot, q_cold = steady_profile((G, Tw))
    q_bath = G * (Tw - T_exp).sum()
    g = nscdpost.read_grains(case, "0.6")
    order = np.argsort([x[1] for x in g["x"]])
    T_sim = nscdpost.read_scalar_field(os.path.join(case, "0.6", "lagrangian", "grains", "T"))[
        order
    ]
    print(
        f"tau {tau:.3e} s; T sim {T_sim}, network {T_exp}; bath {Qbath / DT:.4e} W/m "
        f"(network {q_bath:.4e}), floor {qb:.4e}, right {qr:.4e}"
    )
    assert np.abs(T_sim - T_exp).max() < 1e-3 * (T_HOT - T_COLD)
    assert abs(Qbath / DT - q_bath) < 0.01 * q_hot
    assert abs(q_hot + q_cold + q_bath) < 1e-9 * q_hot  # the network itself
    assert abs(qb + qr + Qbath / DT) < 0.01 * q_hot  # the run: steady
    # bad input
    gp = os.path.join(case, "constant", "grainProperties")
    txt = open(gp).read()
    assert f"relaxationTime {tau:.17g}" in txt
    open(gp, "w").write(txt.replace(f"relaxationTime {tau:.17g}", "relaxationTime -1"))
    p = run("grainFoam", case, env, check=False)
    out = p.stdout + p.stderr
    assert p.returncode != 0 and "FOAM FATAL IO ERROR" in out
    assert "relaxationTime" in out and "frontRearWalls" in out, out[-2000:]
