// SPDX-License-Identifier: GPL-3.0-or-later
#include "grainCentreOfMass.H"
#include "freeSurfaceTools.H"
#include "grainCloud.H"
#include "addToRunTimeSelectionTable.H"

namespace Foam
{
namespace functionObjects
{
    defineTypeNameAndDebug(grainCentreOfMass, 0);
    addToRunTimeSelectionTable
    (
        functionObject,
        grainCentreOfMass,
        dictionary
    );
}
}


Foam::functionObjects::grainCentreOfMass::grainCentreOfMass
(
    const word& name,
    const Time& runTime,
    const dictionary& dict
)
:
    fvMeshFunctionObject(name, runTime, dict),
    writeFile(mesh_, name, typeName, dict),
    fluxPoint_(Zero),
    fluxNormal_(0, -1, 0),
    bandHalfWidth_(0),
    values_(9, Zero)
{
    read(dict);
    List<string> columns({"mass", "x", "y", "z", "Ux", "Uy", "Uz"});
    if (flux())
    {
        columns.append(string("massFlux"));
        columns.append(string("speedMassFlux"));
    }
    freeSurfaceTools::writeColumnHeader
    (
        *this,
        "Centre of mass of the moving grains [kg, m, m/s] (2D: mass per unit"
        " depth); massFlux [kg/s] and speedMassFlux [kg m/s^2] through the"
        " band |(x - " + Foam::name(fluxPoint_) + ") . "
      + Foam::name(fluxNormal_) + "| <= " + Foam::name(bandHalfWidth_)
      + " m",
        columns
    );
}


bool Foam::functionObjects::grainCentreOfMass::read(const dictionary& dict)
{
    freeSurfaceTools::readBase(*this, dict);
    freeSurfaceTools::checkKeywords
    (
        dict,
        {"fluxPoint", "fluxNormal", "fluxBandHalfWidth"}
    );
    bandHalfWidth_ = dict.getOrDefault<scalar>("fluxBandHalfWidth", 0);
    if (bandHalfWidth_ < 0)
    {
        FatalIOErrorInFunction(dict)
            << "fluxBandHalfWidth " << bandHalfWidth_ << " in " << dict.name()
            << " must be >= 0 [m] (0: no flux columns)"
            << exit(FatalIOError);
    }
    if
    (
        (dict.found("fluxPoint") || dict.found("fluxNormal"))
     && !(bandHalfWidth_ > 0)
    )
    {
        FatalIOErrorInFunction(dict)
            << "fluxPoint/fluxNormal in " << dict.name() << " need"
            << " fluxBandHalfWidth > 0 [m]" << nl
            << "    Fix: add fluxBandHalfWidth (larger than a grain's"
            << " displacement in a step)." << exit(FatalIOError);
    }
    fluxPoint_ = dict.getOrDefault<point>("fluxPoint", Zero);
    fluxNormal_ =
        freeSurfaceTools::getDirection(dict, "fluxNormal", vector(0, -1, 0));
    return true;
}


bool Foam::functionObjects::grainCentreOfMass::execute()
{
    const grainCloud& cloud = freeSurfaceTools::grainsOf(mesh_, *this);
    const nscd::System& s = cloud.system();
    scalarList sums(9, Zero);
    const scalar w = bandHalfWidth_;
    for (std::size_t i = 0; i < s.size(); ++i)
    {
        if (!cloud.owned(i) || s.fixed(i)) continue;
        const scalar m = s.mass(i);
        const vector x(cloud.meshPosition(i));
        const nscd::Vec3& vi = s.velocities()[i];
        const vector v(vi.x(), vi.y(), vi.z());
        sums[0] += m;
        for (direction c = 0; c < 3; ++c)
        {
            sums[1 + c] += m*x[c];
            sums[4 + c] += m*v[c];
        }
        if (w > 0 && mag((x - fluxPoint_) & fluxNormal_) <= w)
        {
            const scalar mdot = m*(v & fluxNormal_)/(2*w);
            sums[7] += mdot;
            sums[8] += mdot*mag(v);
        }
    }
    if (cloud.decomposed())
    {
        reduce(sums, sumOp<scalarList>());
    }
    values_ = sums;
    const scalar M = max(sums[0], VSMALL);
    for (label c = 1; c < 7; ++c)
    {
        values_[c] /= M;
    }
    Log << type() << " " << name() << ": mass " << values_[0]
        << ", centre (" << values_[1] << " " << values_[2] << " "
        << values_[3] << "), velocity (" << values_[4] << " " << values_[5]
        << " " << values_[6] << ")" << endl;
    return true;
}


bool Foam::functionObjects::grainCentreOfMass::write()
{
    if (writeToFile() && Pstream::master())
    {
        writeCurrentTime(file());
        const label n = flux() ? 9 : 7;
        for (label c = 0; c < n; ++c)
        {
            file() << tab << values_[c];
        }
        file() << endl;
    }
    return true;
}
