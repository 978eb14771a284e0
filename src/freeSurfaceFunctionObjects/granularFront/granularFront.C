// SPDX-License-Identifier: GPL-3.0-or-later
#include "granularFront.H"
#include "freeSurfaceTools.H"
#include "grainCloud.H"
#include "addToRunTimeSelectionTable.H"

namespace Foam
{
namespace functionObjects
{
    defineTypeNameAndDebug(granularFront, 0);
    addToRunTimeSelectionTable(functionObject, granularFront, dictionary);
}
}


Foam::functionObjects::granularFront::granularFront
(
    const word& name,
    const Time& runTime,
    const dictionary& dict
)
:
    fvMeshFunctionObject(name, runTime, dict),
    writeFile(mesh_, name, typeName, dict),
    h0_(0),
    bottom_(0),
    bandHalfWidth_(0),
    direction_(1, 0, 0),
    vertical_(0, 1, 0),
    smoothingTime_(0),
    startTime_(-GREAT),
    front_(0),
    velocity_(0),
    maxVelocity_(0),
    froude_(0),
    found_(false)
{
    read(dict);
    freeSurfaceTools::writeColumnHeader
    (
        *this,
        "Granular front at y = bottom + h0 = "
      + Foam::name(bottom_ + h0_) + " m; Fr_f = v_f/sqrt(|g| h0)",
        {"frontPosition", "frontVelocity", "maxFrontVelocity", "froudeNumber"}
    );
}


bool Foam::functionObjects::granularFront::read(const dictionary& dict)
{
    freeSurfaceTools::readBase(*this, dict);
    freeSurfaceTools::checkKeywords
    (
        dict,
        {
            "h0", "bottom", "bandHalfWidth", "frontDirection",
            "smoothingTime", "startTime", "verticalDirection"
        }
    );
    h0_ = dict.get<scalar>("h0");
    if (!(h0_ > 0))
    {
        FatalIOErrorInFunction(dict)
            << "h0 " << h0_ << " in " << dict.name() << " must be > 0 [m]"
            << " (the still-water depth)" << exit(FatalIOError);
    }
    bottom_ = dict.getOrDefault<scalar>("bottom", 0);
    bandHalfWidth_ = dict.getOrDefault<scalar>("bandHalfWidth", 0);
    smoothingTime_ = dict.getOrDefault<scalar>("smoothingTime", 0);
    if (bandHalfWidth_ < 0 || smoothingTime_ < 0)
    {
        FatalIOErrorInFunction(dict)
            << "bandHalfWidth and smoothingTime in " << dict.name()
            << " must be >= 0" << exit(FatalIOError);
    }
    startTime_ = dict.getOrDefault<scalar>("startTime", -GREAT);
    direction_ =
        freeSurfaceTools::getDirection(dict, "frontDirection", vector(1, 0, 0));
    vertical_ =
        freeSurfaceTools::getDirection
        (
            dict, "verticalDirection", vector(0, 1, 0)
        );
    return true;
}


bool Foam::functionObjects::granularFront::execute()
{
    const grainCloud& cloud = freeSurfaceTools::grainsOf(mesh_, *this);
    const nscd::System& s = cloud.system();
    const nscd::Vec3& gv = s.gravity();
    const vector g(gv.x(), gv.y(), gv.z());
    const scalar magG = mag(g);
    if (magG < SMALL)
    {
        FatalErrorInFunction
            << "granularFront " << name() << ": zero gravity, Fr_f undefined"
            << exit(FatalError);
    }
    const vector& up = vertical_;
    const scalar yBand = bottom_ + h0_;

    scalar xf = -GREAT;
    const std::vector<double>& r = s.radii();
    for (std::size_t i = 0; i < s.size(); ++i)
    {
        if (!cloud.owned(i)) continue;  // (decomposed: ghosts)
        const vector p(cloud.meshPosition(i));
        if (mag((p & up) - yBand) <= r[i] + bandHalfWidth_)
        {
            xf = max(xf, (p & direction_) + r[i]);
        }
    }
    if (cloud.decomposed())
    {
        reduce(xf, maxOp<scalar>());
    }
    const scalar t = time_.value();
    found_ = xf > -0.5*GREAT;
    if (found_)
    {
        front_ = xf;
        if (t_.size() && t <= t_.last())
        {
            // same time executed twice (start/restart): keep the last
            xf_.last() = xf;
        }
        else
        {
            t_.append(t);
            xf_.append(xf);
        }
        // drop the samples older than the window (keep at least two)
        label first = 0;
        while (t_.size() - first > 2 && t - t_[first] > smoothingTime_ + SMALL)
        {
            ++first;
        }
        if (first > 0)
        {
            const scalarList tk(SubList<scalar>(t_, t_.size() - first, first));
            const scalarList xk
            (
                SubList<scalar>(xf_, xf_.size() - first, first)
            );
            t_ = tk;
            xf_ = xk;
        }
        const label n = t_.size();
        if (n >= 2)
        {
            // least-squares slope (n = 2: the backward difference)
            scalar tm = 0, xm = 0;
            for (label k = 0; k < n; ++k) { tm += t_[k]; xm += xf_[k]; }
            tm /= n;
            xm /= n;
            scalar stt = 0, stx = 0;
            for (label k = 0; k < n; ++k)
            {
                stt += sqr(t_[k] - tm);
                stx += (t_[k] - tm)*(xf_[k] - xm);
            }
            velocity_ = stt > 0 ? stx/stt : 0;
            if (t >= startTime_)
            {
                maxVelocity_ = max(maxVelocity_, velocity_);
            }
        }
    }
    froude_ = maxVelocity_/sqrt(magG*h0_);
    Log << type() << " " << name() << ": front " << front_ << " m, velocity "
        << velocity_ << " m/s, max " << maxVelocity_ << " m/s, Fr_f "
        << froude_ << endl;
    return true;
}


bool Foam::functionObjects::granularFront::write()
{
    if (writeToFile() && Pstream::master())
    {
        writeCurrentTime(file());
        if (found_)
        {
            file() << tab << front_ << tab << velocity_;
        }
        else
        {
            file() << tab << "nan" << tab << "nan";
        }
        file() << tab << maxVelocity_ << tab << froude_ << endl;
    }
    return true;
}
