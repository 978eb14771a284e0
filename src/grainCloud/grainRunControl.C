// SPDX-License-Identifier: GPL-3.0-or-later
#include "grainRunControl.H"
#include "IFstream.H"
#include "dictionary.H"
#include "OSspecific.H"
#include "TimePaths.H"
#include "PstreamReduceOps.H"
#include "error.H"
#include "functionObject.H"
#include "writeCheck.H"

#include <csignal>
#include <fstream>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <signal.h>
#include <sys/types.h>

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{
    volatile std::sig_atomic_t stopSignal = 0;

    //- The lock file of this process's run, removed at exit() too (a
    //  FatalError ends the process without unwinding the stack)
    std::string lockAtExit;

    //- postProcessing/runEnd/<startTime>/runEnd of this process's run
    //  (master; empty: none), the time name of its last completed step,
    //  and whether the run returned from its time loop: at exit() without
    //  it, the run ended on a FatalError (no stack unwinding)
    std::string runEndFile;
    std::string lastStepTime;
    bool runReturned = false;
    const char* returnReason = "endTime";

    //- Write runEndFile: an OpenFOAM dictionary of the reason the run
    //  ended, the last completed step's time and the error's message as a
    //  list of its non-empty lines (quotes and backslashes escaped)
    void writeRunEnd(const char* reason, const std::string& message)
    {
        std::ofstream os(runEndFile.c_str());
        os  << "FoamFile\n{\n    version     2.0;\n    format      ascii;\n"
            << "    class       dictionary;\n    object      runEnd;\n}\n\n"
            << "// How the run ended (grainRunControl): reason running (not"
            << " ended, or killed),\n// endTime, stopSignal or fatalError;"
            << " time: its last completed step\n\n"
            << "reason      " << reason << ";\n"
            << "time        " << lastStepTime << ";\n"
            << "message\n(\n";
        std::size_t begin = 0;
        while (begin < message.size())
        {
            std::size_t end = message.find('\n', begin);
            if (end == std::string::npos) end = message.size();
            const std::string line = message.substr(begin, end - begin);
            if (line.find_first_not_of(" \t") != std::string::npos)
            {
                os  << "    \"";
                for (const char c : line)
                {
                    if (c == '"' || c == '\\') os << '\\';
                    os  << c;
                }
                os  << "\"\n";
            }
            begin = end + 1;
        }
        os  << ");\n";
    }

    extern "C" void atRunExit()
    {
        if (!lockAtExit.empty())
        {
            std::remove(lockAtExit.c_str());
        }
        if (!runEndFile.empty() && !runReturned)
        {
            const std::string m = Foam::FatalIOError.message();
            writeRunEnd
            (
                "fatalError", m.empty() ? Foam::FatalError.message() : m
            );
        }
    }

    void registerAtRunExit()
    {
        static const bool registered = (std::atexit(atRunExit) == 0);
        (void)registered;
    }

    extern "C" void onStopSignal(int sig)
    {
        if (stopSignal && sig == SIGTERM)
        {
            // second SIGTERM in the same step: default action (terminate)
            std::signal(SIGTERM, SIG_DFL);
            std::raise(SIGTERM);
            return;
        }
        stopSignal = sig;
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::grainRunControl::checkControlDict
(
    const argList& args,
    const wordList& required
)
{
    const fileName path
    (
        args.rootPath()/args.globalCaseName()/"system"/"controlDict"
    );
    IFstream is(path);
    if (!is.good())
    {
        return;  // Time reports the missing file
    }
    const dictionary dict(is);
    scalar writeInterval = 1;
    if
    (
        dict.readIfPresent("writeInterval", writeInterval)
     && !(writeInterval > 0)
    )
    {
        FatalIOErrorInFunction(dict)
            << "writeInterval " << writeInterval << " in " << path
            << " must be > 0 (OpenFOAM divides by it)." << nl
            << "    Fix: set writeInterval to the time between writes"
            << " (writeControl runTime/adjustableRunTime) or to the number of"
            << " steps between writes (writeControl timeStep)."
            << exit(FatalIOError);
    }
    if (dict.getOrDefault<word>("startFrom", "latestTime") == "latestTime")
    {
        skipIncompleteTimes(args, required);
    }
}


void Foam::grainRunControl::skipIncompleteTimes
(
    const argList& args,
    const wordList& required
)
{
    const fileName casePath(args.path());
    // the master's times on every rank: each rank takes the same number of
    // steps of the loop below (its reduction is collective), even if its
    // own processor directory lacks a time (a directory missing here is
    // incomplete)
    wordList names;
    if (Pstream::master())
    {
        for (const instant& t : TimePaths::findTimes(casePath, "constant"))
        {
            if (t.name() != "constant")
            {
                names.append(t.name());
            }
        }
    }
    Pstream::scatter(names);
    const label nTimes = names.size();
    if (Pstream::parRun() && nTimes > 0)
    {
        // decomposePar gives no time directory to a rank whose cells hold
        // no grain (nothing to write): Time would stop the run ("processor
        // N has startTime 0"). Such a rank gets the latest time from the
        // undecomposed case (its uniform/ data), as the master has it.
        const fileName dir(casePath/names.last());
        const fileName global
        (
            args.rootPath()/args.globalCaseName()/names.last()
        );
        if (!isDir(dir) && isDir(global))
        {
            mkDir(dir);
            if (isDir(global/"uniform"))
            {
                cp(global/"uniform", dir);
            }
            Pout<< "grainRunControl: no directory " << names.last()
                << " in " << casePath.name() << " (no grain in its cells):"
                << " created from the case's" << endl;
        }
    }
    // from the latest down; the earliest is never moved
    for (label k = nTimes - 1; k > 0; --k)
    {
        const fileName dir(casePath/names[k]);
        DynamicList<word> missing;
        if (!isDir(dir))
        {
            missing.append(word("the directory"));
        }
        // in parallel a required file may be in the undecomposed case's
        // time directory instead (the grain state of a decomposed run)
        const fileName global
        (
            args.rootPath()/args.globalCaseName()/names[k]
        );
        for (const word& f : required)
        {
            if (!isFile(dir/f) && !(Pstream::parRun() && isFile(global/f)))
            {
                missing.append(f);
            }
        }
        for (const fileName& d : {dir, global})
        {
            for (const fileName& f : readDir(d, fileName::FILE, false))
            {
                if (f.hasExt("tmp"))
                {
                    missing.append(word(f + " (an interrupted write)"));
                }
            }
            if (!Pstream::parRun())
            {
                break;  // (dir is global)
            }
        }
        const bool incomplete = returnReduce(missing.size() > 0, orOp<bool>());
        if (!incomplete)
        {
            return;
        }
        const fileName aside(dir + ".incomplete");
        if (isDir(aside))
        {
            rmDir(aside);
        }
        if (isDir(dir) && !mv(dir, aside))
        {
            FatalErrorInFunction
                << "The latest time directory " << dir << " is incomplete"
                << " but cannot be moved aside to " << aside << nl
                << "    Fix: delete " << dir << " and restart."
                << exit(FatalError);
        }
        WarningInFunction
            << "The latest time directory " << names[k] << " is"
            << " incomplete (missing: " << flatOutput(missing)
            << (missing.empty() ? " here, incomplete on another rank" : "")
            << "): moved to " << aside.name() << " in " << casePath << "."
            << nl << "    startFrom latestTime starts from "
            << names[k - 1] << " instead." << endl;
    }
}


Foam::grainRunControl::grainRunControl(Time& runTime)
:
    runTime_(runTime),
    startTime_(runTime.value()),
    startClock_(runTime.elapsedClockTime())
{
    const scalar endTime = runTime.endTime().value();
    if (endTime <= startTime_ + 0.5*runTime.deltaTValue())
    {
        WarningInFunction
            << "endTime " << endTime << " is not after the start time "
            << startTime_ << ": no time step will run." << nl
            << "    Fix: raise endTime in system/controlDict, or check"
            << " startFrom/startTime (latestTime starts from the last time"
            << " directory)." << endl;
    }
    checkLaterWrites();
    lockCase();
    startRunEnd();
    stopSignal = 0;
    std::signal(SIGTERM, onStopSignal);
    std::signal(SIGUSR1, onStopSignal);
}


Foam::grainRunControl::~grainRunControl()
{
    if (!runEndFile.empty())
    {
        runReturned = true;
        writeRunEnd(returnReason, "");
        runEndFile.clear();
    }
    if (!lockFile_.empty())
    {
        std::remove(lockFile_.c_str());
        lockAtExit.clear();
    }
}


void Foam::grainRunControl::checkLaterWrites() const
{
    if
    (
        !Pstream::parRun()
     || runTime_.controlDict().getOrDefault<word>("startFrom", "latestTime")
     != "latestTime"
    )
    {
        return;
    }
    // the grain state of a decomposed run is written in the undecomposed
    // case (grainCloudIO.C): the master looks there for a later one
    const fileName root(runTime_.rootPath()/runTime_.globalCaseName());
    scalar later = -GREAT;
    if (Pstream::master())
    {
        const instantList times(Time::findTimes(root));
        const scalar tol = 1e-9*max(scalar(1), mag(runTime_.endTime().value()));
        for (const instant& t : times)
        {
            // a time moved aside as an interrupted write
            // (skipIncompleteTimes) is not a result to keep: the run redoes it
            if
            (
                t.value() > startTime_ + tol
             && isFile(root/t.name()/"grainState.h5")
             && !isDir(runTime_.path()/(t.name() + ".incomplete"))
            )
            {
                later = max(later, t.value());
            }
        }
    }
    Pstream::scatter(later);
    if (later > -GREAT)
    {
        FatalErrorInFunction
            << "the case " << root << " holds the grain state of t = "
            << later << ", later than this run's start time " << startTime_
            << " (the latest time of the processor directories): the run"
            << " would overwrite it." << nl
            << "    Fix: to continue from t = " << later << ", run"
            << " reconstructPar -latestTime in the earlier decomposition"
            << " before decomposePar -latestTime -force; if the earlier"
            << " processor directories are gone, the grain state is whole in "
            << root/name(later) << ": create the time directory " << later
            << " in every processor directory (grainFoam) or decompose the"
            << " fields of that time.  To start again from " << startTime_
            << ", remove the later time directories (or set startFrom"
            << " startTime in system/controlDict)."
            << exit(FatalError);
    }
}


void Foam::grainRunControl::lockCase()
{
    const fileName lock
    (
        runTime_.rootPath()/runTime_.globalCaseName()/".nscdFoam.lock"
    );
    // the master decides; every rank stops on a refusal (no rank left
    // waiting in a collective)
    label refused = 0;
    std::string holder;
    if (Pstream::master() && isFile(lock))
    {
        // plain text: "<pid> <host> <application>"
        std::ifstream is(lock.c_str());
        long pid = -1;
        std::string host, app;
        is >> pid >> host >> app;
        const bool here = host == std::string(hostName());
        // signal 0: does the process exist (EPERM: it does, not ours)
        const bool alive =
            pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno == EPERM);
        holder = app + " (process " + std::to_string(pid) + " on " + host + ")";
        if (!here || alive)
        {
            refused = 1;
        }
        else
        {
            WarningInFunction
                << "taking over the lock file " << lock << " of "
                << holder.c_str() << ", which no longer runs (killed?)"
                << endl;
        }
    }
    Pstream::scatter(refused);
    if (refused)
    {
        FatalErrorInFunction
            << (Pstream::master() ? holder.c_str() : "another solver")
            << " runs in this case (lock file " << lock << "): two solvers"
            << " would overwrite each other's results." << nl
            << "    Fix: wait for it to end, or run in a copy of the case; if"
            << " no solver runs there any more, remove " << lock << "."
            << exit(FatalError);
    }
    if (!Pstream::master())
    {
        return;
    }
    {
        std::ofstream os(lock.c_str());
        os  << long(pid()) << ' ' << std::string(hostName()) << ' '
            << std::string
               (
                   runTime_.controlDict().getOrDefault<word>
                   (
                       "application", "solver"
                   )
               )
            << '\n';
        os.close();
        if (!os)
        {
            std::remove(lock.c_str());
            FatalErrorInFunction
                << "Cannot write the lock file " << lock
                << noSpaceHint(lock.path()).c_str() << "." << nl
                << "    Fix: free disk space (or check the case directory's"
                << " permissions and quota)." << exit(FatalError);
        }
    }
    lockFile_ = lock;
    registerAtRunExit();
    lockAtExit = lock;
}


void Foam::grainRunControl::startRunEnd()
{
    if (!Pstream::master())
    {
        return;
    }
    const fileName dir
    (
        runTime_.globalPath()/functionObject::outputPrefix/"runEnd"
       /runTime_.timeName(runTime_.startTime().value())
    );
    mkDir(dir);
    runEndFile = dir/"runEnd";
    lastStepTime = runTime_.timeName();
    runReturned = false;
    returnReason = "endTime";
    registerAtRunExit();
    writeRunEnd("running", "");
}


bool Foam::grainRunControl::stopRequested() const
{
    return signalReceived() != 0;
}


Foam::label Foam::grainRunControl::signalReceived()
{
    return returnReduce(label(stopSignal), maxOp<label>());
}


bool Foam::grainRunControl::writeStep(const std::function<void()>& writeGrains)
{
    const label sig = signalReceived();
    const bool stop = sig != 0;
    const bool last =
        !(
            runTime_.value()
          < runTime_.endTime().value() - 0.5*runTime_.deltaTValue()
        );
    lastStepTime = runTime_.timeName();
    const bool scheduled = runTime_.writeTime();
    const bool written = scheduled || last || stop;
    // OpenFOAM's streams stop on a write that failed (a full disk) with a
    // bare "error in IOstream": caught, and reported by checkTimeWrite
    std::string failure;
    const bool throwing = FatalIOError.throwExceptions();
    try
    {
        if (written)
        {
            writeGrains();
        }
        if (written && !scheduled)
        {
            runTime_.writeNow();
        }
        else
        {
            runTime_.write();
        }
    }
    catch (const IOerror& err)
    {
        failure = err.message();
    }
    FatalIOError.throwExceptions(throwing);
    if (written || !failure.empty())
    {
        checkTimeWrite(runTime_, failure);
    }
    if (written)
    {
        const scalar span = runTime_.endTime().value() - startTime_;
        scalar f =
            span > 0
          ? min(max((runTime_.value() - startTime_)/span, scalar(0)), scalar(1))
          : 1;
        if (last)
        {
            f = 1;
        }
        const scalar clock = runTime_.elapsedClockTime() - startClock_;
        char line[128];
        if (f > 0 && f < 1)
        {
            std::snprintf
            (
                line, sizeof(line),
                "Progress: %.1f %% of the run, about %.0f s of clock time left",
                100*f, clock*(1 - f)/f
            );
        }
        else
        {
            std::snprintf
            (
                line, sizeof(line), "Progress: %.1f %% of the run", 100*f
            );
        }
        Info<< line;
        Info<< nl;
    }
    if (stop)
    {
        returnReason = "stopSignal";
        Info<< nl << "Stop signal " << sig
            <<
            (
                sig == SIGTERM ? " (SIGTERM)"
              : sig == SIGUSR1 ? " (SIGUSR1)"
              : ""
            )
            << " received: wrote"
            << " time " << runTime_.timeName() << " (continue with startFrom"
            << " latestTime) and stopped." << nl << endl;
        return false;
    }
    return true;
}


// ************************************************************************* //
