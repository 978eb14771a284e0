// SPDX-License-Identifier: GPL-3.0-or-later
#include "dragModel.H"
#include "diFeliceExponent.H"
#include "mathematicalConstants.H"

namespace Foam
{
    defineTypeNameAndDebug(dragModel, 0);
    defineRunTimeSelectionTable(dragModel, dictionary);
}


namespace
{
    Foam::dragModel::discConvention readDiscConvention
    (
        const Foam::dictionary& dict
    )
    {
        using namespace Foam;
        const word c
        (
            dict.getOrDefault<word>("twoDimensionalDrag", "perUnitDepth")
        );
        if (c == "perUnitDepth")
        {
            return dragModel::discConvention::perUnitDepth;
        }
        if (c == "thesisEq3.32")
        {
            return dragModel::discConvention::thesisEq3_32;
        }
        FatalIOErrorInFunction(dict)
            << "twoDimensionalDrag " << c << " in " << dict.name()
            << " is not a 2D drag convention." << nl
            << "    Fix: twoDimensionalDrag perUnitDepth; (1/2 rho C_d d |w| w"
            << " per unit depth, as MigFlow, the default) or"
            << " twoDimensionalDrag thesisEq3.32; (the thesis' eq. 3.32 as"
            << " printed, 2.36 x perUnitDepth)"
            << exit(FatalIOError);
        return dragModel::discConvention::perUnitDepth;
    }
}


Foam::dragModel::dragModel(const dictionary& dict)
:
    coeffs_(dict.subOrEmptyDict(dict.get<word>("dragModel") + "Coeffs")),
    disc_(readDiscConvention(dict))
{}


Foam::autoPtr<Foam::dragModel> Foam::dragModel::New(const dictionary& dict)
{
    const word modelType(dict.get<word>("dragModel"));
    Info<< "Selecting drag model " << modelType << endl;

    auto cstrIter = dictionaryConstructorTablePtr_->cfind(modelType);
    if (!cstrIter.found())
    {
        FatalIOErrorInLookup
        (
            dict,
            "dragModel",
            modelType,
            *dictionaryConstructorTablePtr_
        ) << exit(FatalIOError);
    }
    autoPtr<dragModel> model(cstrIter()(dict));
    if
    (
        model->disc() == discConvention::thesisEq3_32
     && modelType != "DallavalleDiFelice"
    )
    {
        FatalIOErrorInFunction(dict)
            << "twoDimensionalDrag thesisEq3.32 in " << dict.name()
            << " is the thesis' eq. 3.32, a form of DallavalleDiFelice;"
            << " dragModel is " << modelType << "." << nl
            << "    Fix: dragModel DallavalleDiFelice; or"
            << " twoDimensionalDrag perUnitDepth;"
            << exit(FatalIOError);
    }
    return model;
}


Foam::scalar Foam::dragModel::gamma
(
    const scalar eps,
    const scalar Re,
    const scalar d,
    const scalar mu,
    const scalar rho,
    const bool twoD
) const
{
    if (!twoD)
    {
        return gamma(eps, Re, d, mu, rho);
    }
    if (disc_ == discConvention::thesisEq3_32)
    {
        return thesisEq3_32(eps, Re, d, mu);
    }
    // (2/pi) C_d rho |w|/d over the sphere's (3/4) C_d rho |w|/d
    return 8.0/(3.0*constant::mathematical::pi)*gamma(eps, Re, d, mu, rho);
}


Foam::scalar Foam::dragModel::thesisEq3_32
(
    const scalar eps,
    const scalar Re,
    const scalar d,
    const scalar mu
)
{
    const scalar epsRe = eps*Re;
    return
        pow(eps, -diFelice::voidageExponent(epsRe, 2.8))
       *sqr(0.77*sqrt(epsRe) + 5.88)*mu/sqr(d);
}


Foam::word Foam::dragModel::discConventionName() const
{
    return
        disc_ == discConvention::thesisEq3_32
      ? "thesisEq3.32"
      : "perUnitDepth";
}
