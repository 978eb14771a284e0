// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud, grains leaving the mesh (see grainCloud.H)

Description
    After every grain step, each grain centre is located in this rank's
    cells; a grain no rank holds crossed the boundary in the step: the
    face its path crossed first says how (both searches: grainMeshExits).
    Through an outletPatches patch it is removed and counted
    (grainCloudOutlets.C); through a grain wall patch, an open patch or a
    gap between wall patches the run stops (FatalError with the fix), so
    that grains never vanish silently.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "nscdMPI/DecomposedSystem.H"  // (unique_ptr member: complete type)
#include "Time.H"
#include "processorPolyPatch.H"

#include <chrono>
#include <cmath>
#include <limits>

// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::grainCloud::checkInsideMesh()
{
    const auto start = std::chrono::steady_clock::now();
    struct addTime
    {
        std::chrono::steady_clock::time_point t0;
        scalar& total;
        ~addTime()
        {
            total += std::chrono::duration<double>
            (
                std::chrono::steady_clock::now() - t0
            ).count();
        }
    } timer{start, health_.insideMeshSeconds};
    const label n = system_->size();
    UList<label> cellHint(column<label>(cellHintColumn));
    // this rank's own bounds (polyMesh::bounds() is global in parallel)
    const boundBox local(mesh_.points(), false);
    // the search-free test first (clearCentres_): most grains stay within
    // the clear ball of their last cell from step to step
    exits_.updateClearance();
    labelList found(n, 0);
    bool allLocal = true;
    for (label i = 0; i < n; ++i)
    {
        label& c = cellHint[i];
        c = exits_.findLocalCell(meshPosition(i), c, local);
        found[i] = c >= 0 ? 1 : 0;
        allLocal = allLocal && found[i];
    }
    if (Pstream::parRun())
    {
        Pstream::listCombineGather(found, maxEqOp<label>());
        Pstream::listCombineScatter(found);
    }
    else if (allLocal)
    {
        return;
    }
    // grains through an outlet patch are removed (the same on every rank:
    // found and exitPatches are reduced); any other exit stops the run
    DynamicList<label> lost;
    for (label i = 0; i < n; ++i)
    {
        if (!found[i])
        {
            lost.append(i);
        }
    }
    const labelList exits(exitPatches(lost));
    DynamicList<label> outGrains, outPatches;
    forAll(lost, k)
    {
        const label i = lost[k];
        const label patch = exits[k];
        if (patch >= 0 && outletPatches_.found(patch))
        {
            outGrains.append(i);
            outPatches.append(patch);
            continue;
        }
        grainLeftMesh
        (
            i,
            system_->grainIds()[i],
            meshPoint(oldPositions_[i]),
            meshPosition(i),
            patch
        );
    }
    if (outGrains.size())
    {
        removeOutletGrains(outGrains, outPatches);
    }
}


void Foam::grainCloud::grainLeftMesh
(
    const label i,
    const long id,
    const point& x0,
    const point& x1,
    const label patch
) const
{
    const string how(describeExit(x0, x1, patch));
    FatalErrorInFunction
        << "Grain " << i << " (grainId " << label(id)
        << ") left the mesh at time "
        << mesh_.time().timeName() << ": from " << x0 << " to " << x1
        << " (radius " << system_->radii()[i] << "), " << how.c_str() << nl
        << "    The last written time holds the last good state."
        << exit(FatalError);
}


Foam::labelList Foam::grainCloud::exitPatches(const labelList& grains) const
{
    List<Pair<point>> paths(grains.size());
    forAll(grains, k)
    {
        paths[k] = Pair<point>
        (
            meshPoint(oldPositions_[grains[k]]),
            meshPosition(grains[k])
        );
    }
    return exits_.exitPatches(paths, outletPatches_);
}


Foam::string Foam::grainCloud::describeExit
(
    const point& x0,
    const point& x1,
    const label patch
) const
{
    const vector dx(x1 - x0);
    const polyBoundaryMesh& pbm = mesh_.boundaryMesh();
    if (patch >= 0)
    {
        const polyPatch& pp = pbm[patch];
        OStringStream os;
        if (patchWalls_.found(pp.name()))
        {
            os  << "through the wall patch " << pp.name() << ": the contact"
                << " with the wall did not hold it (the grain moved "
                << mag(dx) << " m in the step)." << nl
                << "    Fix: reduce deltaT or maxDisplacementFraction; check"
                << " that the wall's velocity (movingWalls) is not faster"
                << " than the grains can follow.";
        }
        else
        {
            os  << "through the open patch " << pp.name() << " (type "
                << pp.type() << "), which is not a wall for the grains"
                << " (not of type wall, or not in wallPatches of "
                << dict_.name() << ")." << nl
                << "    Fix: if " << pp.name() << " is a wall, make it of"
                << " type wall in constant/polyMesh/boundary or list it in"
                << " wallPatches; to let grains leave through it, list it"
                << " in outletPatches.";
        }
        return os.str();
    }
    OStringStream os;
    os  << "through a gap between wall patches (its path crosses no"
        << " boundary face: e.g. a corner where the wall faces do not meet)."
        << nl << "    Fix: check that the wall patches close the domain"
        << " (checkMesh) and reduce deltaT or maxDisplacementFraction.";
    return os.str();
}

// ************************************************************************* //
