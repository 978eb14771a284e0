// SPDX-License-Identifier: GPL-3.0-or-later
#include "DallavalleDiFelice.H"
#include "addToRunTimeSelectionTable.H"
#include "grainDictionaryTools.H"
#include "diFeliceExponent.H"

namespace Foam
{
namespace dragModels
{
    defineTypeNameAndDebug(DallavalleDiFelice, 0);
    addToRunTimeSelectionTable(dragModel, DallavalleDiFelice, dictionary);
}
}


Foam::dragModels::DallavalleDiFelice::DallavalleDiFelice(const dictionary& dict)
:
    dragModel(dict)
{
    grainTools::checkKeywords(coeffs_, {});
}


Foam::scalar Foam::dragModels::DallavalleDiFelice::chi(const scalar Res)
{
    return 3.7 - 0.65*diFelice::bump(Res);
}


Foam::scalar Foam::dragModels::DallavalleDiFelice::gamma
(
    const scalar eps, const scalar Re, const scalar d,
    const scalar mu, const scalar /*rho*/
) const
{
    const scalar Res = eps*Re;
    return 0.75*sqr(0.63*sqrt(Res) + 4.8)*pow(eps, 1 - chi(Res))*mu/sqr(d);
}
