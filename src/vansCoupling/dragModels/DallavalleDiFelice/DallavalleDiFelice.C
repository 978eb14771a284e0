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
    dragModel(dict),
    constantExponent_(coeffs_.getOrDefault<bool>("constantExponent", false))
{
    grainTools::checkKeywords(coeffs_, {"constantExponent"});
}


Foam::scalar Foam::dragModels::DallavalleDiFelice::exponent
(
    const scalar epsRe
) const
{
    if (constantExponent_)
    {
        return 2.8;
    }
    // Thesis eq. 4.10 exponent plus 1 (shared with the Nusselt model)
    return diFelice::voidageExponent(epsRe, 2.8);
}


Foam::scalar Foam::dragModels::DallavalleDiFelice::gamma
(
    const scalar eps, const scalar Re, const scalar d,
    const scalar mu, const scalar rho
) const
{
    const scalar epsRe = eps*Re;
    return pow(eps, -exponent(epsRe))*sqr(0.77*sqrt(epsRe) + 5.88)*mu/sqr(d);
}
