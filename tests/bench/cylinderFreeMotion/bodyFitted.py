#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Benchmark: the falling cylinder of thesis 3.3.3 on a body-fitted mesh,
with OpenFOAM's own solvers only (pimpleFoam, sixDoFRigidBodyMotion): an
independent reference for the free cylinder's drag against the fixed one's
(issue 59 item 3; see cylinderFreeMotion.py for the resolved-grain runs).

The mesh is a 2D O-grid around the cylinder (D = 5 mm, rho_s/rho_f = 1.01,
nu = 8e-7 m^2/s, the values of tutorials/vansFoam/cylinderSedimentation),
out to a circle of radius 30 D: an unconfined fluid, like Namkoong, Yoo &
Choi (2008).  The modes, all on the same mesh:

  fixed  the cylinder at rest in a uniform stream U_t = 2.501 cm/s entering
         through the lower half of the outer circle (Re 156): the fixed
         drag of Henderson (1995) on this mesh
  free   fluid at rest; the whole mesh moves rigidly with the cylinder
         (sixDoFRigidBodyMotion, innerDistance beyond the mesh), which falls
         from rest, free to translate in the plane and to rotate.  The
         pressure is the dynamic one, so the body carries its net weight:
         gravity (1 - rho_f/rho_s) g on the mass rho_s V.  The lower half
         of the outer circle holds the fluid at rest (U = 0), the upper
         half is an outlet (p = 0).
  norotation  free with the rotation locked
  heavy  free with rho_s/rho_f = 10 under the gravity that gives it the
         light cylinder's net weight, released at U_t: ten times the
         inertia against the lift, so it hardly sways
  forced fixed's stream with the whole mesh swaying sideways as a rigid
         body, x = A sin(2 pi f t), f = St U_t / D (solidBody motion,
         oscillatingLinearMotion): the free light cylinder's sway (A/D
         0.092, St 0.167) or another (setup's last two arguments) imposed
         on a cylinder that cannot otherwise move

A small lateral kick (a velocity of 1 % of U_t across a wake strip, fixed;
a lateral body velocity of 1 % of U_t, free; none for forced, whose sway
breaks the symmetry) starts the shedding early.

usage: bodyFitted.py setup fixed|free|norotation|heavy|forced CASE [cells around] [end time]
           [A/D St (forced)]
       (cd CASE && blockMesh && [setFields (fixed) &&] pimpleFoam)
           one core, 200 cells around, 25 s: fixed ~10 CPU min, free ~45;
           forced ~12 for 20 s
       bodyFitted.py post OUT.json [LABEL:]MODE:CASE ...
           C_D and speed per half second, and over the whole shedding
           periods of the last 10 s: C_D, speed, Strouhal number
"""

import datetime
import json
import math
import os
import sys

import nscdpost
import numpy as np
from foamlib import FoamFile

here = os.path.dirname(os.path.abspath(__file__))
tutorial = os.path.join(here, "..", "..", "..", "tutorials", "vansFoam", "cylinderSedimentation")
setupCase = nscdpost.load_module("cs_setupCase", os.path.join(tutorial, "setupCase.py"))
freeMotion = nscdpost.load_module("cylinderFreeMotion", os.path.join(here, "cylinderFreeMotion.py"))

D, RHO_F, NU, UT = setupCase.D, setupCase.RHO_F, setupCase.NU, setupCase.UT_REF
RHO_S = setupCase.RHO_S  # 1.01 rho_f
G = 9.81
R_OUT = 30 * D  # outer circle [m]
LZ = 1e-3  # mesh thickness [m]; forces are per LZ
MODES = ("fixed", "free", "norotation", "heavy", "forced")
#: the forced mode's default sway: the free light cylinder's lateral
#: amplitude over D and Strouhal number (cylinderFreeMotionBodyFitted.json)
FORCED_AMPLITUDE, FORCED_STROUHAL = 0.092, 0.167
#: rho_s / rho_f of the heavy mode, and the gravity [m/s^2] that gives it the
#: light cylinder's net weight (those of the resolved `heavy` variant)
HEAVY, HEAVY_G = freeMotion.HEAVY, freeMotion.HEAVY_G

HEADER = """FoamFile
{
    version 2.0;
    format ascii;
    class %s;
    object %s;
}
"""


def _write(case, rel, cls, text):
    path = os.path.join(case, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(HEADER % (cls, os.path.basename(rel)) + text)


def block_mesh(n_theta, first_cell, n_r):
    """The O-grid: four blocks between the cylinder and the outer circle,
    split at 0, 90, 180 and 270 degrees; radial grading from first_cell."""
    r = D / 2
    span = R_OUT - r
    # geometric ratio q with first_cell (q^n_r - 1) / (q - 1) = span, by the
    # fixed point q = (1 + (q - 1) span / first_cell)^(1/n_r) (a contraction
    # for these meshes: slope q / (n_r (q - 1)) ~ 0.2 at 100 cells)
    q = 1.05
    for _ in range(100):
        q = (1 + (q - 1) * span / first_cell) ** (1.0 / n_r)
    if abs(first_cell * (q**n_r - 1) / (q - 1) - span) > 1e-9 * span:
        sys.exit("bodyFitted.py: no radial grading found for %d cells" % n_r)
    grading = q ** (n_r - 1)
    verts = []
    for z in (0.0, LZ):
        for rad in (r, R_OUT):
            for k in range(4):
                a = k * math.pi / 2
                verts.append((rad * math.cos(a), rad * math.sin(a), z))
    # index: z-layer * 8 + (0 inner | 4 outer) + k

    def v(z, outer, k):
        return 8 * z + 4 * outer + k % 4

    blocks, edges = [], []
    for k in range(4):
        blocks.append(
            "    hex (%d %d %d %d %d %d %d %d) (%d %d 1) simpleGrading (%.10g 1 1)"
            % (
                v(0, 0, k),
                v(0, 1, k),
                v(0, 1, k + 1),
                v(0, 0, k + 1),
                v(1, 0, k),
                v(1, 1, k),
                v(1, 1, k + 1),
                v(1, 0, k + 1),
                n_r,
                n_theta // 4,
                grading,
            )
        )
        a = (k + 0.5) * math.pi / 2
        for z in (0, 1):
            for outer, rad in ((0, r), (1, R_OUT)):
                edges.append(
                    "    arc %d %d (%.12g %.12g %.12g)"
                    % (
                        v(z, outer, k),
                        v(z, outer, k + 1),
                        rad * math.cos(a),
                        rad * math.sin(a),
                        z * LZ,
                    )
                )

    def face(k, outer):
        if outer:  # x-max face (1 2 6 5) of the hex
            return "(%d %d %d %d)" % (v(0, 1, k), v(0, 1, k + 1), v(1, 1, k + 1), v(1, 1, k))
        return "(%d %d %d %d)" % (v(0, 0, k), v(1, 0, k), v(1, 0, k + 1), v(0, 0, k + 1))

    sides = "\n".join(
        "            (%d %d %d %d)\n            (%d %d %d %d)"
        % (
            v(0, 0, k),
            v(0, 0, k + 1),
            v(0, 1, k + 1),
            v(0, 1, k),
            v(1, 0, k),
            v(1, 1, k),
            v(1, 1, k + 1),
            v(1, 0, k + 1),
        )
        for k in range(4)
    )
    return """convertToMeters 1;
vertices
(
%s
);
blocks
(
%s
);
edges
(
%s
);
boundary
(
    cylinder
    {
        type wall;
        faces ( %s );
    }
    outlet
    {
        type patch;
        faces ( %s %s );
    }
    inlet
    {
        type patch;
        faces ( %s %s );
    }
    frontAndBack
    {
        type empty;
        faces
        (
%s
        );
    }
);
""" % (
        "\n".join("    (%.12g %.12g %.12g)" % p for p in verts),
        "\n".join(blocks),
        "\n".join(edges),
        " ".join(face(k, 0) for k in range(4)),
        face(0, 1),
        face(1, 1),
        face(2, 1),
        face(3, 1),
        sides,
    )


def setup(
    mode, case, n_theta=200, end_time=10.0, amplitude=FORCED_AMPLITUDE, strouhal=FORCED_STROUHAL
):
    if mode not in MODES:
        sys.exit(f"bodyFitted.py: unknown mode {mode}; modes: {', '.join(MODES)}")
    if mode == "forced" and not (amplitude > 0 and strouhal > 0):
        sys.exit(f"bodyFitted.py: forced sway A/D {amplitude:g}, St {strouhal:g}: both must be > 0")
    if os.path.isdir(case) and os.listdir(case):
        sys.exit(f"bodyFitted.py: {case} exists and is not empty; remove it or name another case")
    moving = mode != "fixed"
    stream = mode in ("fixed", "forced")  # a uniform stream of U_t, else fluid at rest
    six_dof = moving and not stream
    h_wall = math.pi * D / n_theta
    _write(
        case, "system/blockMeshDict", "dictionary", block_mesh(n_theta, h_wall / 2, n_theta // 2)
    )
    cyl = "movingWallVelocity" if moving else "noSlip"
    cyl_value = "value uniform (0 0 0);" if moving else ""
    inflow = "(0 %.12g 0)" % UT if stream else "(0 0 0)"
    _write(
        case,
        "0/U",
        "volVectorField",
        """dimensions [0 1 -1 0 0 0 0];
internalField uniform %s;
boundaryField
{
    cylinder { type %s; %s }
    inlet { type fixedValue; value uniform %s; }
    outlet { type inletOutlet; inletValue uniform (0 0 0); value uniform (0 0 0); }
    frontAndBack { type empty; }
}
"""
        % (inflow, cyl, cyl_value, inflow),
    )
    _write(
        case,
        "0/p",
        "volScalarField",
        """dimensions [0 2 -2 0 0 0 0];
internalField uniform 0;
boundaryField
{
    cylinder { type zeroGradient; }
    inlet { type zeroGradient; }
    outlet { type fixedValue; value uniform 0; }
    frontAndBack { type empty; }
}
""",
    )
    if six_dof:
        _write(
            case,
            "0/pointDisplacement",
            "pointVectorField",
            """dimensions [0 1 0 0 0 0 0];
internalField uniform (0 0 0);
boundaryField
{
    cylinder { type calculated; value uniform (0 0 0); }
    inlet { type calculated; value uniform (0 0 0); }
    outlet { type calculated; value uniform (0 0 0); }
    frontAndBack { type empty; }
}
""",
        )
    _write(
        case,
        "constant/transportProperties",
        "dictionary",
        "transportModel Newtonian;\nnu %.12g;\n" % NU,
    )
    _write(case, "constant/turbulenceProperties", "dictionary", "simulationType laminar;\n")
    rho_s, g = (HEAVY * RHO_F, HEAVY_G) if mode == "heavy" else (RHO_S, G)
    mass = rho_s * math.pi * D * D / 4 * LZ
    inertia = mass * D * D / 8
    constraints = "plane { sixDoFRigidBodyMotionConstraint plane; normal (0 0 1); }\n"
    constraints += (
        "        orientation { sixDoFRigidBodyMotionConstraint orientation; }\n"
        if mode == "norotation"
        else "        axis { sixDoFRigidBodyMotionConstraint axis; axis (0 0 1); }\n"
    )
    if mode == "forced":
        _write(
            case,
            "constant/dynamicMeshDict",
            "dictionary",
            """dynamicFvMesh dynamicMotionSolverFvMesh;
motionSolverLibs (fvMotionSolvers);
motionSolver solidBody;   // no cellZone: the entire mesh
solidBodyMotionFunction oscillatingLinearMotion;
amplitude (%.12g 0 0);
omega %.12g;
"""
            % (amplitude * D, 2 * math.pi * strouhal * UT / D),
        )
    elif moving:
        _write(
            case,
            "constant/dynamicMeshDict",
            "dictionary",
            """dynamicFvMesh dynamicMotionSolverFvMesh;
motionSolverLibs (sixDoFRigidBodyMotion);
motionSolver sixDoFRigidBodyMotion;
sixDoFRigidBodyMotionCoeffs
{
    patches (cylinder);
    innerDistance 1e3;   // beyond the mesh: every point moves with the body
    outerDistance 2e3;
    centreOfMass (0 0 %.12g);
    mass %.12g;
    momentOfInertia (%.12g %.12g %.12g);
    velocity (%.12g %.12g 0);
    rho rhoInf;
    rhoInf %.12g;
    g (0 %.12g 0);   // (1 - rho_f/rho_s) g: the pressure is the dynamic one
    report on;
    accelerationRelaxation 0.5;
    solver { type Newmark; }
    constraints
    {
        %s    }
}
"""
            % (
                LZ / 2,
                mass,
                inertia,
                inertia,
                inertia,
                0.01 * UT,
                -UT if mode == "heavy" else 0.0,
                RHO_F,
                -(1 - RHO_F / rho_s) * g,
                constraints,
            ),
        )
    else:
        _write(case, "constant/dynamicMeshDict", "dictionary", "dynamicFvMesh staticFvMesh;\n")
    functions = """    forces
    {
        type forces;
        libs (forces);
        writeControl timeStep;
        writeInterval 10;
        patches (cylinder);
        rho rhoInf;
        rhoInf %.12g;
        CofR (0 0 %.12g);
    }
""" % (RHO_F, LZ / 2)
    if six_dof:
        functions += """    body
    {
        type sixDoFRigidBodyState;
        libs (sixDoFRigidBodyState);
        writeControl timeStep;
        writeInterval 10;
        angleFormat degrees;
    }
"""
    _write(
        case,
        "system/controlDict",
        "dictionary",
        """application pimpleFoam;
startFrom latestTime;
startTime 0;
stopAt endTime;
endTime %.12g;
deltaT 1e-4;
writeControl adjustable;
writeInterval 1;
purgeWrite 0;
writeFormat binary;
writePrecision 10;
writeCompression off;
timeFormat general;
timePrecision 8;
runTimeModifiable no;
adjustTimeStep yes;
maxCo 0.8;
maxDeltaT 2e-3;
functions
{
%s}
"""
        % (end_time, functions),
    )
    _write(
        case,
        "system/fvSchemes",
        "dictionary",
        """ddtSchemes { default backward; }
gradSchemes { default Gauss linear; }
divSchemes
{
    default none;
    div(phi,U) Gauss linearUpwind grad(U);
    div((nuEff*dev2(T(grad(U))))) Gauss linear;
}
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
""",
    )
    _write(
        case,
        "system/fvSolution",
        "dictionary",
        """solvers
{
    p { solver GAMG; smoother GaussSeidel; tolerance 1e-8; relTol 0.01; }
    pFinal { $p; relTol 0; }
    "pcorr.*" { $pFinal; tolerance 1e-6; }
    "(U|UFinal)" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-9; relTol 0; }
    "cellDisplacement.*" { solver GAMG; smoother GaussSeidel; tolerance 1e-8; relTol 0; }
}
PIMPLE
{
    momentumPredictor yes;
    nOuterCorrectors %d;
    nCorrectors 2;
    nNonOrthogonalCorrectors 0;
    correctPhi no;
    moveMeshOuterCorrectors %s;
}
"""
        % (3 if six_dof else 1, "yes" if moving else "no"),
    )
    if not moving:  # the lateral kick: 1 % of U_t across the wake strip
        _write(
            case,
            "system/setFieldsDict",
            "dictionary",
            """defaultFieldValues ( volVectorFieldValue U (0 %.12g 0) );
regions
(
    boxToCell
    {
        box (%.12g %.12g -1) (%.12g %.12g 1);
        fieldValues ( volVectorFieldValue U (%.12g %.12g 0) );
    }
);
"""
            % (UT, -D, 0.5 * D, D, 10 * D, 0.01 * UT, UT),
        )


def _rows(case, function_object, file_name):
    """The rows of a function object's .dat file over every start time
    (restarts), by time: {time: [numbers after the time]}; brackets dropped,
    a later start's rows replacing an earlier one's."""
    root = os.path.join(case, "postProcessing", function_object)
    rows = {}
    for name in sorted(os.listdir(root), key=float):
        for line in open(os.path.join(root, name, file_name)):
            if line.startswith("#") or not line.strip():
                continue
            nums = [float(x) for x in line.replace("(", " ").replace(")", " ").split()]
            rows[nums[0]] = nums[1:]
    return rows


def forced_motion(case):
    """The forced mode's sway amplitude [m] and angular frequency [rad/s],
    read back from CASE/constant/dynamicMeshDict (foamlib)."""
    mesh_dict = FoamFile(os.path.join(case, "constant", "dynamicMeshDict"))
    return float(mesh_dict["amplitude"][0]), float(mesh_dict["omega"])


def history(mode, case):
    """Per forces write: time, drag coefficient, fall speed, lateral velocity."""
    # total force (x, y, z) first
    force = {t: r[:2] for t, r in _rows(case, "forces", "force.dat").items()}
    if mode in ("fixed", "forced"):
        t = np.array(sorted(force))
        fy = np.array([force[x][1] for x in t])
        speed, lateral = np.full(len(t), UT), np.zeros(len(t))
        omega = np.zeros(len(t))
        if mode == "forced":
            amplitude, w = forced_motion(case)
            lateral = amplitude * w * np.cos(w * t)
    else:
        # after the time: centre of rotation (3), centre of mass (3), rotation
        # angle (3), velocity (3), angular velocity (3, degrees/s)
        state = {
            t: r[9:12] + [math.radians(r[14])]
            for t, r in _rows(case, "body", "sixDoFRigidBodyState.dat").items()
        }
        t = np.array(sorted(set(force) & set(state)))
        fy = np.array([force[x][1] for x in t])
        speed = np.array([-state[x][1] for x in t])
        lateral = np.array([state[x][0] for x in t])
        omega = np.array([state[x][3] for x in t])
    cd = fy / (0.5 * RHO_F * speed**2 * D * LZ)
    # the shedding signal: the lift (fixed), the lateral velocity (free)
    signal = np.array([force[x][0] for x in t]) if mode in ("fixed", "forced") else lateral
    return t, cd, speed, lateral, signal, omega


def summary(t, cd, speed, signal, omega, window):
    """Over the whole shedding periods of the last `window` seconds: mean
    C_D, mean speed, shedding frequency, Strouhal number f D / U, largest
    |angular velocity| [rad/s]."""
    s = t >= t[-1] - window
    ts, ss = t[s], signal[s] - signal[s].mean()
    i = np.where((ss[:-1] < 0) & (ss[1:] >= 0))[0]
    if len(i) < 2:
        return None
    tz = ts[i] - ss[i] * (ts[i + 1] - ts[i]) / (ss[i + 1] - ss[i])
    w = (t >= tz[0]) & (t <= tz[-1])
    span = t[w][-1] - t[w][0]
    u = float(np.trapezoid(speed[w], t[w]) / span)
    f = (len(tz) - 1) / (tz[-1] - tz[0])
    return {
        "window": [float(tz[0]), float(tz[-1])],
        "periods": len(tz) - 1,
        "C_D": float(np.trapezoid(cd[w], t[w]) / span),
        "speed": u,
        "shedding_frequency": float(f),
        "strouhal": float(f * D / u),
        "max_angular_velocity": float(np.abs(omega[w]).max()),
    }


def forced_lift(case, t, lift, window=10.0):
    """Forced mode, over the last `window` seconds of the lift force [N]
    at times t [s] (history's signal): the lift coefficient's components at
    the forcing frequency, in phase with the displacement A sin(w t) and
    with the velocity (least squares; the second, positive, is the work the
    fluid does on the swaying cylinder, zero for a free one without
    damping)."""
    amplitude, w = forced_motion(case)
    s = t >= t[-1] - window
    t = t[s]
    cl = lift[s] / (0.5 * RHO_F * UT**2 * D * LZ)
    basis = np.column_stack([np.sin(w * t), np.cos(w * t), np.ones(len(t))])
    (a, b, _), *_ = np.linalg.lstsq(basis, cl, rcond=None)
    return {
        "amplitude_over_D": amplitude / D,
        "strouhal_forced": float(w / (2 * math.pi) * D / UT),
        "lift_in_phase_with_displacement": float(a),
        "lift_in_phase_with_velocity": float(b),
    }


def post(out, pairs):
    modes = {}
    for pair in pairs:
        label, mode, case = (
            pair.split(":", 2) if pair.count(":") >= 2 else (None,) + tuple(pair.split(":", 1))
        )
        t, cd, speed, lateral, signal, omega = history(mode, case)
        modes[label or mode] = {
            "mode": mode,
            "end_time": float(t[-1]),
            "last_10_s": summary(t, cd, speed, signal, omega, 10.0),
            "per_half_second": freeMotion.half_second_rows(t, cd, speed, lateral),
            "columns": freeMotion.HALF_SECOND_COLUMNS,
        }
        if mode == "forced":
            modes[label or mode]["forced_lift"] = forced_lift(case, t, signal)
    result = {
        "benchmark": "cylinderFreeMotion/bodyFitted",
        "date": datetime.date.today().isoformat(),
        "reference": freeMotion.REFERENCE,
        "solver": "OpenFOAM v1912 pimpleFoam (dynamicMotionSolverFvMesh, sixDoFRigidBodyMotion)",
        "command": "bodyFitted.py setup MODE CASE; blockMesh; [setFields;] taskset -c K pimpleFoam; "
        "bodyFitted.py post "
        + " ".join([os.path.basename(out)] + [p.rsplit(":", 1)[0] + ":CASE" for p in pairs]),
        "modes": modes,
    }
    json.dump(result, open(out, "w"), indent=1)
    for m, r in modes.items():
        print(m, r["last_10_s"])


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "setup":
        setup(
            sys.argv[2],
            sys.argv[3],
            int(sys.argv[4]) if len(sys.argv) > 4 else 200,
            float(sys.argv[5]) if len(sys.argv) > 5 else 10.0,
            float(sys.argv[6]) if len(sys.argv) > 6 else FORCED_AMPLITUDE,
            float(sys.argv[7]) if len(sys.argv) > 7 else FORCED_STROUHAL,
        )
    elif len(sys.argv) >= 4 and sys.argv[1] == "post":
        post(sys.argv[2], sys.argv[3:])
    else:
        sys.exit(__doc__)
