// SPDX-License-Identifier: GPL-3.0-or-later
#include "runUp.H"
#include "freeSurfaceTools.H"
#include "addToRunTimeSelectionTable.H"

namespace Foam
{
namespace functionObjects
{
    defineTypeNameAndDebug(runUp, 0);
    addToRunTimeSelectionTable(functionObject, runUp, dictionary);
}
}


Foam::functionObjects::runUp::runUp
(
    const word& name,
    const Time& runTime,
    const dictionary& dict
)
:
    fvMeshFunctionObject(name, runTime, dict),
    writeFile(mesh_, name, typeName, dict),
    alphaName_("alpha.water"),
    threshold_(0.5),
    xMin_(-GREAT),
    xMax_(GREAT),
    stillWaterLevel_(0),
    horizontal_(1, 0, 0),
    vertical_(0, 1, 0),
    runUp_(-GREAT),
    maxRunUp_(-GREAT)
{
    read(dict);
    // restart: the maximum so far is kept in the function-object state
    // (<time>/uniform/functionObjects/functionObjectProperties)
    getProperty("maxRunUp", maxRunUp_);
    freeSurfaceTools::writeColumnHeader
    (
        *this,
        "Run-up [m] (" + alphaName_ + " >= " + Foam::name(threshold_)
      + ") minus stillWaterLevel " + Foam::name(stillWaterLevel_),
        {"runUp", "maxRunUp"}
    );
}


bool Foam::functionObjects::runUp::read(const dictionary& dict)
{
    freeSurfaceTools::readBase(*this, dict);
    freeSurfaceTools::checkKeywords
    (
        dict,
        {
            "alpha", "threshold", "patches", "xRange", "stillWaterLevel",
            "horizontalDirection", "verticalDirection"
        }
    );
    alphaName_ = dict.getOrDefault<word>("alpha", "alpha.water");
    threshold_ = dict.getOrDefault<scalar>("threshold", 0.5);
    if (!(threshold_ > 0 && threshold_ <= 1))
    {
        FatalIOErrorInFunction(dict)
            << "threshold " << threshold_ << " in " << dict.name()
            << " must be in (0, 1]" << exit(FatalIOError);
    }
    patchIds_.clear();
    if (dict.found("patches"))
    {
        const wordRes names(dict.get<wordRes>("patches"));
        patchIds_ = mesh_.boundaryMesh().patchSet(names).sortedToc();
        if (patchIds_.empty())
        {
            FatalIOErrorInFunction(dict)
                << "patches " << flatOutput(names) << " in " << dict.name()
                << " match no patch. Patches: "
                << flatOutput(mesh_.boundaryMesh().names())
                << exit(FatalIOError);
        }
    }
    const Pair<scalar> xRange = freeSurfaceTools::getRange(dict, "xRange");
    xMin_ = xRange.first();
    xMax_ = xRange.second();
    stillWaterLevel_ = dict.getOrDefault<scalar>("stillWaterLevel", 0);
    freeSurfaceTools::getFrame(dict, horizontal_, vertical_);
    return true;
}


bool Foam::functionObjects::runUp::execute()
{
    tmp<volScalarField> talpha =
        freeSurfaceTools::lookupOrRead(mesh_, alphaName_);
    const volScalarField& alpha = talpha();
    scalar R = -GREAT;
    if (patchIds_.size())
    {
        for (const label patchi : patchIds_)
        {
            const scalarField& ap = alpha.boundaryField()[patchi];
            const vectorField& Cf = mesh_.C().boundaryField()[patchi];
            forAll(ap, facei)
            {
                if (ap[facei] >= threshold_ && inWindow(Cf[facei]))
                {
                    R = max(R, Cf[facei] & vertical_);
                }
            }
        }
    }
    else
    {
        const vectorField& C = mesh_.C().primitiveField();
        forAll(alpha, celli)
        {
            if (alpha[celli] >= threshold_ && inWindow(C[celli]))
            {
                R = max(R, C[celli] & vertical_);
            }
        }
    }
    reduce(R, maxOp<scalar>());
    if (R > -0.5*GREAT)
    {
        runUp_ = R - stillWaterLevel_;
        maxRunUp_ = max(maxRunUp_, runUp_);
    }
    else
    {
        runUp_ = -GREAT;
    }
    setProperty("maxRunUp", maxRunUp_);
    Log << type() << " " << name() << ": run-up " << runUp_
        << " m, max " << maxRunUp_ << " m" << endl;
    return true;
}


bool Foam::functionObjects::runUp::write()
{
    if (writeToFile() && Pstream::master())
    {
        writeCurrentTime(file());
        for (const scalar v : {runUp_, maxRunUp_})
        {
            if (v > -0.5*GREAT)
            {
                file() << tab << v;
            }
            else
            {
                file() << tab << "nan";
            }
        }
        file() << endl;
    }
    return true;
}
