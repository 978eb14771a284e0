// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud run-health checks

Description
    The checks that make a run fail loudly instead of hanging, crashing on
    a signal or writing a state it cannot restart from:
      - a grain state file that cannot be used (damaged, truncated, NaN/Inf
        or negative values): FatalError naming the grain, the field and the
        previous write as the way out; states written atomically;
      - contact steps that did not converge: counted, warned at the first
        one, summarised with the worst overlap at the end of the run;
      - a fluid velocity that blew up (non-finite, or a cell Courant number
        above 1e4) before the grain step.
    Grains leaving the mesh: grainCloudLeaving.C.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "nscdMPI/DecomposedSystem.H"  // (unique_ptr member: complete type)
#include "volFields.H"
#include "Time.H"
#include "OSspecific.H"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{
    //- Name of the latest time directory of casePath before time t that
    //  holds a grain state (empty if none)
    Foam::word previousStateTime
    (
        const Foam::fileName& casePath,
        const Foam::scalar t
    )
    {
        using namespace Foam;
        word best;
        scalar bestValue = -GREAT;
        for (const instant& i : TimePaths::findTimes(casePath))
        {
            if
            (
                i.value() < t - SMALL*max(mag(t), scalar(1))
             && i.value() > bestValue
             && isFile(casePath/i.name()/grainCloud::stateFileName)
            )
            {
                best = i.name();
                bestValue = i.value();
            }
        }
        return best;
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

namespace
{
    //- nscd::InputError if the grain state file statePath is missing
    void checkStateFileExists(const Foam::fileName& statePath)
    {
        if (!Foam::isFile(statePath))
        {
            throw nscd::InputError
            (
                "Cannot find the grain state " + statePath
              + " (a run that never wrote grains here, or a write that was"
                " interrupted)"
            );
        }
    }
}


nscd::System Foam::grainCloud::readStateFile
(
    const fileName& statePath,
    const std::function<bool(const nscd::Vec3&, double)>& keep
) const
{
    try
    {
        checkStateFileExists(statePath);
        return nscd::System::readHDF5(statePath, keep, declareColumns_);
    }
    catch (const nscd::InputError& err)
    {
        stateFileError(statePath, err.what());
    }
    return nscd::System(dimension_);  // not reached
}


bool Foam::grainCloud::readStartColumn(const word& name)
{
    if (startStatePath_.empty())
    {
        return false;
    }
    try
    {
        return system_->readColumnHDF5(startStatePath_, name);
    }
    catch (const nscd::InputError& err)
    {
        stateFileError(startStatePath_, err.what());
    }
    return false;  // not reached
}


std::vector<double> Foam::grainCloud::readStateRadii
(
    const fileName& statePath,
    std::vector<long>& ids
) const
{
    try
    {
        checkStateFileExists(statePath);
        ids = nscd::System::grainIdsHDF5(statePath);
        return nscd::System::grainRadiiHDF5(statePath);
    }
    catch (const nscd::InputError& err)
    {
        stateFileError(statePath, err.what());
    }
    return {};  // not reached
}


void Foam::grainCloud::stateFileError
(
    const fileName& statePath,
    const std::string& what
) const
{
    const fileName timeDir(statePath.path());
    const word prev =
        previousStateTime(timeDir.path(), mesh_.time().value());
    OStringStream fix;
    if (prev.size())
    {
        fix << "restart from the previous write " << prev
            << " (startFrom startTime; startTime " << prev
            << "; in system/controlDict, or delete " << timeDir
            << " and use startFrom latestTime)";
    }
    else
    {
        fix << "no earlier time holds a grain state: create the"
            << " initial grains with grainDeposit";
    }
    FatalErrorInFunction
        << "Cannot use the grain state " << statePath << nl
        << "    " << what.c_str() << nl
        << "    Fix: " << fix.str().c_str() << exit(FatalError);
}


void Foam::grainCloud::writeStateFile
(
    const fileName& path,
    const std::function<void(const std::string&, const std::string&)>& write
) const
{
    const std::string tmp(path + ".tmp");
    std::string what;
    errno = 0;
    try
    {
        // a FoamFile header in the HDF5 user block: decomposePar and
        // reconstructPar read the header of every file of a time directory
        // and warn about a file without one
        std::ostringstream header;
        header
            << "FoamFile\n{\n    version     2.0;\n    format      binary;\n"
            << "    class       nscdGrainState;\n    location    \""
            << path.path().name() << "\";\n    object      " << path.name()
            << ";\n}\n// nscd grain state: an HDF5 file after this header (HDF5"
            << " user block), read it with h5dump or h5py\n";
        write(tmp, header.str());
        if (std::rename(tmp.c_str(), path.c_str()) != 0)
        {
            what =
                std::string("cannot rename ") + tmp + ": "
              + std::strerror(errno);
        }
    }
    catch (const std::runtime_error& err) // nscd::InputError, the XDMF datasets
    {
        what = err.what();
        if (errno != 0)
        {
            what += std::string(" (") + std::strerror(errno) + ")";
        }
    }
    if (what.empty())
    {
        return;
    }
    const int code = errno;
    std::remove(tmp.c_str());
    stateWriteFailed(path, what, code);
}


void Foam::grainCloud::stateWriteFailed
(
    const fileName& path,
    const std::string& what,
    const int code
) const
{
    // a time directory this write created and left empty would be taken by
    // startFrom latestTime: remove it
    const fileName dir(path.path());
    bool removed = false;
    if
    (
        isDir(dir)
     && readDir(dir, fileName::FILE).empty()
     && readDir(dir, fileName::DIRECTORY).empty()
    )
    {
        removed = rmDir(dir);
    }
    FatalErrorInFunction
        << "Writing the grain state " << path << " failed: " << what.c_str()
        << nl << "    " << path << " was not changed; the previous write"
        << " holds the last complete state." << nl << "    Fix: "
        << (code == ENOSPC ? "free disk space (no space left on device)"
            : "check the disk (space, quota, permissions)")
        << (removed ? " (the empty time directory was removed)" : "")
        << ", then restart from the last complete time directory."
        << exit(FatalError);
}


void Foam::grainCloud::setHeartbeat()
{
    system_->settings().heartbeat = [this](long done, double all)
    {
        char line[160];
        std::snprintf
        (
            line, sizeof(line), "sub-step %ld of about %.0f (%.1f %%)",
            done, all, 100*done/all
        );
        Info<< "    grain step to time " << mesh_.time().timeName() << ": "
            << line << endl;
    };
}


void Foam::grainCloud::recordStepHealth()
{
    const scalar t = mesh_.time().value();
    ++health_.steps;
    const scalar ov = report_.maxOverlap/max(minDiameter(), VSMALL);
    if (ov > health_.worstOverlap)
    {
        health_.worstOverlap = ov;
        health_.worstOverlapTime = t;
    }
    if (report_.relaxationFallbacks > 0)
    {
        ++health_.relaxationFallbacks;
    }
    if (report_.energyLimited > 0)
    {
        ++health_.energyLimited;
        health_.worstEnergyRaise =
            max(health_.worstEnergyRaise, report_.energyRaise);
        health_.minImpulseScale =
            min(health_.minImpulseScale, report_.impulseScale);
    }
    if (!report_.converged)
    {
        if (health_.notConverged++ == 0)
        {
            health_.firstNotConverged = t;
            const nscd::System::Settings& s = system_->settings();
            WarningInFunction
                << "The contact solver did NOT converge at time "
                << mesh_.time().timeName() << " (residual "
                << report_.residual << " > tolerance " << s.tolerance
                << " after maxIterations " << s.maxIterations
                << " sweeps; overlap " << ov << " d_min)." << nl
                << "    Grains may overlap; the end of the run counts these"
                << " steps and gives the worst overlap." << nl
                << "    Fix: raise maxIterations (or tolerance) in the"
                << " contactSolver dictionary of " << dict_.name() << endl;
        }
    }
}


Foam::grainCloud::~grainCloud()
{
    if (health_.steps == 0)
    {
        return;
    }
    logOutletSummary();
    if (health_.relaxationFallbacks)
    {
        Info<< "grainCloud: in " << health_.relaxationFallbacks << " of "
            << health_.steps << " grain steps the over-relaxed contact solve"
            << " had not converged after half of maxIterations and went on"
            << " with relaxation 1" << nl;
    }
    if (health_.notConverged)
    {
        OSstream& os = WarningInFunction;
        os  << "contact solver NOT converged in " << health_.notConverged
            << " of " << health_.steps << " grain steps (first at time "
            << health_.firstNotConverged << "); worst overlap/d_min "
            << health_.worstOverlap << " at time "
            << health_.worstOverlapTime << nl;
        if (health_.energyLimited)
        {
            os  << "    In " << health_.energyLimited << " of them the"
                << " impulses of the unconverged solve would have raised the"
                << " kinetic energy (by up to " << health_.worstEnergyRaise
                << " of the free-flight energy); they were scaled down"
                << " (factor >= " << health_.minImpulseScale << ") so that"
                << " the step dissipates." << nl;
        }
        os  << "    Fix: raise maxIterations in the contactSolver dictionary"
            << " of " << dict_.name() << endl;
    }
    else
    {
        Info<< "grainCloud summary: " << health_.steps << " grain steps,"
            << " contact solver converged in all; worst overlap/d_min "
            << health_.worstOverlap << " at time "
            << health_.worstOverlapTime << nl;
    }
    Info<< "grainCloud: inside-mesh checks " << health_.insideMeshSeconds
        << " s of clock time" << nl << endl;
}


void Foam::grainCloud::checkFluidBlowUp
(
    const volVectorField& U,
    scalar dt,
    const char* where
)
{
    // cell Courant number |U| dt/h, h the cell size (2D: of the cell's x-y
    // area): a diverged fluid stops the run with the cause instead of a
    // grain step of ~forever or a SIGFPE in the linear solver
    const fvMesh& mesh = U.mesh();
    const scalarField& V = mesh.V();
    const bool twoD = mesh.nSolutionD() == 2;
    const scalar depth = twoD ? mesh.bounds().span().z() : 1;
    scalar coMax = 0, uMax = 0;
    label cellMax = -1;
    bool finite = true;
    forAll(U, c)
    {
        const scalar u = mag(U[c]);
        if (!std::isfinite(u))
        {
            finite = false;
            cellMax = c;
            break;
        }
        const scalar h = twoD ? std::sqrt(V[c]/depth) : std::cbrt(V[c]);
        const scalar co = u*dt/h;
        if (co > coMax)
        {
            coMax = co;
            uMax = u;
            cellMax = c;
        }
    }
    const scalar coLimit = 1e4;
    const bool bad = !finite || coMax > coLimit;
    if (!returnReduce(bad, orOp<bool>()))
    {
        return;
    }
    // the failing ranks report (the others wait for the abort)
    if (bad)
    {
        OStringStream what;
        if (!finite)
        {
            what << "non-finite fluid velocity " << U[cellMax];
        }
        else
        {
            what << "fluid velocity " << uMax << " m/s, cell Courant number"
                 << " |U| dt/h = " << coMax << " > " << coLimit;
        }
        FatalErrorInFunction
            << "The fluid solution blew up at time "
            << mesh.time().timeName() << " (before the " << where << "): "
            << what.str().c_str() << " in cell " << cellMax << " at "
            << mesh.C()[cellMax] << nl
            << "    The last written time holds the last good state." << nl
            << "    Fix: reduce deltaT, or use adjustTimeStep yes with"
            << " maxCo 0.5 in system/controlDict." << exit(FatalError);
    }
}


// ************************************************************************* //
