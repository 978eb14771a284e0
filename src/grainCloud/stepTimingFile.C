// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: stepTimingFile (stepTimingFile.H)
\*---------------------------------------------------------------------------*/

#include "stepTimingFile.H"
#include "grainCloud.H"

namespace
{

Foam::List<Foam::stepDataFile::column> timingColumns(const bool coupled)
{
    Foam::List<Foam::stepDataFile::column> c
    ({
        {"deltaT", "s", "time step"},
        {
            "executionTime", "s",
            "CPU time since the start of the run (the log's ExecutionTime)"
        },
        {
            "clockTime", "s",
            "clock time since the start of the run (the log's ClockTime)"
        },
        {
            "insideMeshChecks", "s",
            "clock time of the grains' inside-mesh checks, summed"
        }
    });
    if (coupled)
    {
        c.append({"mapping", "s", "clock time of the grain mapping, summed"});
        c.append({"fluid", "s", "clock time of the fluid solve, summed"});
        c.append({"contacts", "s", "clock time of the grain step, summed"});
    }
    return c;
}

} // End anonymous namespace


// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::stepTimingFile::stepTimingFile(const Time& runTime, const bool coupled)
:
    runTime_(runTime),
    file_
    (
        runTime, "stepTiming",
        "computing time per step, after the write (the log's ExecutionTime"
        " and ClockTime lines and the end-of-run \"Timing [s]:\" line)",
        timingColumns(coupled)
    ),
    coupled_(coupled)
{}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::stepTimingFile::write
(
    const grainCloud* grains,
    const UList<scalar>& split
)
{
    scalarList row
    ({
        runTime_.deltaTValue(),
        runTime_.elapsedCpuTime(),
        runTime_.elapsedClockTime(),
        grains ? grains->health().insideMeshSeconds : 0
    });
    if (coupled_)
    {
        row.append(split);
    }
    file_.write(row);
}


// ************************************************************************* //
