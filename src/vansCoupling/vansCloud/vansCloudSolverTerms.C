// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: vansCloud, the grains' terms of the fluid equations

Description
    What the solver's UEqn.H and pEqn.H take from the cloud (vansCloud.H,
    "One vansFoam time step" of docs/architecture.md): the face and cell
    forces of gravity and the pressure gradient with the pressure
    coefficient pf + K_p, the weight flux of the grains' K_g, and the
    solid flux of the predicted grain velocities v* (eq. 3.51).
\*---------------------------------------------------------------------------*/

#include "vansCloud.H"
#include "fvc.H"

// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

Foam::tmp<Foam::surfaceScalarField> Foam::vansCloud::faceForces
(
    const surfaceScalarField& fluidWeightFlux,
    const uniformDimensionedVectorField& g,
    const surfaceScalarField& snGradpSf
) const
{
    return
        fluidWeightFlux
      + fvc::interpolate(Kg())*(g & mesh_.Sf())
      - fvc::interpolate(pressureCoefficient_)*snGradpSf;
}


Foam::tmp<Foam::volVectorField> Foam::vansCloud::cellForces
(
    const volScalarField& w,
    const uniformDimensionedVectorField& g,
    const volVectorField& gradp
) const
{
    return w*g + Kg()*g - pressureCoefficient_*gradp;
}


Foam::tmp<Foam::surfaceScalarField> Foam::vansCloud::weightFlux
(
    const volScalarField& rAU,
    const uniformDimensionedVectorField& g
) const
{
    return fvc::interpolate(Kg()*rAU)*(g & mesh_.Sf());
}


Foam::tmp<Foam::surfaceScalarField> Foam::vansCloud::solidFlux
(
    const volVectorField& U,
    const scalar dt
)
{
    const nscd::System& s = grains_.system();
    const scalar depth = adapter_.depth();
    const std::vector<double>& W = adapter_.grainMappedVolume();
    adapter_.gather(U, Ug_);
    const UList<scalar> held(scalars(columns::heldFraction));
    for (label i = 0; i < label(s.size()); ++i)
    {
        if (s.fixed(i)) continue;
        const scalar im = fluidInverseMass(i, held);
        const scalar Wdg = W[i]/depth*dt*gamma_[i];
        // resolved grain: only the v** part, a_p v**_0; its fluid part
        // b_p U is added per cell with the cell's own, pressure-dependent
        // velocity by the solver (B_f, pEqn.H)
        const scalar b =
            resolved_.size() == label(s.size()) && resolved_[i]
          ? 0 : Wdg*im;
        vStar_[i] = (vss_[i] + b*Ug_[i])/(1 + Wdg*im);
    }
    if (!settings_.rotation)
    {
        adapter_.solidVelocity(vStar_, phiVs_);
    }
    else
    {
        rotationalSolidVelocity(dt);
    }
    return fvc::flux(phiVs_);
}


// ************************************************************************* //
