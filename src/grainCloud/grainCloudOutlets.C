// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud outlet patches

Description
    outletPatches: open patches through which grains leave the domain (a
    silo's orifice, an open top), so that a run goes on, with the grains
    counted, where leaving grains would otherwise stop it.  A grain whose
    centre crossed one during a step (grainCloud::checkInsideMesh,
    grainCloudLeaving.C) is removed from the nscd system (nscd::System::
    removeGrains: per-grain state compacted, its contacts dropped, ids not
    reused) and counted per patch: number and mass [kg] (2D: over the mesh
    depth), in the log, in postProcessing/grainOutlets/<startTime>/
    grainOutlets.dat (a row per step, stepDataFile) and, at every write,
    in <time>/uniform/grainOutlets, from which a restart continues the
    counts.  Decomposed grains: the rank that owns a leaving grain removes
    it (nscd::mpi::DecomposedSystem::removeOwned drops its ghost copies on
    the other ranks) and the counts are summed over the ranks, so every
    rank holds the totals.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "nscdMPI/DecomposedSystem.H"  // (removeOwned)
#include "grainDictionaryTools.H"
#include "Time.H"
#include "OSspecific.H"
#include "IFstream.H"
#include "OFstream.H"
#include "writeCheck.H"
#include "emptyPolyPatch.H"

#include <sstream>

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{
    const Foam::word outletCountsName("grainOutlets");
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::grainCloud::readOutletPatches()
{
    outletPatches_.clear();
    if (!dict_.found("outletPatches"))
    {
        return;
    }
    const polyBoundaryMesh& pbm = mesh_.boundaryMesh();
    outletPatches_ = grainTools::patchIds(pbm, dict_, "outletPatches", "");
    for (const label patchi : outletPatches_)
    {
        const polyPatch& pp = pbm[patchi];
        if (patchWalls_.found(pp.name()))
        {
            FatalIOErrorInFunction(dict_)
                << "Patch " << pp.name() << " is in outletPatches of "
                << dict_.name() << " but it is a wall for the grains (type"
                << " wall or listed in wallPatches): grains cannot leave"
                << " through it." << nl
                << "    Fix: remove it from outletPatches, or give"
                << " wallPatches without it." << exit(FatalIOError);
        }
        if (pp.coupled() || isA<emptyPolyPatch>(pp))
        {
            FatalIOErrorInFunction(dict_)
                << "Patch " << pp.name() << " (type " << pp.type() << ") in"
                << " outletPatches of " << dict_.name() << " is not a"
                << " boundary grains can cross." << nl
                << "    Fix: list only open patches (e.g. an outlet of type"
                << " patch)." << exit(FatalIOError);
        }
    }
    outletCount_.setSize(outletPatches_.size(), 0);
    outletMass_.setSize(outletPatches_.size(), 0);

    // counts of the start time (a restart continues them); in parallel the
    // undecomposed case's copy if the processor directory has none
    const Time& runTime = mesh_.time();
    fileName path(runTime.timePath()/"uniform"/outletCountsName);
    if (Pstream::parRun() && !isFile(path))
    {
        path =
            runTime.globalPath()/runTime.timeName()/"uniform"
           /outletCountsName;
    }
    if (isFile(path))
    {
        IFstream is(path);
        const dictionary counts(is);
        forAll(outletPatches_, k)
        {
            const word& name = pbm[outletPatches_[k]].name();
            if (counts.found(name))
            {
                const dictionary& d = counts.subDict(name);
                outletCount_[k] = d.get<label>("grains");
                outletMass_[k] = d.get<scalar>("mass");
            }
        }
        if (sum(outletCount_) > 0)
        {
            Info<< "grainCloud: outlet counts continued from " << path << nl;
        }
    }

    outletStepCount_.setSize(outletPatches_.size(), 0);
    outletStepMass_.setSize(outletPatches_.size(), 0);
}


void Foam::grainCloud::removeOutletGrains
(
    const labelList& grains,
    const labelList& patches
)
{
    const scalar depth = dimension_ == 2 ? depth_ : 1;
    labelList count(outletPatches_.size(), Zero);
    scalarList mass(outletPatches_.size(), Zero);
    List<labelList> ids(outletPatches_.size());
    std::vector<std::size_t> indices;
    forAll(grains, k)
    {
        const label slot = outletPatches_.find(patches[k]);
        ++count[slot];
        mass[slot] += system_->mass(grains[k])*depth;
        ids[slot].append(label(system_->grainIds()[grains[k]]));
        indices.push_back(std::size_t(grains[k]));
    }
    if (decomposed_)
    {
        // each grain is removed by its owner: the counts are summed over
        // the ranks, the ids gathered for the log
        Pstream::listCombineGather(count, plusEqOp<label>());
        Pstream::listCombineScatter(count);
        Pstream::listCombineGather(mass, plusEqOp<scalar>());
        Pstream::listCombineScatter(mass);
        forAll(ids, slot)
        {
            List<labelList> perRank(Pstream::nProcs());
            perRank[Pstream::myProcNo()] = ids[slot];
            Pstream::gatherList(perRank);
            ids[slot].clear();
            for (const labelList& l : perRank)
            {
                ids[slot].append(l);
            }
        }
    }

    const std::vector<std::size_t> removed =
        decomposed_
      ? decomposed_->removeOwned(indices)
      : system_->removeGrains(indices);
    lastRemoved_.setSize(label(removed.size()));
    forAll(lastRemoved_, k)
    {
        lastRemoved_[k] = label(removed[k]);
    }
    if (!decomposed_)
    {
        // positions before the step, for the checks of the other grains
        std::size_t k = 0, r = 0;
        for (std::size_t i = 0; i < oldPositions_.size(); ++i)
        {
            if (r < removed.size() && removed[r] == i)
            {
                ++r;
                continue;
            }
            oldPositions_[k++] = oldPositions_[i];
        }
        oldPositions_.resize(k);
    }

    const word t(mesh_.time().timeName());
    forAll(outletPatches_, slot)
    {
        if (count[slot] == 0)
        {
            continue;
        }
        outletCount_[slot] += count[slot];
        outletMass_[slot] += mass[slot];
        outletStepCount_[slot] += count[slot];
        outletStepMass_[slot] += mass[slot];
        const word& name = mesh_.boundaryMesh()[outletPatches_[slot]].name();
        Info<< "grainOutlets: " << count[slot] << " grains (mass "
            << mass[slot] << " kg) left through " << name << " at time " << t
            << ", ids";
        Foam::sort(ids[slot]);
        forAll(ids[slot], k)
        {
            if (k == 10)
            {
                Info<< " ...";
                break;
            }
            Info<< ' ' << ids[slot][k];
        }
        Info<< "; total through " << name << ": " << outletCount_[slot]
            << " grains, " << outletMass_[slot] << " kg" << endl;
    }
}


void Foam::grainCloud::writeOutletCounts() const
{
    if (outletPatches_.empty())
    {
        return;
    }
    const Time& runTime = mesh_.time();
    std::ostringstream os;
    os.precision(17);
    os  << "FoamFile\n{\n    version     2.0;\n    format      ascii;\n"
        << "    class       dictionary;\n    location    \""
        << runTime.timeName()
        << "/uniform\";\n    object      " << outletCountsName << ";\n}\n\n";
    os  << "// grains removed through the outlet patches since the case"
        << " started (grainCloud\n// outletPatches); mass [kg] (2D: over"
        << " the mesh depth).  A restart continues them.\n\n";
    forAll(outletPatches_, k)
    {
        os  << mesh_.boundaryMesh()[outletPatches_[k]].name() << nl
            << "{\n    grains " << outletCount_[k] << ";\n    mass "
            << outletMass_[k] << ";\n}\n\n";
    }
    auto put = [&os](const fileName& dir)
    {
        mkDir(dir);
        std::ofstream f(dir/outletCountsName);
        f << os.str();
        f.close();
        if (!f)
        {
            FatalErrorInFunction
                << "Cannot write " << dir/outletCountsName
                << noSpaceHint(dir).c_str() << "." << nl
                << "    Fix: free disk space (or check the quota), then"
                << " continue with startFrom latestTime." << exit(FatalError);
        }
    };
    put(runTime.timePath()/"uniform");
    if (Pstream::parRun() && Pstream::master())
    {
        put(runTime.globalPath()/runTime.timeName()/"uniform");
    }
}


void Foam::grainCloud::writeOutletRow()
{
    if (outletPatches_.empty())
    {
        return;
    }
    // a solver's cloud (writeStepStatistics), not grainDeposit's
    if (statisticsFile_)
    {
        if (!outletFile_)
        {
            // created at the first step of a solver
            List<stepDataFile::column> columns;
            for (const label patchi : outletPatches_)
            {
                const std::string name(mesh_.boundaryMesh()[patchi].name());
                const std::string mass("their mass (2D: over the mesh depth)");
                columns.append
                ({
                    name + "_grains", "1",
                    "grains removed through " + name + " in the step"
                });
                columns.append({name + "_mass", "kg", mass});
                columns.append
                ({
                    name + "_totalGrains", "1",
                    "grains removed through " + name + " since the case started"
                });
                columns.append({name + "_totalMass", "kg", mass});
            }
            outletFile_.reset
            (
                new stepDataFile
                (
                    mesh_.time(), outletCountsName,
                    "grains removed through the outlet patches (grainCloud"
                    " outletPatches)",
                    columns
                )
            );
        }
        scalarList row(4*outletPatches_.size());
        forAll(outletPatches_, slot)
        {
            row[4*slot] = outletStepCount_[slot];
            row[4*slot + 1] = outletStepMass_[slot];
            row[4*slot + 2] = outletCount_[slot];
            row[4*slot + 3] = outletMass_[slot];
        }
        outletFile_->write(row);
    }
    outletStepCount_ = 0;
    outletStepMass_ = 0;
}


void Foam::grainCloud::logOutletSummary() const
{
    if (outletPatches_.empty())
    {
        return;
    }
    Info<< "grainOutlets summary (since the case started):";
    forAll(outletPatches_, k)
    {
        Info<< ' ' << mesh_.boundaryMesh()[outletPatches_[k]].name() << ' '
            << outletCount_[k] << " grains " << outletMass_[k] << " kg;";
    }
    Info<< " grains left " << nGrainsTotal() << nl;
}


// ************************************************************************* //
