// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vansCloud after grains left through outlet patches

Description
    grainCloud removes the grains that crossed an outlet patch at the end
    of its step (grainCloud outletPatches, issue 27 item 4); the per-grain
    lists of vansCloud that outlive a step (the contact impulse of the
    restart and of eq. 3.46, the fluid force and velocity written at the
    next write, ...) are compacted the same way, so that entry i stays
    grain i.  The lists rebuilt by every predictDrag are compacted too (no
    stale size between the grain step and the next fluid step).
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"

// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::vansCloud::compactRemovedGrains()
{
    const grainCloud& g = grains_;
    resolved_.compactRemoved();
    g.compactRemoved(Ug_);
    g.compactRemoved(epsg_);
    g.compactRemoved(gradpg_);
    g.compactRemoved(gamma_);
    g.compactRemoved(gammaStar_);
    g.compactRemoved(vss_);
    g.compactRemoved(vStar_);
    g.compactRemoved(contactImpulse_);
    g.compactRemoved(fluidDragGiven_);
    g.compactRemoved(dragImpulseDefect_);
    g.compactRemoved(heldFraction_);
    g.compactRemoved(explicitFluidForce_);
    g.compactRemoved(ReP_);
    g.compactRemoved(rhog_);
    g.compactRemoved(nug_);
    g.compactRemoved(omega_);
    g.compactRemoved(fluidTorque_);
    g.compactRemoved(fluidForce_);
    g.compactRemoved(fluidVelocity_);
    heat_.compactRemoved();
    cohesion_.compactRemoved();
}


// ************************************************************************* //
