// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vansCloud, fluid forces on the grains and the grain step

Description
    The fluid force on each grain from the final U and p (pressure force
    explicit, drag implicit in the contact solve; a resolved grain's drag
    explicit too), extra forces, the NSCD
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

// * * * * * * * * * * * * * * * Static Data  * * * * * * * * * * * * * * * //

const Foam::word Foam::vansCloudColumns::heldFraction("grainHeldFraction");
const Foam::word
    Foam::vansCloudColumns::contactImpulse("grainContactImpulse");
const Foam::word
    Foam::vansCloudColumns::fluidDragGiven("vansFluidDragGiven");
const Foam::word
    Foam::vansCloudColumns::dragImpulseDefect("grainDragImpulseDefect");
const Foam::word
    Foam::vansCloudColumns::explicitFluidForce("vansExplicitFluidForce");
const Foam::word Foam::vansCloudColumns::fluidForce("vansFluidForce");
const Foam::word Foam::vansCloudColumns::fluidVelocity("vansFluidVelocity");
const Foam::word Foam::vansCloudColumns::fluidTorque("vansFluidTorque");
const Foam::word Foam::vansCloudColumns::grainReynolds("vansGrainReynolds");
const Foam::word
    Foam::vansCloudColumns::stepStartVelocity("vansStepStartVelocity");
const Foam::word Foam::vansCloudColumns::explicitDrag("vansExplicitDrag");


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::vansCloud::declareGrainColumns(nscd::System& s)
{
    // the impulses of the last grain step and the held fraction: in the
    // grain state (their own datasets) and with a grain that changes
    // ranks; a state without them takes the defaults (readRestart then
    // reads the per-grain lists older runs wrote)
    const unsigned restart =
        nscd::ColumnRestart | nscd::ColumnMigrate | nscd::ColumnOptional;
    // the state of a grain step's start travels with the grains that
    // change ranks or ghosts in the step (read back after it by
    // updateGrainImpulses, the step log and the output)
    const unsigned carried = nscd::ColumnMigrate | nscd::ColumnGhost;
    using grainColumns::add;
    add<scalar>(s, columns::heldFraction, restart, 0);
    add<vector>(s, columns::contactImpulse, restart, Zero);
    add<vector>(s, columns::dragImpulseDefect, restart, Zero);
    add<vector>(s, columns::fluidDragGiven, carried, Zero);
    add<vector>(s, columns::explicitFluidForce, carried, Zero);
    add<vector>(s, columns::fluidForce, carried, Zero);
    add<vector>(s, columns::fluidVelocity, carried, Zero);
    add<vector>(s, columns::fluidTorque, 0u, Zero);
    add<scalar>(s, columns::grainReynolds, carried, 0);
    add<vector>(s, columns::stepStartVelocity, carried, Zero);
    add<label>(s, columns::explicitDrag, carried, 0);
}


void Foam::vansCloud::initHeldFraction()
{
    const nscd::System& s = grains_.system();
    const label n = s.size();
    bool missing = !heldFractionSet_;
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
    UList<scalar> heldFraction(scalars(columns::heldFraction));
    forAll(heldFraction, i)
    {
        heldFraction[i] = min(held[i], scalar(1));
    }
    heldFractionSet_ = true;
}


Foam::scalar Foam::vansCloud::fluidInverseMass
(
    const label i,
    const UList<scalar>& held
) const
{
    // a held grain is seen 1e4 times heavier, not infinitely: where eps is
    // clipped at epsMin the drag coefficient is astronomical and gamma*
    // must stay bounded (<= 1e4 m/(W dt)) for a well-posed pressure equation
    const scalar theta = resolved_[i] ? 0 : held[i];
    return (1 - theta*(1 - 1e-4))/grains_.system().mass(i);
}


void Foam::vansCloud::applyGrainForces(const UList<vector>& extra)
{
    nscd::System& s = grains_.system();
    const label n = s.size();
    const scalar depth = adapter_.depth();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    const bool torque = settings_.rotation;
    const UList<vector> explicitForce(vectors(columns::explicitFluidForce));
    const UList<vector> fluidTorque(vectors(columns::fluidTorque));
    const UList<vector> fluidVelocity(vectors(columns::fluidVelocity));
    const UList<vector> dragGiven(vectors(columns::fluidDragGiven));
    UList<label> explicitDrag(grains_.column<label>(columns::explicitDrag));
    const bool anyResolved = resolved_.size() == n;
    for (label i = 0; i < n; ++i)
    {
        vector F = explicitForce[i];
        if (extra.size() == n)
        {
            F += extra[i];
        }
        // A resolved free grain gets the drag the fluid took, W gamma*
        // (U - v**) (eq. 3.50), as an explicit force, as the thesis does
        // for every grain (Figure 3.8): its b_p ~ 1 ties it to the fluid
        // inside it, and an implicit drag towards that fixed U would make
        // a contact stop the grain against all of it, an impulse W dt
        // gamma/m times the grain's own, handed to the fluid at the next
        // step as a kick apart (docs/validation/resolvedGrains.md,
        // "The contact kick")
        explicitDrag[i] = anyResolved && resolved_[i] && !s.fixed(i);
        if (explicitDrag[i])
        {
            F += dragGiven[i]/dt_;
        }
        const vector T = torque ? fluidTorque[i] : vector(Zero);
        s.setExternalForce(i, foamTools::toVec3(F), foamTools::toVec3(T));
        // drag coefficient W gamma [kg/s] (2D: per unit depth)
        s.setFluidDrag
        (
            i,
            (s.fixed(i) || explicitDrag[i]) ? 0.0 : W[i]/depth*gamma_[i],
            foamTools::toVec3(fluidVelocity[i])
        );
    }
}


void Foam::vansCloud::updateGrainImpulses(const scalar dt)
{
    // Contact impulse of the whole step (all sub-steps), p^n of eq. 3.46:
    // what changed the momentum besides gravity and the fluid force; the
    // fluid force actually received (explicit part + the drag impulse of
    // the contact solve) and the drag impulse the fluid still owes
    const nscd::System& s = grains_.system();
    const label n = s.size();
    const vector g(foamTools::toVector(s.gravity()));
    const std::vector<nscd::Vec3>& J = s.fluidDragImpulses();
    const bool coupled = fluidForcesSet_;
    const UList<vector> v0(vectors(columns::stepStartVelocity));
    const UList<vector> explicitForce(vectors(columns::explicitFluidForce));
    const UList<vector> dragGiven(vectors(columns::fluidDragGiven));
    const UList<vector> fluidVelocity(vectors(columns::fluidVelocity));
    const UList<label> explicitDrag
    (
        grains_.column<label>(columns::explicitDrag)
    );
    UList<vector> fluidForce(vectors(columns::fluidForce));
    UList<vector> defect(vectors(columns::dragImpulseDefect));
    UList<vector> contactImpulse(vectors(columns::contactImpulse));
    UList<scalar> held(scalars(columns::heldFraction));
    heldFractionSet_ = true;
    for (label i = 0; i < n; ++i)
    {
        defect[i] = Zero;
        if (s.fixed(i))
        {
            held[i] = 0;
            contactImpulse[i] = Zero;
            continue;
        }
        const scalar m = s.mass(i);
        // the drag impulse the grain received: from the contact solve, or
        // the fluid's own W dt gamma* (U - v**) where applyGrainForces
        // gave it as an explicit force (a resolved free grain)
        const bool explicitGiven = coupled && explicitDrag[i];
        const vector Jd
        (
            explicitGiven ? dragGiven[i] : foamTools::toVector(J[i])
        );
        // rotation on: F0 includes the rotational drag part
        const vector F0 = coupled ? explicitForce[i] : vector::zero;
        contactImpulse[i] =
            m*(foamTools::toVector(s.velocities()[i]) - v0[i])
          - dt*(m*g + F0) - Jd;
        if (coupled)
        {
            fluidForce[i] = F0 + Jd/dt;
            defect[i] = Jd - dragGiven[i];
        }
        // held fraction: how much of the free drift P the contacts cancelled
        const vector u = coupled ? fluidVelocity[i] : v0[i];
        const vector P =
            dt*(m*g + F0)
          + (
                explicitGiven
              ? Jd
              : dt*s.fluidDragCoefficient(i)*(u - v0[i])
            );
        const scalar P2 = magSqr(P);
        held[i] =
            P2 > 0
          ? min(max(-(contactImpulse[i] & P)/P2, scalar(0)), scalar(1))
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
    // resolved grains on (both forms: Kg g [m/s^2] kinematic, [N/m^3]
    // dynamic): their weight leaves the cell source for the faces
    if (settings_.resolvedCellsPerDiameter < GREAT)
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
    const UList<scalar> held(scalars(columns::heldFraction));
    UList<vector> fluidForce(vectors(columns::fluidForce));
    UList<vector> explicitForce(vectors(columns::explicitFluidForce));
    UList<vector> dragGiven(vectors(columns::fluidDragGiven));
    vectors(columns::fluidVelocity).deepCopy(Ug_);
    // (rotation on: the fluid torque of addRotationalForces)
    fluidForcesSet_ = true;
    for (label i = 0; i < nGrains; ++i)
    {
        const scalar Wi = W[i]/depth;
        // v** with the final pressure gradient (eq. 3.47)
        const vector vss =
            s.fixed(i)
          ? vss_[i]
          : vss_[i] - (dt_*Wi*fluidInverseMass(i, held)*rhoK)*gradpg_[i];
        // the drag the fluid took from its own equation, W gamma (U - v*)
        // with the predicted v* (eq. 3.48); the grains get W gamma (U - v)
        // with their velocity after the contact solve (evolve)
        const vector drag = Wi*gammaStar_[i]*(Ug_[i] - vss);
        explicitForce[i] = -Wi*rhoK*gradpg_[i];
        fluidForce[i] = explicitForce[i] + drag;
        dragGiven[i] = dt_*drag;
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
    if (F.size() != n || !fluidForcesSet_)
    {
        FatalErrorInFunction
            << "addExternalForces: " << F.size() << " forces for " << n
            << " grains (fluid forces "
            << (fluidForcesSet_ ? "set" : "not set") << "):"
            << " call it after setFluidForces with one force per grain."
            << exit(FatalError);
    }
    applyGrainForces(F);
}


void Foam::vansCloud::evolve(const scalar dt)
{
    // v^n for updateGrainImpulses (a column: it follows the grains that
    // leave through outlets or change ranks in the step)
    {
        const nscd::System& s = grains_.system();
        UList<vector> v0(vectors(columns::stepStartVelocity));
        forAll(v0, i)
        {
            v0[i] = foamTools::toVector(s.velocities()[i]);
        }
    }

    // vapour-switched cohesion (decomposed: each rank looks psi up at the
    // contacts it solves; across a processor boundary: where the point
    // lies)
    cohesion_.beforeGrainStep();

    grains_.evolve(dt);
    // bodies that moved inside the NSCD step read their state back
    for (grainCouplingSource* src : couplingSources_)
    {
        src->afterGrainStep();
    }
    if (grains_.decomposed())
    {
        // (the carried fluid forces are those of the step start)
        fluidForcesSet_ = true;
    }

    cohesion_.report();
    updateGrainImpulses(dt);
}


// ************************************************************************* //
