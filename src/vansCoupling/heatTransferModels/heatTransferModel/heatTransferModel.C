// SPDX-License-Identifier: GPL-3.0-or-later
#include "heatTransferModel.H"
#include "error.H"

namespace Foam
{
    defineTypeNameAndDebug(heatTransferModel, 0);
    defineRunTimeSelectionTable(heatTransferModel, dictionary);
}


Foam::heatTransferModel::heatTransferModel(const dictionary& dict)
:
    coeffs_
    (
        dict.subOrEmptyDict(dict.get<word>("heatTransferModel") + "Coeffs")
    )
{}


Foam::autoPtr<Foam::heatTransferModel> Foam::heatTransferModel::New
(
    const dictionary& dict
)
{
    const word modelType(dict.get<word>("heatTransferModel"));
    Info<< "Selecting heat transfer model " << modelType << endl;

    if (modelType == "none")
    {
        FatalIOErrorInFunction(dict)
            << "heatTransferModel none in " << dict.name() << " has no"
            << " Nusselt number: none switches the fluid-grain heat"
            << " exchange off." << nl
            << "    Fix: select a closure (DiFeliceColburn, Gunn,"
            << " RanzMarshall) to evaluate it" << exit(FatalIOError);
    }
    auto cstrIter = dictionaryConstructorTablePtr_->cfind(modelType);
    if (!cstrIter.found())
    {
        FatalIOErrorInLookup
        (
            dict,
            "heatTransferModel",
            modelType,
            *dictionaryConstructorTablePtr_
        )   << "or none (no fluid-grain heat exchange)" << nl
            << exit(FatalIOError);
    }
    return autoPtr<heatTransferModel>(cstrIter()(dict));
}


Foam::scalar Foam::heatTransferModel::surfaceToVolume
(
    const scalar d,
    const label nDims
)
{
    if (nDims == 3)
    {
        return 6/d;     // sphere: pi d^2 / (pi d^3/6)
    }
    if (nDims == 2)
    {
        return 4/d;     // disc: pi d L / (pi d^2 L/4)
    }
    FatalErrorInFunction
        << "Grain dimension " << nDims << ": use 2 (discs) or 3 (spheres)"
        << exit(FatalError);
    return 0;
}


Foam::scalar Foam::heatTransferModel::h
(
    const scalar eps,
    const scalar Re,
    const scalar Pr,
    const scalar d,
    const scalar k,
    const label nDims
) const
{
    return k*Nu(eps, Re, Pr)/d*surfaceToVolume(d, nDims);
}
