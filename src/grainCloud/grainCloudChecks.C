// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud run-health checks (issue 27)

Description
    The checks that make a run fail loudly instead of hanging, crashing on
    a signal or losing grains silently:
      - a grain state file that cannot be used (damaged, truncated, NaN/Inf
        or negative values): FatalError naming the grain, the field and the
        previous write as the way out;
      - contact steps that did not converge: counted, warned at the first
        one, summarised with the worst overlap at the end of the run;
      - grain centres that left the mesh during a step: FatalError saying
        whether the grain crossed a grain wall patch, an open patch or a
        gap between wall patches;
      - a fluid velocity that blew up (non-finite, or a cell Courant number
        above 1e4) before the grain step.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "nscdMPI/DecomposedSystem.H"  // (unique_ptr member: complete type)
#include "volFields.H"
#include "Time.H"
#include "OSspecific.H"
#include "processorPolyPatch.H"
#include "emptyPolyPatch.H"
#include "indexedOctree.H"
#include "treeDataFace.H"
#include "Random.H"

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{
    //- Clock time spent in grainCloud::checkInsideMesh over the run [s]
    //  (reported in the end-of-run summary; tests/bench/faultChecks)
    double insideMeshSeconds = 0;

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
    const nscd::System& state
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
        state.writeHDF5(tmp, header.str());
        addXdmfDatasets(tmp);
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
    // a time directory this write created and left empty would be taken by
    // startFrom latestTime: remove it
    const fileName dir(path.path());
    bool removed = false;
    if
    (
        readDir(dir, fileName::FILE).empty()
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
    Info<< "grainCloud: inside-mesh checks " << insideMeshSeconds
        << " s of clock time" << nl << endl;
}


Foam::label Foam::grainCloud::findLocalCell
(
    const point& p,
    const label hint,
    const boundBox& local
) const
{
    if (hint >= 0)
    {
        if
        (
            clearRadiusSqr_.size() == mesh_.nCells()
         && magSqr(p - clearCentres_[hint]) < clearRadiusSqr_[hint]
        )
        {
            return hint;
        }
        if (mesh_.pointInCell(p, hint))
        {
            return hint;
        }
    }
    return local.contains(p) ? mesh_.findCell(p) : -1;
}


void Foam::grainCloud::computeCellClearance() const
{
    // Around an interior point, a ball that meets no boundary face lies in
    // the mesh (it is connected and does not cross the boundary): each
    // cell's centre and the distance from it to the nearest face of this
    // rank's boundary (processor faces included, so "in the mesh" is "on
    // this rank"), exact through an octree of the boundary faces, with a
    // 10 % margin for warped faces (whose tet decomposition, which
    // findCell uses, differs slightly from the face triangles the octree
    // measures). In 2D the grains lie in the plane z = zMid_ and the empty
    // front and back patches are no boundary for them: distances in that
    // plane, to the other patches.
    const polyBoundaryMesh& patches = mesh_.boundaryMesh();
    DynamicList<label> faces(mesh_.nBoundaryFaces());
    for (const polyPatch& pp : patches)
    {
        if (dimension_ == 2 && isA<emptyPolyPatch>(pp))
        {
            continue;
        }
        forAll(pp, i)
        {
            faces.append(pp.start() + i);
        }
    }
    clearCentres_ = mesh_.cellCentres();
    if (dimension_ == 2)
    {
        for (point& c : clearCentres_)
        {
            c.z() = zMid_;
        }
    }
    clearRadiusSqr_.setSize(mesh_.nCells(), 0);
    if (faces.empty())
    {
        clearRadiusSqr_ = GREAT;
        return;
    }
    Random rndGen(123456);
    treeBoundBox bb
    (
        treeBoundBox(mesh_.points()).extend(rndGen, 1e-4)
    );
    bb.min() -= point::uniform(ROOTVSMALL);
    bb.max() += point::uniform(ROOTVSMALL);
    const indexedOctree<treeDataFace> tree
    (
        treeDataFace(false, mesh_, labelList(faces)),
        bb, 8, 10, 3.0
    );
    const scalar span2 = magSqr(bb.span());
    forAll(clearCentres_, celli)
    {
        const pointIndexHit hit = tree.findNearest(clearCentres_[celli], span2);
        clearRadiusSqr_[celli] =
            hit.hit()
          ? sqr(0.9)*magSqr(hit.hitPoint() - clearCentres_[celli])
          : 0;
    }
}


void Foam::grainCloud::checkInsideMesh()
{
    const auto start = std::chrono::steady_clock::now();
    struct addTime
    {
        std::chrono::steady_clock::time_point t0;
        ~addTime()
        {
            insideMeshSeconds += std::chrono::duration<double>
            (
                std::chrono::steady_clock::now() - t0
            ).count();
        }
    } timer{start};
    const label n = system_->size();
    UList<label> cellHint(column<label>(cellHintColumn));
    // this rank's own bounds (polyMesh::bounds() is global in parallel)
    const boundBox local(mesh_.points(), false);
    // the search-free test first (clearCentres_): most grains stay within
    // the clear ball of their last cell from step to step
    if (mesh_.changing())
    {
        clearCentres_.clear();
        clearRadiusSqr_.clear();
    }
    else if (clearRadiusSqr_.size() != mesh_.nCells())
    {
        computeCellClearance();
    }
    labelList found(n, 0);
    bool allLocal = true;
    for (label i = 0; i < n; ++i)
    {
        label& c = cellHint[i];
        c = findLocalCell(meshPosition(i), c, local);
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
    return exitPatches(paths);
}


Foam::labelList Foam::grainCloud::exitPatches
(
    const List<Pair<point>>& paths
) const
{
    // first boundary face crossed by each path on this rank
    scalarList tFirst(paths.size(), GREAT);
    labelList patch(paths.size(), -1);
    forAll(paths, k)
    {
        firstCrossing(paths[k].first(), paths[k].second(), tFirst[k], patch[k]);
    }
    // the rank whose face is crossed first names the patch (the indices of
    // the non-processor patches are the same on every rank); on a tie
    // (crossing points within exitTieDistance(), e.g. a point on an edge
    // shared by faces of two ranks) an outlet patch wins, as in
    // firstCrossing.  Two list reductions for all the grains.
    scalarList tGlobal(tFirst);
    Pstream::listCombineGather(tGlobal, minEqOp<scalar>());
    Pstream::listCombineScatter(tGlobal);
    const label nPatches = mesh_.boundaryMesh().size();
    const scalar tie = exitTieDistance();
    forAll(paths, k)
    {
        const scalar len = mag(paths[k].second() - paths[k].first());
        if
        (
            !(tGlobal[k] < GREAT && (tFirst[k] - tGlobal[k])*len <= tie)
         || patch[k] < 0
        )
        {
            patch[k] = -1;
        }
        else if (outletPatches_.found(patch[k]))
        {
            patch[k] += nPatches;    // priority of the outlets on a tie
        }
    }
    Pstream::listCombineGather(patch, maxEqOp<label>());
    Pstream::listCombineScatter(patch);
    for (label& p : patch)
    {
        if (p >= nPatches)
        {
            p -= nPatches;
        }
    }
    return patch;
}


Foam::scalar Foam::grainCloud::exitTieDistance() const
{
    // round-off of the crossing points is ~1e-16 of the coordinates; 1e-9
    // of the (global) mesh span is far above it and far below any grain
    return 1e-9*mag(mesh_.bounds().span());
}


void Foam::grainCloud::firstCrossing
(
    const point& x0,
    const point& x1,
    scalar& tBest,
    label& patchBest
) const
{
    const vector dx(x1 - x0);
    const scalar len = mag(dx);

    // first boundary face crossed by the path x0 -> x1 on this rank
    tBest = GREAT;
    patchBest = -1;
    if (len < VSMALL)
    {
        return;
    }
    // the path's crossing with a face: the exact point-in-polygon test of
    // face::intersection (the face-centre triangle fan, barycentric bounds)
    // widened by faceTol, relative to the face size (barycentric
    // coordinates), so that a point on an edge shared by two faces is in
    // both and no point between two faces is in none
    const scalar faceTol = 1e-6;
    // the path parameter t is in [0, 1] (x0 inside the mesh, x1 outside);
    // tTol: exitTieDistance() in t, both the round-off allowed at x0 or x1
    // and the tie of two crossings
    const scalar tTol = exitTieDistance()/len;
    const pointField& points = mesh_.points();
    const polyBoundaryMesh& pbm = mesh_.boundaryMesh();
    bool bestIsOutlet = false;
    for (const polyPatch& pp : pbm)
    {
        if (pp.coupled() || isA<emptyPolyPatch>(pp))
        {
            continue;
        }
        const bool isOutlet = outletPatches_.found(pp.index());
        const vectorField::subField Cf(pp.faceCentres());
        const vectorField::subField Sf(pp.faceAreas());
        forAll(pp, facei)
        {
            // outwards only (Sf points out of the mesh)
            if ((dx & Sf[facei]) <= 0) continue;
            const pointHit hit
            (
                pp[facei].intersection
                (
                    x0, dx, Cf[facei], points, intersection::FULL_RAY, faceTol
                )
            );
            if (!hit.hit()) continue;
            const scalar t = hit.distance();
            if (t < -tTol || t > 1 + tTol) continue;
            // the first face along the path; on a tie (the same crossing
            // point to within exitTieDistance: an edge shared by two faces,
            // or faces of two patches in one plane) an outlet patch wins
            // over a wall or an open patch, so that a grain whose centre
            // crosses the boundary on the rim of an orifice leaves through
            // it; between two faces of one kind the first found stays
            const bool tie = mag(t - tBest) <= tTol;
            if
            (
                (!tie && t < tBest)
             || (tie && isOutlet && !bestIsOutlet)
            )
            {
                tBest = t;
                patchBest = pp.index();
                bestIsOutlet = isOutlet;
            }
        }
    }
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


void Foam::grainCloud::checkFluidBlowUp
(
    const volVectorField& U,
    scalar dt,
    const char* where
)
{
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
