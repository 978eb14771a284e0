// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vapourDroplet capillary entry barrier (see vapourDroplet.H)

Description
    With surfaceTension > 0 and grains, the droplet is an nscd::System
    droplet that moves inside the NSCD step of the grains: handed over at
    the end of the fluid step (endStep), read back by afterGrainStep()
    (velocity, position, capillary force [N], wall contact).
\*---------------------------------------------------------------------------*/

#include "vapourDroplet.H"
#include "vansCloud.H"
#include "meshTools.H"

#include <algorithm>
#include <cmath>

// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

nscd::System* Foam::vapourDroplet::barrierSystem()
{
    nscd::System* sysPtr = nullptr;
    if (sigma_ > 0 && cloud_)
    {
        sysPtr = &cloud_->grains().system();
        if (barrierId_ < 0)
        {
            nscd::System::Droplet d;
            d.radius = radius() > 0 ? radius() : 1;
            barrierId_ = sysPtr->addDroplet(d);
            // grains inside the surface at the start are pushed out with up
            // to F_max each and kick the droplet: say so
            // (decomposed: each grain counted by its owner, the droplet
            // added identically on every rank, nscd::Subdomain)
            const grainCloud& grains = cloud_->grains();
            const bool twoD = adapter_.twoD();
            const auto& pos = sysPtr->positions();
            const auto& rad = sysPtr->radii();
            label nIn = 0;
            for (std::size_t gi = 0; gi < rad.size(); ++gi)
            {
                if (!grains.owned(label(gi)))
                {
                    continue;
                }
                const scalar dx = pos[gi][0] - x_.x();
                const scalar dy = pos[gi][1] - x_.y();
                const scalar dz = twoD ? 0.0 : pos[gi][2] - x_.z();
                const scalar gap =
                    std::sqrt(dx*dx + dy*dy + dz*dz) - radius() - rad[gi];
                if (gap < -1e-3*rad[gi] && gap > -2*rad[gi])
                {
                    ++nIn;
                }
            }
            if (grains.decomposed())
            {
                reduce(nIn, sumOp<label>());
            }
            if (nIn > 0)
            {
                WarningInFunction
                    << nIn << " grains cross the droplet surface at time "
                    << mesh_.time().timeName() << " (" << dict_.name()
                    << ": centre " << x_ << ", radius " << radius() << "):"
                    << " the capillary barrier (surfaceTension " << sigma_
                    << ") pushes each out with up to its entry force, which"
                    << " kicks the droplet." << nl
                    << "    Fix: start the droplet resting on the bed (no"
                    << " grain inside its surface)." << endl;
            }
        }
    }
    return sysPtr;
}


void Foam::vapourDroplet::handToBarrier
(
    nscd::System& sys,
    const scalar dt,
    const bool move,
    const vector& u
)
{
    const bool twoD = adapter_.twoD();
    const scalar depth = twoD ? adapter_.depth() : 1;
    nscd::System::Droplet& d = sys.droplet(barrierId_);
    d.centre = nscd::Vec3(x_.x(), x_.y(), twoD ? 0.0 : x_.z());
    d.radius = radius() > 0 ? radius() : 1;
    d.impulse.setZero();
    std::fill(d.grainImpulse.begin(), d.grainImpulse.end(), 0.0);
    d.surfaceTension = m_ > 0 ? sigma_ : 0;
    if (move)
    {
        // the droplet's equation of exchangeGrainMomentum,
        // Mp (u - u^n) = dt F, with the capillary impulse added by NSCD
        const vector F(Mp_*(u - u_)/dt);
        d.mass = Mp_/depth;
        d.velocity = nscd::Vec3(u_.x(), u_.y(), twoD ? 0.0 : u_.z());
        d.force = nscd::Vec3(F.x(), F.y(), twoD ? 0.0 : F.z())/depth;
    }
    else
    {
        // held: a fixed surface
        d.mass = 0;
        d.velocity.setZero();
        d.force.setZero();
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vapourDroplet::afterGrainStep()
{
    if (!barrierActive_)
    {
        return;
    }
    barrierActive_ = false;
    const scalar dt = mesh_.time().deltaTValue();
    const bool twoD = adapter_.twoD();
    const scalar depth = twoD ? adapter_.depth() : 1;
    const nscd::System& sys = cloud_->grains().system();
    const nscd::System::Droplet& d = sys.droplet(barrierId_);
    computeFilmHeat(sys, dt);

    // capillary force on the droplet over the step [N] (2D: over the depth)
    Fc_ =
        vector(d.impulse.x(), d.impulse.y(), twoD ? 0.0 : d.impulse.z())
       *depth/dt;
    meshTools::constrainDirection(mesh_, mesh_.solutionD(), Fc_);

    if (moving_ && m_ > 0)
    {
        vector u(d.velocity.x(), d.velocity.y(), twoD ? 0.0 : d.velocity.z());
        meshTools::constrainDirection(mesh_, mesh_.solutionD(), u);
        const vector xNew
        (
            d.centre.x(), d.centre.y(), twoD ? x_.z() : d.centre.z()
        );
        // the walls stay impenetrable: the capillary impulse may push the
        // droplet towards a wall (x_ is still x^n here)
        vector uc = u;
        const FixedList<bool, 3> clampedBefore = wallClamped_;
        wallClamped_ = false;
        if (wallContact(dt, uc))
        {
            for (direction k = 0; k < vector::nComponents; ++k)
            {
                if (wallClamped_[k])
                {
                    Fw_[k] += Mp_*(uc[k] - u[k])/dt;
                }
            }
            x_ += dt*uc;
        }
        else
        {
            x_ = xNew;
        }
        for (direction k = 0; k < vector::nComponents; ++k)
        {
            wallClamped_[k] = wallClamped_[k] || clampedBefore[k];
        }
        u_ = uc;
    }
    finishStep();
}


// ************************************************************************* //
