// SPDX-License-Identifier: GPL-3.0-or-later
#include "RanzMarshall.H"
#include "addToRunTimeSelectionTable.H"
#include "grainDictionaryTools.H"

namespace Foam
{
namespace heatTransferModels
{
    defineTypeNameAndDebug(RanzMarshall, 0);
    addToRunTimeSelectionTable(heatTransferModel, RanzMarshall, dictionary);
}
}


Foam::heatTransferModels::RanzMarshall::RanzMarshall(const dictionary& dict)
:
    heatTransferModel(dict)
{
    grainTools::checkKeywords(coeffs_, wordList());
}


Foam::scalar Foam::heatTransferModels::RanzMarshall::Nu
(
    const scalar eps, const scalar Re, const scalar Pr
) const
{
    return 2 + 0.6*sqrt(max(Re, scalar(0)))*cbrt(Pr);
}
