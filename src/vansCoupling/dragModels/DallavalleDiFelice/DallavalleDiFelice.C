#include "DallavalleDiFelice.H"
#include "addToRunTimeSelectionTable.H"
#include "grainDictionaryTools.H"

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
    const scalar l = 1.5 - log10(max(epsRe, 1e-12));
    return 2.8 - exp(-0.5*l*l);
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
