// SPDX-License-Identifier: GPL-3.0-or-later
#include "DiFeliceColburn.H"
#include "addToRunTimeSelectionTable.H"
#include "grainDictionaryTools.H"
#include "diFeliceExponent.H"

namespace Foam
{
namespace heatTransferModels
{
    defineTypeNameAndDebug(DiFeliceColburn, 0);
    addToRunTimeSelectionTable
    (
        heatTransferModel, DiFeliceColburn, dictionary
    );
}
}


Foam::heatTransferModels::DiFeliceColburn::DiFeliceColburn
(
    const dictionary& dict
)
:
    heatTransferModel(dict),
    delta_(grainTools::getPositiveOrDefault(coeffs_, "delta", 500)),
    alpha_(coeffs_.getOrDefault<scalar>("alpha", 0.4))
{
    grainTools::checkKeywords(coeffs_, {"delta", "alpha"});
}


Foam::scalar Foam::heatTransferModels::DiFeliceColburn::f
(
    const scalar x
) const
{
    return (x + delta_)/(0.11*pow(x, 1.4) + x + delta_);
}


Foam::scalar Foam::heatTransferModels::DiFeliceColburn::Nu
(
    const scalar eps, const scalar Re, const scalar Pr
) const
{
    const scalar epsRe = eps*max(Re, scalar(0));    // superficial Re
    const scalar g = pow(eps, -diFelice::voidageExponent(epsRe, 1.8));
    return g*f(epsRe)*sqr(0.18*sqrt(epsRe) + 1.39)*pow(Pr, alpha_);
}
