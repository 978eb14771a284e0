// SPDX-License-Identifier: GPL-3.0-or-later
#include "writeGridTime.H"

#include <cmath>

Foam::writeGridTime::writeGridTime
(
    const word& ctrlDictName,
    const argList& args
)
:
    Time(ctrlDictName, args),
    runStartTime_(startTime_)
{
    if (writeControl_ != wcRunTime && writeControl_ != wcAdjustableRunTime)
    {
        return;
    }
    const scalar origin =
        controlDict().getOrDefault<scalar>("startTime", 0);
    const scalar n = (startTime_ - origin)/writeInterval_;
    // on the grid to round-off, or before its origin: nothing to align
    if (n < 0 || std::abs(n - std::round(n)) < 1e-6)
    {
        return;
    }
    const scalar gridStart = origin + std::floor(n)*writeInterval_;
    Info<< "writeGridTime: the start time " << timeName(runStartTime_)
        << " is off the write grid " << origin << " + k " << writeInterval_
        << " (system/controlDict): the next write is at "
        << timeName(gridStart + writeInterval_) << nl << endl;
    startTime_ = gridStart;
    writeTimeIndex_ = 0;
}


Foam::dimensionedScalar Foam::writeGridTime::startTime() const
{
    return dimensionedScalar("startTime", dimTime, runStartTime_);
}
