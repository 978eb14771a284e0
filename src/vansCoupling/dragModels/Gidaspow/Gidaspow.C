// SPDX-License-Identifier: GPL-3.0-or-later
#include "Gidaspow.H"
#include "addToRunTimeSelectionTable.H"

namespace Foam
{
namespace dragModels
{
    defineTypeNameAndDebug(Gidaspow, 0);
    addToRunTimeSelectionTable(dragModel, Gidaspow, dictionary);
}
}


Foam::dragModels::Gidaspow::Gidaspow(const dictionary& dict)
:
    dragModel(dict)
{}


Foam::scalar Foam::dragModels::Gidaspow::gamma
(
    const scalar eps, const scalar Re, const scalar d,
    const scalar mu, const scalar rho
) const
{
    const scalar slip = Re*mu/(rho*d);      // |u - v|
    if (eps < 0.8)
    {
        return 150*(1 - eps)*mu/(eps*sqr(d)) + 1.75*rho*slip/d;
    }
    const scalar epsRe = eps*Re;
    if (epsRe < 1000)
    {
        // 0.75 C_d eps rho |u-v| / d
        // with C_d = 24/(eps Re)(1 + 0.15 (eps Re)^0.687)
        return 18*mu/sqr(d)*(1 + 0.15*pow(epsRe, 0.687))*pow(eps, -2.65);
    }
    return 0.75*0.44*eps*rho*slip*pow(eps, -2.65)/d;
}
