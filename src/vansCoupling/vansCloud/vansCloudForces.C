// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vansCloud, fluid forces on the grains and the grain step

Description
    The fluid force on each grain from the final U and p (pressure force
    explicit, drag implicit in the contact solve), extra forces, the NSCD
    step and the per-grain impulses it leaves for the next fluid prediction
    (contact impulse p^n of eq. 3.46, the drag impulse the fluid owes, the
    held fraction and the inverse mass the fluid's prediction gives a held
    grain).  See vansCloud.H.
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"
#include "foamTools.H"
#include "fvc.H"
#include "fvmSup.H"
#include "fvMatrices.H"

// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vansCloud::initHeldFraction()
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    bool missing = heldFraction_.size() != n;
    if (grains_.decomposed())
    {
        reduce(missing, orOp<bool>());   // (the same decision on every rank)
    }
    if (!missing)
    {
        return;
    }
    std::vector<double> held(n, 0.0);
    for (const nscd::System::ContactView& c : s.contacts())
    {
        if (c.impulse.squaredNorm() > 0)
        {
            held[c.i] = 1;
            if (c.j >= 0)
            {
                held[c.j] = 1;
            }
        }
    }
    // decomposed: a grain's contacts may be solved on several ranks (the
    // rank of each contact's smaller grain id): held if held on any
    if (grains_.decomposed())
    {
        grains_.sumOverCopies(held, 1);
    }
    heldFraction_.setSize(n);
    forAll(heldFraction_, i)
    {
        heldFraction_[i] = min(held[i], scalar(1));
    }
}


Foam::scalar Foam::vansCloud::fluidInverseMass(const label i) const
{
    // a held grain is seen 1e4 times heavier, not infinitely: where eps is
    // clipped at epsMin the drag coefficient is astronomical and gamma*
    // must stay bounded (<= 1e4 m/(W dt)) for a well-posed pressure equation
    const scalar theta = resolved_[i] ? 0 : heldFraction_[i];
    return (1 - theta*(1 - 1e-4))/grains_.system().mass(i);
}


void Foam::vansCloud::applyGrainForces(const UList<vector>& extra)
{
    nscd::System& s = grains_.system();
    const label n = s.size();
    const scalar depth = adapter_.depth();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    const bool torque = settings_.rotation && fluidTorque_.size() == n;
    for (label i = 0; i < n; ++i)
    {
        vector F = explicitFluidForce_[i];
        if (extra.size() == n)
        {
            F += extra[i];
        }
        const vector T = torque ? fluidTorque_[i] : vector(Zero);
        s.setExternalForce(i, foamTools::toVec3(F), foamTools::toVec3(T));
        // drag coefficient W gamma [kg/s] (2D: per unit depth)
        s.setFluidDrag
        (
            i,
            s.fixed(i) ? 0.0 : W[i]/depth*gamma_[i],
            foamTools::toVec3(fluidVelocity_[i])
        );
    }
}


void Foam::vansCloud::updateGrainImpulses
(
    const UList<vector>& v0,
    const scalar dt
)
{
    // Contact impulse of the whole step (all sub-steps), p^n of eq. 3.46:
    // what changed the momentum besides gravity and the fluid force; the
    // fluid force actually received (explicit part + the drag impulse of
    // the contact solve) and the drag impulse the fluid still owes
    const nscd::System& s = grains_.system();
    const label n = s.size();
    const vector g(foamTools::toVector(s.gravity()));
    const std::vector<nscd::Vec3>& J = s.fluidDragImpulses();
    const bool coupled =
        explicitFluidForce_.size() == n && fluidDragGiven_.size() == n
     && fluidForce_.size() == n;
    dragImpulseDefect_.setSize(n);
    heldFraction_.setSize(n);
    for (label i = 0; i < n; ++i)
    {
        dragImpulseDefect_[i] = Zero;
        if (s.fixed(i))
        {
            heldFraction_[i] = 0;
            contactImpulse_[i] = Zero;
            continue;
        }
        const scalar m = s.mass(i);
        const vector Jd(foamTools::toVector(J[i]));
        // rotation on: F0 includes the rotational drag part
        const vector F0 = coupled ? explicitFluidForce_[i] : vector::zero;
        contactImpulse_[i] =
            m*(foamTools::toVector(s.velocities()[i]) - v0[i])
          - dt*(m*g + F0) - Jd;
        if (coupled)
        {
            fluidForce_[i] = F0 + Jd/dt;
            dragImpulseDefect_[i] = Jd - fluidDragGiven_[i];
        }
        // held fraction: how much of the free drift P the contacts cancelled
        const vector u = fluidVelocity_.size() == n ? fluidVelocity_[i] : v0[i];
        const vector P =
            dt*(m*g + F0 + s.fluidDragCoefficient(i)*(u - v0[i]));
        const scalar P2 = magSqr(P);
        heldFraction_[i] =
            P2 > 0
          ? min(max(-(contactImpulse_[i] & P)/P2, scalar(0)), scalar(1))
          : 0;
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vansCloud::addMomentumSources
(
    fvMatrix<vector>& UEqn,
    const uniformDimensionedVectorField& g
) const
{
    UEqn += fvm::Sp(Kdrag_, UEqn.psi());
    if (fluid_->kinematic() && settings_.resolvedCellsPerDiameter < GREAT)
    {
        UEqn -= KUs_ - Kg()*g;
    }
    else
    {
        UEqn -= KUs_;
    }
    if (!modelA())
    {
        UEqn -= solidPressureForce_;
    }
}


void Foam::vansCloud::setFluidForces
(
    const volVectorField& U,
    const volScalarField& p
)
{
    nscd::System& s = grains_.system();
    const scalar depth = adapter_.depth();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    const scalar rhoK = fluid_->rhoK();
    adapter_.gather(U, Ug_);
    const volVectorField gradp(fvc::grad(p));
    adapter_.gather(gradp, gradpg_);
    const label nGrains = s.size();
    fluidForce_.setSize(nGrains);
    explicitFluidForce_.setSize(nGrains);
    fluidDragGiven_.setSize(nGrains);
    fluidVelocity_ = Ug_;
    for (label i = 0; i < nGrains; ++i)
    {
        const scalar Wi = W[i]/depth;
        // v** with the final pressure gradient (eq. 3.47)
        const vector vss =
            s.fixed(i)
          ? vss_[i]
          : vss_[i] - (dt_*Wi*fluidInverseMass(i)*rhoK)*gradpg_[i];
        // the drag the fluid took from its own equation, W gamma (U - v*)
        // with the predicted v* (eq. 3.48); the grains get W gamma (U - v)
        // with their velocity after the contact solve (evolve)
        const vector drag = Wi*gammaStar_[i]*(Ug_[i] - vss);
        explicitFluidForce_[i] = -Wi*rhoK*gradpg_[i];
        fluidForce_[i] = explicitFluidForce_[i] + drag;
        fluidDragGiven_[i] = dt_*drag;
    }
    if (!settings_.rotation)
    {
        applyGrainForces(UList<vector>());
        return;
    }
    addRotationalForces(U, gradp);
    applyGrainForces(UList<vector>());
    logDragAngularMomentum(U, gradp);
}


void Foam::vansCloud::addExternalForces(const UList<vector>& F)
{
    const label n = grains_.system().size();
    if (F.empty())
    {
        return;
    }
    if (F.size() != n || explicitFluidForce_.size() != n)
    {
        FatalErrorInFunction
            << "addExternalForces: " << F.size() << " forces for " << n
            << " grains (" << explicitFluidForce_.size() << " fluid forces):"
            << " call it after setFluidForces with one force per grain."
            << exit(FatalError);
    }
    applyGrainForces(F);
}


void Foam::vansCloud::evolveDecomposed(const scalar dt)
{
    // the grains change ranks and ghosts in the step: the per-grain state
    // of its start that updateGrainImpulses needs travels with them
    // (v^n, the explicit fluid force, the drag impulse the fluid gave, the
    // gathered fluid velocity, Re_p for the log, the gathered fluid
    // temperature for the output)
    const nscd::System& s = grains_.system();
    constexpr int width = 14;
    label n = s.size();
    const bool coupled =
        explicitFluidForce_.size() == n && fluidDragGiven_.size() == n
     && fluidVelocity_.size() == n && ReP_.size() == n;
    const bool heat = heat_.Tfluid().size() == n;
    {
        std::vector<double>& carried = grains_.carriedValues(width);
        std::fill(carried.begin(), carried.end(), 0.0);
        for (label i = 0; i < n; ++i)
        {
            double* c = carried.data() + std::size_t(i)*width;
            const vector v(foamTools::toVector(s.velocities()[i]));
            const vector zero(Zero);
            const vector* parts[4] =
            {
                &v,
                coupled ? &explicitFluidForce_[i] : &zero,
                coupled ? &fluidDragGiven_[i] : &zero,
                coupled ? &fluidVelocity_[i] : &zero
            };
            for (int k = 0; k < 4; ++k)
            {
                for (direction d = 0; d < 3; ++d)
                {
                    c[3*k + d] = (*parts[k])[d];
                }
            }
            c[12] = coupled ? ReP_[i] : 0;
            c[13] = heat ? heat_.Tfluid()[i] : 0;
        }
    }

    // vapour-switched cohesion: each rank looks psi up at the contacts it
    // solves (across a processor boundary: where the point lies)
    cohesion_.beforeGrainStep();
    grains_.evolve(dt);
    cohesion_.report();

    n = s.size();
    const std::vector<double>& carried = grains_.carriedValues(width);
    List<vector> v0(n);
    explicitFluidForce_.setSize(n);
    fluidDragGiven_.setSize(n);
    fluidVelocity_.setSize(n);
    fluidForce_.setSize(n);
    ReP_.setSize(n);
    contactImpulse_.setSize(n);
    List<scalar> Tfluid(n);
    for (label i = 0; i < n; ++i)
    {
        const double* c = carried.data() + std::size_t(i)*width;
        v0[i] = vector(c[0], c[1], c[2]);
        explicitFluidForce_[i] = vector(c[3], c[4], c[5]);
        fluidDragGiven_[i] = vector(c[6], c[7], c[8]);
        fluidVelocity_[i] = vector(c[9], c[10], c[11]);
        ReP_[i] = c[12];
        Tfluid[i] = c[13];
    }
    if (heat_.on())
    {
        heat_.setTfluid(std::move(Tfluid));
    }
    updateGrainImpulses(v0, dt);
}


void Foam::vansCloud::evolve(const scalar dt)
{
    if (grains_.decomposed())
    {
        evolveDecomposed(dt);
        return;
    }
    nscd::System& s = grains_.system();
    const label n = s.size();
    List<vector> v0(n);
    for (label i = 0; i < n; ++i)
    {
        v0[i] = foamTools::toVector(s.velocities()[i]);
    }

    cohesion_.beforeGrainStep();

    grains_.evolve(dt);
    // bodies that moved inside the NSCD step read their state back
    for (grainCouplingSource* src : couplingSources_)
    {
        src->afterGrainStep();
    }
    if (grains_.removedGrains().size())   // grains left through outlets
    {
        grains_.compactRemoved(v0);
        compactRemovedGrains();
    }

    cohesion_.report();
    updateGrainImpulses(v0, dt);
}


// ************************************************************************* //
