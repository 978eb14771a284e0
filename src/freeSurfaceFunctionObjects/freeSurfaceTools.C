// SPDX-License-Identifier: GPL-3.0-or-later
#include "freeSurfaceTools.H"
#include "grainDictionaryTools.H"
#include "grainCloud.H"

void Foam::freeSurfaceTools::checkKeywords
(
    const dictionary& dict,
    const wordList& own
)
{
    static const wordList generic
    {
        "type", "libs", "enabled", "log", "timeStart", "timeEnd",
        "executeControl", "executeInterval", "writeControl", "writeInterval",
        "region", "writePrecision", "writeToFile", "useUserTime",
        "updateHeader"
    };
    grainTools::checkKeywords(dict, own, generic);
}


Foam::tmp<Foam::volScalarField> Foam::freeSurfaceTools::lookupOrRead
(
    const fvMesh& mesh,
    const word& name
)
{
    const volScalarField* fp = mesh.findObject<volScalarField>(name);
    if (fp)
    {
        return tmp<volScalarField>(*fp);
    }
    IOobject io
    (
        name,
        mesh.time().timeName(),
        mesh,
        IOobject::MUST_READ,
        IOobject::NO_WRITE,
        false
    );
    if (!io.typeHeaderOk<volScalarField>(true))
    {
        FatalErrorInFunction
            << "Field " << name << " is neither registered nor readable at"
            << " time " << mesh.time().timeName() << nl
            << "    Fix: check the field name (keyword 'alpha')."
            << exit(FatalError);
    }
    return tmp<volScalarField>::New(io, mesh);
}


Foam::vector Foam::freeSurfaceTools::getDirection
(
    const dictionary& dict,
    const word& key,
    const vector& deflt
)
{
    const vector d = dict.getOrDefault<vector>(key, deflt);
    if (mag(d) < SMALL)
    {
        FatalIOErrorInFunction(dict)
            << key << " " << d << " in " << dict.name() << " is a zero vector."
            << " Fix: give a direction, e.g. (0 1 0)." << exit(FatalIOError);
    }
    return d/mag(d);
}


void Foam::freeSurfaceTools::getFrame
(
    const dictionary& dict,
    vector& horizontal,
    vector& vertical
)
{
    horizontal = getDirection(dict, "horizontalDirection", vector(1, 0, 0));
    vertical = getDirection(dict, "verticalDirection", vector(0, 1, 0));
    if (mag(horizontal & vertical) > 1e-6)
    {
        FatalIOErrorInFunction(dict)
            << "horizontalDirection and verticalDirection in " << dict.name()
            << " are not orthogonal" << exit(FatalIOError);
    }
}


Foam::Pair<Foam::scalar> Foam::freeSurfaceTools::getRange
(
    const dictionary& dict,
    const word& key
)
{
    if (!dict.found(key))
    {
        return Pair<scalar>(-GREAT, GREAT);
    }
    const Pair<scalar> r = dict.get<Pair<scalar>>(key);
    if (!(r.second() > r.first()))
    {
        FatalIOErrorInFunction(dict)
            << key << " (" << r.first() << " " << r.second() << ") in "
            << dict.name() << " must be (min max) with max > min"
            << exit(FatalIOError);
    }
    return r;
}


void Foam::freeSurfaceTools::writeColumnHeader
(
    functionObjects::writeFile& wf,
    const string& title,
    const List<string>& columns
)
{
    if (wf.writeToFile() && Pstream::master())
    {
        wf.writeHeader(wf.file(), title);
        wf.writeCommented(wf.file(), "Time");
        for (const string& column : columns)
        {
            wf.writeTabbed(wf.file(), column);
        }
        wf.file() << endl;
    }
}


const Foam::grainCloud& Foam::freeSurfaceTools::grainsOf
(
    const fvMesh& mesh,
    const functionObject& fo
)
{
    const grainCloudReference* ref =
        mesh.findObject<grainCloudReference>(grainCloud::registryName);
    if (!ref)
    {
        FatalErrorInFunction
            << fo.type() << " " << fo.name() << ": no grainCloud on mesh "
            << mesh.name() << nl << "    Fix: use it with grainFoam, vansFoam"
            << " or vansInterFoam." << exit(FatalError);
    }
    return ref->cloud();
}
