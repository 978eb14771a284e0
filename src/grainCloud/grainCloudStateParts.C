// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud state written in parts (see grainCloud.H)

Description
    The HDF5 state of a decomposed run without a gather: each rank writes
    its own grains (and the contacts it solves) into its part,
    <case>/<time>/grainStateA/rank<N>.h5 (DecomposedSystem::statePart,
    then nscd::System::writeHDF5Part of the rank's own System, with its
    XDMF datasets), and the master joins the parts, through one small
    allgather of the grain counts and HDF5 virtual datasets (serial HDF5 >=
    1.10), into <case>/<time>/grainState.h5 (nscd::System::writeHDF5Joined):
    the one file a serial run, any number of ranks, h5py and ParaView (the
    XDMF) read as before, as long as the part directory stays beside it.

    Atomic: the parts go into the directory the state in place does not use
    (grainStateA, or grainStateB when the file in place reads grainStateA:
    a rewrite of the same time), the joined file is written to
    grainState.h5.tmp and renamed; only then is the other directory removed.
    A run killed at any point leaves the previous state readable. A part
    that cannot be written stops every rank (FatalError, disk full named).
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "nscdMPI/DecomposedSystem.H"
#include "OSspecific.H"

#include <cerrno>
#include <stdexcept>

// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::grainCloud::writeStateParts(const fileName& dir) const
{
    const fileName path(dir/stateFileName);
    // the part directory: the one the state in place does not read
    label useB = 0;
    if (Pstream::master())
    {
        mkDir(dir);
        for (const std::string& p : nscd::System::partsOfHDF5(path))
        {
            useB = useB || p.rfind("grainStateA/", 0) == 0;
        }
        const fileName sub(dir/(useB ? "grainStateB" : "grainStateA"));
        if (isDir(sub))
        {
            rmDir(sub);  // (left by a write that did not finish)
        }
        mkDir(sub);
    }
    Pstream::scatter(useB);  // (after the master made the directory)
    const word sub(useB ? "grainStateB" : "grainStateA");

    // this rank's part, from its own System (no copy)
    long nextId = 0;
    const nscd::System::StatePart part(decomposed_->statePart(nextId));
    const fileName piece
    (
        dir/sub/("rank" + Foam::name(Pstream::myProcNo()) + ".h5")
    );
    std::string what;
    int code = 0;
    errno = 0;
    try
    {
        system_->writeHDF5Part(piece, part);
        addXdmfDatasets
        (
            piece, part.first, part.nGrains, system_->lastStepDt()
        );
    }
    catch (const std::runtime_error& err)
    {
        code = errno;
        what = std::string("part ") + piece + ": " + err.what();
    }
    if (returnReduce(!what.empty(), orOp<bool>()))
    {
        if (Pstream::master())
        {
            rmDir(dir/sub);
        }
        stateWriteFailed
        (
            path, what.empty() ? "another rank's part failed" : what, code
        );
    }

    // the joined file, renamed into place; then the old parts go
    if (Pstream::master())
    {
        std::vector<std::string> parts;
        for (label r = 0; r < Pstream::nProcs(); ++r)
        {
            parts.push_back(sub + "/rank" + Foam::name(r) + ".h5");
        }
        writeStateFile
        (
            path,
            [&](const std::string& tmp, const std::string& header)
            {
                system_->writeHDF5Joined(tmp, parts, nextId, header);
            }
        );
        const fileName old(dir/(useB ? "grainStateA" : "grainStateB"));
        if (isDir(old))
        {
            rmDir(old);
        }
        writeXdmf(path);
    }
}

// ************************************************************************* //
