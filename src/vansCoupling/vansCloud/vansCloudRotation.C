// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vansCloud, rotation coupling

Description
    couplingProperties `rotationCoupling yes;`: the grain velocity at an
    overlapped cell is the rigid-body velocity v_p + omega_p x r_pc in K v**
    and in the solid flux, and the fluid torque T_p = sum_c r_pc x f_pc of
    the overlap-distributed force is handed to the grains (see vansCloud.H,
    "Rotation coupling").  Decomposed grains: a grain's torque is summed
    over its copies on the ranks whose cells it overlaps, as the drag.
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"
#include "foamTools.H"
#include "PstreamReduceOps.H"

// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

Foam::vector Foam::vansCloud::leverArm(const std::size_t e) const
{
    const nscd::System& s = grains_.system();
    const label gi = adapter_.entryGrain()[e];
    vector r =
        mesh_.C()[adapter_.entryCell()[e]]
      - foamTools::toVector(s.positions()[gi]);
    if (adapter_.twoD())
    {
        r.z() = 0;
    }
    return r;
}


void Foam::vansCloud::gatherAngularVelocities()
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    omega_.setSize(n);
    for (label i = 0; i < n; ++i)
    {
        omega_[i] = foamTools::toVector(s.angularVelocities()[i]);
    }
}


void Foam::vansCloud::rotationalSolidVelocity(const scalar dt)
{
    // the rigid-body velocity v*_p + omega_p x r_pc per overlap entry: the
    // mixture flux eps U + phi v_s is then divergence free where the
    // penalisation imposes U = v_s (a rotating grain in cells of varying
    // eps), as for the translation
    const nscd::System& s = grains_.system();
    const scalar depth = adapter_.depth();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    vectorField& f = phiVs_.primitiveFieldRef();
    f = Zero;
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    const auto& ev = adapter_.entryVolume();
    const UList<scalar> held(scalars(columns::heldFraction));
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const label gi = eg[e];
        // resolved grain: a_p (v**_0 + omega x r), the b_p part comes
        // with the local fluid velocity (which the penalisation drives
        // to v** + omega x r)
        scalar a = 1;
        if
        (
            !s.fixed(gi)
         && resolved_.size() == label(s.size())
         && resolved_[gi]
        )
        {
            const scalar Wdg = W[gi]/depth*dt*gamma_[gi];
            a = 1/(1 + Wdg*fluidInverseMass(gi, held));
        }
        f[ec[e]] +=
            ev[e]*(vStar_[gi] + a*(omega_[gi] ^ leverArm(e)));
    }
    f /= mesh_.V();
    phiVs_.correctBoundaryConditions();
}


void Foam::vansCloud::addRotationalForces
(
    const volVectorField& U,
    const volVectorField& gradp
)
{
    // Per overlap entry the force on the grain is
    //   f_pc = (V_pc/depth)(-rho grad(p)_c
    //          + gamma*_p (U_c - v**_p(c) - omega_p x r_pc))
    // with v**_p(c) = v**_0 - (W dt/m) rho grad(p)_c: summed over c it is
    // F_p (the gather weights are V_pc/W_p) plus the rotational part
    // -gamma* omega x sum V_pc r_pc; the torque is sum r_pc x f_pc, explicit
    // for the next NSCD step.  The fluid lost exactly sum f_pc at the cell
    // centres x_p + r_pc: angular momentum is exchanged exactly.
    const nscd::System& s = grains_.system();
    const label n = s.size();
    const scalar depth = adapter_.depth();
    const scalar rhoK = fluid_->rhoK();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    const auto& eg = adapter_.entryGrain();
    const auto& ec = adapter_.entryCell();
    const auto& ev = adapter_.entryVolume();
    const vectorField& UI = U.primitiveField();
    const vectorField& gI = gradp.primitiveField();
    List<vector> Frot(n, Zero);
    List<vector> torque(n, Zero);
    const UList<scalar> held(scalars(columns::heldFraction));
    // and the drag angular momentum the grains gain about the origin,
    // sum_pc x_c x (drag part of f_pc) (mesh units), logged with the
    // fluid's by logDragAngularMomentum
    dragTorqueGrains_ = Zero;
    for (std::size_t e = 0; e < ec.size(); ++e)
    {
        const label gi = eg[e];
        const label c = ec[e];
        const vector r = leverArm(e);
        const scalar cp =
            s.fixed(gi)
          ? 0 : dt_*W[gi]/depth*fluidInverseMass(gi, held)*rhoK;
        const vector vs = vss_[gi] - cp*gI[c] + (omega_[gi] ^ r);
        const vector f =
            ev[e]/depth*(-rhoK*gI[c] + gammaStar_[gi]*(UI[c] - vs));
        torque[gi] += r ^ f;
        Frot[gi] -= ev[e]/depth*gammaStar_[gi]*(omega_[gi] ^ r);
        vector xc = mesh_.C()[c];
        if (adapter_.twoD())
        {
            xc.z() = s.positions()[gi].z();
        }
        dragTorqueGrains_ += xc ^ (ev[e]*gammaStar_[gi]*(UI[c] - vs));
    }
    if (Pstream::parRun())
    {
        // the entries of a grain lie in the cells of several ranks: summed
        // over its copies (decomposed grains) or over the ranks (replicated)
        std::vector<double> sums(6*n);
        for (label i = 0; i < n; ++i)
        {
            for (direction d = 0; d < 3; ++d)
            {
                sums[6*i + d] = torque[i][d];
                sums[6*i + 3 + d] = Frot[i][d];
            }
        }
        adapter_.sumOverRanks(sums, 6);
        for (label i = 0; i < n; ++i)
        {
            for (direction d = 0; d < 3; ++d)
            {
                torque[i][d] = sums[6*i + d];
                Frot[i][d] = sums[6*i + 3 + d];
            }
        }
    }
    UList<vector> fluidForce(vectors(columns::fluidForce));
    UList<vector> explicitForce(vectors(columns::explicitFluidForce));
    UList<vector> fluidTorque(vectors(columns::fluidTorque));
    for (label i = 0; i < n; ++i)
    {
        // the rotational drag -gamma* omega x sum V_pc r_pc: explicit
        fluidForce[i] += Frot[i];
        explicitForce[i] += Frot[i];
        fluidTorque[i] = torque[i];
        if (adapter_.twoD())
        {
            fluidTorque[i].x() = 0;
            fluidTorque[i].y() = 0;
        }
    }
}


void Foam::vansCloud::logDragAngularMomentum
(
    const volVectorField& U,
    const volVectorField& gradp
)
{
    // drag angular momentum exchange about the origin (mesh units):
    // the grains gain sum_p x_p x F^drag_p + T^drag_p (dragTorqueGrains_,
    // summed per overlap entry by addRotationalForces), the fluid loses
    // sum_c V_c x_c x rho (K U - K v_s)_c
    const scalar rhoK = fluid_->rhoK();
    const vectorField& UI = U.primitiveField();
    const vectorField& gI = gradp.primitiveField();
    // fluid side from the fields (K U - K v**_0 + K_p rho grad p): the
    // pressure part of v** enters the fluid through K_p
    dragTorqueFluid_ = Zero;
    const vectorField& KU = KUs_.primitiveField();
    const scalarField& K = Kdrag_.primitiveField();
    const scalarField& Kp = Kp_.primitiveField();
    forAll(K, c)
    {
        vector xc = mesh_.C()[c];
        const vector f =
            mesh_.V()[c]*rhoK*(K[c]*UI[c] - KU[c] + Kp[c]*gI[c]);
        dragTorqueFluid_ += xc ^ f;
    }
    reduce(dragTorqueGrains_, sumOp<vector>());
    reduce(dragTorqueFluid_, sumOp<vector>());
    if (adapter_.twoD())
    {
        // about the z axis through the origin; the in-plane components
        // carry the arbitrary z of the cell centres
        dragTorqueGrains_.x() = dragTorqueGrains_.y() = 0;
        dragTorqueFluid_.x() = dragTorqueFluid_.y() = 0;
    }
    scalar Tmax = 0;
    for (const vector& T : vectors(columns::fluidTorque))
    {
        Tmax = max(Tmax, mag(T));
    }
    reduce(Tmax, maxOp<scalar>());   // (decomposed: each rank its grains)
    Info<< "rotationCoupling: max |fluid torque| " << Tmax
        << ", drag angular momentum rate lost by the fluid "
        << dragTorqueFluid_.z() << " gained by the grains "
        << dragTorqueGrains_.z() << endl;
    if (!rotationFile_)
    {
        const bool twoD = adapter_.twoD();
        const std::string perDepth(twoD ? " (2D: per unit depth)" : "");
        const std::string overDepth(twoD ? " (2D: over the mesh depth)" : "");
        rotationFile_.reset
        (
            new stepDataFile
            (
                mesh_.time(), "rotationCoupling",
                "fluid torque and drag angular momentum exchange about the"
                " z axis through the origin (the log's \"rotationCoupling:\""
                " line)",
                {
                    {
                        "maxFluidTorque", "N m",
                        "largest |fluid torque| on a grain" + perDepth
                    },
                    {
                        "fluidAngularMomentumRate", "N m",
                        "drag angular momentum rate lost by the fluid, z"
                        + overDepth
                    },
                    {
                        "grainAngularMomentumRate", "N m",
                        "drag angular momentum rate gained by the grains, z"
                        + overDepth
                    }
                }
            )
        );
    }
    rotationFile_->write
    (
        scalarList({Tmax, dragTorqueFluid_.z(), dragTorqueGrains_.z()})
    );
}


// ************************************************************************* //
