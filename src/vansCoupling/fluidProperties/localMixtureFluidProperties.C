// SPDX-License-Identifier: GPL-3.0-or-later
#include "localMixtureFluidProperties.H"
#include "overlapMeshAdapter.H"
#include "volFields.H"

namespace Foam
{
    defineTypeNameAndDebug(localMixtureFluidProperties, 0);
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::localMixtureFluidProperties::setFields
(
    const volScalarField& rho,
    const volScalarField& mu
)
{
    rho_ = &rho;
    mu_ = &mu;
}


void Foam::localMixtureFluidProperties::gather
(
    const overlapMeshAdapter& adapter,
    const label n,
    List<scalar>& rhog,
    List<scalar>& nug
) const
{
    if (!rho_ || !mu_)
    {
        FatalErrorInFunction
            << "the local mixture fluid properties have no fields: the"
            << " solver must call setFields(rho, mu) before predictDrag"
            << exit(FatalError);
    }
    List<scalar> mug;
    adapter.gather(*rho_, rhog);
    adapter.gather(*mu_, mug);
    nug.setSize(n);
    forAll(nug, i)
    {
        // a grain outside the mesh (W = 0) has no drag: any positive value
        if (!(rhog[i] > 0) || !(mug[i] > 0))
        {
            rhog[i] = 1;
            mug[i] = 1;
        }
        nug[i] = mug[i]/rhog[i];
    }
}


void Foam::localMixtureFluidProperties::describe(Ostream& os) const
{
    os  << ", local fluid rho and mu (mixture fields)";
}
