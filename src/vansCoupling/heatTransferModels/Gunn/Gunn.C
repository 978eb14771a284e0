// SPDX-License-Identifier: GPL-3.0-or-later
#include "Gunn.H"
#include "addToRunTimeSelectionTable.H"
#include "grainDictionaryTools.H"

namespace Foam
{
namespace heatTransferModels
{
    defineTypeNameAndDebug(Gunn, 0);
    addToRunTimeSelectionTable(heatTransferModel, Gunn, dictionary);
}
}


Foam::heatTransferModels::Gunn::Gunn(const dictionary& dict)
:
    heatTransferModel(dict)
{
    grainTools::checkKeywords(coeffs_, wordList());
}


Foam::scalar Foam::heatTransferModels::Gunn::Nu
(
    const scalar eps, const scalar Re, const scalar Pr
) const
{
    const scalar Res = eps*max(Re, scalar(0));      // superficial Re
    const scalar Pr13 = cbrt(Pr);
    return
        (7 - 10*eps + 5*sqr(eps))*(1 + 0.7*pow(Res, 0.2)*Pr13)
      + (1.33 - 2.4*eps + 1.2*sqr(eps))*pow(Res, 0.7)*Pr13;
}
