// SPDX-License-Identifier: GPL-3.0-or-later
#include "constantFluidProperties.H"
#include "dimensionedScalar.H"
#include "dimensionSets.H"

#include <cmath>

namespace Foam
{
    defineTypeNameAndDebug(constantFluidProperties, 0);
}


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::constantFluidProperties::constantFluidProperties
(
    const dictionary& td
)
:
    rho_(dimensionedScalar("rho", dimDensity, td).value()),
    nu_(dimensionedScalar("nu", dimViscosity, td).value())
{
    if
    (
        !(rho_ > 0) || !(nu_ > 0)
     || !std::isfinite(rho_) || !std::isfinite(nu_)
    )
    {
        FatalIOErrorInFunction(td)
            << "rho " << rho_ << " and nu " << nu_ << " in " << td.name()
            << " must be finite and > 0 (fluid density [kg/m^3] and"
            << " kinematic viscosity [m^2/s])." << nl
            << "    Fix: e.g. rho 1000; nu 1e-6; (water)"
            << exit(FatalIOError);
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::constantFluidProperties::gather
(
    const overlapMeshAdapter&,
    const label n,
    List<scalar>& rhog,
    List<scalar>& nug
) const
{
    rhog.setSize(n);
    nug.setSize(n);
    rhog = rho_;
    nug = nu_;
}


void Foam::constantFluidProperties::describe(Ostream& os) const
{
    os  << ", fluid rho " << rho_ << " nu " << nu_;
}
