// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud decomposed over the ranks (see grainCloud.H)

Description
    grainDecomposition decomposed: in a parallel run each rank owns the
    grains whose centre lies in its cells (OpenFOAM's decomposition) and
    holds ghost copies of the other ranks' grains within a halo of its own;
    it detects and solves only its contacts (nscd::mpi::DecomposedSystem,
    src/nscdMPI: the interface-averaged NSCD of Visseq et al. 2012).

    Owner function: a grain stays with this rank while its centre lies in
    one of its cells, tested first against the clear ball of its last cell
    (grainMeshExits, processor faces included), then pointInCell, then
    a search of this rank's cells; the owner of a grain that left them is the
    rank whose cells hold it (asked of every rank by the library).

    Halo: 6 r_max, so that a contact pair (reach 2 r_max + the alert
    distance) is on the rank that solves it; DecomposedSystem::advance
    sub-steps a step whose fastest grain would reach beyond it.

    Start: every rank reads its part of the state, the grains within the
    halo of its cells' bounding box (nscd::System::readHDF5 with a region:
    no rank holds the whole system), unless something replicates the grains
    (then every rank reads the whole state); write: each rank writes its
    grains into its part, joined into the undecomposed case's grainState.h5
    (grainCloudStateParts.C; a run restarts from it on any number of ranks).
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "nscdMPI/DecomposedSystem.H"

#include "Tuple2.H"
#include "grainVectorTools.H"

#include <algorithm>
#include <unordered_map>

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{
    //- Whether a parallel run keeps every grain on every rank (logged:
    //  why) for mode (grainDecomposition) and notDecomposable (the
    //  solver's reasons); FatalIOError if grainDecomposition decomposed was
    //  asked for explicitly, FatalError if the state was already read in
    //  parts (partRead)
    bool replicatedBecause
    (
        const Foam::dictionary& dict,
        const Foam::word& mode,
        const Foam::string& notDecomposable,
        const bool partRead
    )
    {
        using namespace Foam;
        // what the decomposed system does not follow yet
        DynamicList<string> why;
        if (!notDecomposable.empty())
        {
            why.append(notDecomposable);
        }
        if (why.size() || mode == "replicated")
        {
            if (partRead)
            {
                FatalErrorInFunction
                    << "The grain state was read in parts for a decomposed"
                    << " run, but the grains are replicated (partStart and"
                    << " selectDecomposition disagree): report this."
                    << exit(FatalError);
            }
            OStringStream os;
            forAll(why, k)
            {
                os << (k ? "; " : "") << why[k].c_str();
            }
            if (dict.found("grainDecomposition"))
            {
                FatalIOErrorInFunction(dict)
                    << "grainDecomposition decomposed: not available with "
                    << os.str().c_str() << "." << nl
                    << "    Fix: use grainDecomposition replicated (every rank"
                    << " holds every grain), or remove the keyword."
                    << exit(FatalIOError);
            }
            Info<< "grainCloud: every rank holds every grain"
                << " (grainDecomposition replicated: " << os.str().c_str()
                << ")" << endl;
            return true;
        }
        return false;
    }

    //- notDecomposable with the contactSolver settings of dict that the
    //  decomposed solve does not follow (nscd::Subdomain: plain Gauss-Seidel
    //  sweeps, relaxation 1, stopping on the max test, alternating with the
    //  averaging of the interface grains' copies) appended; an unknown
    //  method or convergence word stops the run in applySolverSettings,
    //  before selectDecomposition
    Foam::string withSolverReasons
    (
        const Foam::dictionary& dict,
        const Foam::string& notDecomposable
    )
    {
        using namespace Foam;
        const dictionary& cs = dict.subOrEmptyDict("contactSolver");
        const word method(cs.getOrDefault<word>("method", "NLGS"));
        const scalar relaxation(cs.getOrDefault<scalar>("relaxation", 1));
        const word convergence(cs.getOrDefault<word>("convergence", "max"));
        OStringStream os;
        if (method != "NLGS")
        {
            os << " method " << method;
        }
        if (relaxation != 1)
        {
            os << " relaxation " << relaxation;
        }
        if (convergence != "max")
        {
            os << " convergence " << convergence;
        }
        if (os.str().empty())
        {
            return notDecomposable;
        }
        return
            notDecomposable + (notDecomposable.empty() ? "" : "; ")
          + "contactSolver" + os.str().c_str()
          + " (the decomposed contact solve is method NLGS, relaxation 1,"
            " convergence max: its sweeps alternate with the averaging of"
            " the interface grains)";
    }
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

bool Foam::grainCloud::partStart(const string& notDecomposable) const
{
    // the conditions of selectDecomposition that replicate the grains,
    // known before the state is read
    return
        Pstream::parRun()
     && withSolverReasons(dict_, notDecomposable).empty()
     && dict_.getOrDefault<word>("grainDecomposition", "decomposed")
        == "decomposed";
}


void Foam::grainCloud::readStatePart(const fileName& statePath)
{
    // the radii of the whole state (the halo, the smallest diameter) and
    // its ids, without its grains
    double rMin = GREAT, rMax = 0;
    for (const double r : readStateRadii(statePath, startIds_))
    {
        rMin = std::min(rMin, r);
        rMax = std::max(rMax, r);
    }
    startRMax_ = rMax > 0 ? rMax : VSMALL;  // (no grain: any positive halo)
    minDiameterAll_ = rMax > 0 ? 2*rMin : 0;
    // the grains within the halo of this rank's cells (selectDecomposition)
    const scalar halo = 6*startRMax_;
    localBounds_ = boundBox(mesh_.points(), false);
    const nscd::Vec3 lo(toSystem(localBounds_.min()));
    const nscd::Vec3 hi(toSystem(localBounds_.max()));
    const int dim = dimension_;
    whole_.reset
    (
        new nscd::System
        (
            readStateFile
            (
                statePath,
                [=](const nscd::Vec3& x, double)
                {
                    for (int k = 0; k < dim; ++k)
                    {
                        if (x[k] < lo[k] - halo || x[k] > hi[k] + halo)
                        {
                            return false;
                        }
                    }
                    return true;
                }
            )
        )
    );
}


void Foam::grainCloud::selectDecomposition(const string& notDecomposable)
{
    const bool partRead = startRMax_ > 0;
    const word mode
    (
        dict_.getOrDefault<word>("grainDecomposition", "decomposed")
    );
    if (mode != "decomposed" && mode != "replicated")
    {
        FatalIOErrorInFunction(dict_)
            << "grainDecomposition " << mode << ": unknown; use decomposed"
            << " (each rank holds the grains in its cells, the default) or"
            << " replicated (every rank holds every grain)."
            << exit(FatalIOError);
    }
    if ((!Pstream::parRun() || mode == "replicated") && !partRead)
    {
        if (Pstream::parRun())
        {
            Info<< "grainCloud: every rank holds every grain"
                << " (grainDecomposition replicated)" << endl;
        }
        return;
    }
    if
    (
        replicatedBecause
        (
            dict_, mode, withSolverReasons(dict_, notDecomposable), partRead
        )
    )
    {
        return;
    }

    exits_.updateClearance();
    // findCell and pointInCell (the owner function) use the tet base points
    // of the faces, which the mesh builds at the first call by an exchange
    // over the processor patches (collective): built here on every rank, as
    // a rank whose cells hold no grain would never call them and leave the
    // others waiting in that exchange
    (void)mesh_.tetBasePtIs();
    double rMax = startRMax_;
    if (!partRead)
    {
        // every rank holds the whole system here
        localBounds_ = boundBox(mesh_.points(), false);
        for (const double r : system_->radii())
        {
            rMax = std::max(rMax, r);
        }
        minDiameterAll_ = system_->minDiameter();
        startIds_ = system_->grainIds();
        if (!(rMax > 0))
        {
            rMax = VSMALL;  // no grain: any positive halo
        }
    }
    const double halo = 6*rMax;
    try
    {
        auto owner = [this](const nscd::Vec3& x, long id)
        {
            return ownerOf(x, id);
        };
        decomposed_.reset
        (
            partRead
          ? new nscd::mpi::DecomposedSystem
            (
                std::move(*whole_), long(startIds_.size()), MPI_COMM_WORLD,
                owner, halo
            )
          : new nscd::mpi::DecomposedSystem
            (
                std::move(*whole_), MPI_COMM_WORLD, owner, halo
            )
        );
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction
            << "Decomposing the grains: " << err.what() << nl
            << "    Fix: every grain centre must lie inside the mesh."
            << exit(FatalError);
    }
    whole_.reset();
    system_ = &decomposed_->system();
    // ghosts also over this rank's cells (for the cell mapping)
    const point& lo = localBounds_.min();
    const point& hi = localBounds_.max();
    decomposed_->setRegionBox
    (
        toSystem(lo),
        toSystem(hi)
    );
    // those ghosts now (the box counts from the next exchange on): the
    // coupling maps the grains before the first step (vansCloud's
    // constructor and the first step's mapping), and a grain overlapping
    // this rank's cells from another's would be missing there, then appear
    // after the first step, a jump of eps that no flux carries
    decomposed_->exchange();
    labelList perRank(Pstream::nProcs(), 0);
    perRank[Pstream::myProcNo()] = label(decomposed_->nOwned());
    Pstream::gatherList(perRank);
    Info<< "grainCloud: grains decomposed over " << Pstream::nProcs()
        << " ranks (owned per rank " << perRank << ", halo " << halo
        << " m; " << (partRead ? "each rank read its part" : "every rank read")
        << " of the start state)" << endl;
}


int Foam::grainCloud::ownerOf(const nscd::Vec3& x, const long id) const
{
    auto hint = ownerCellHint_.find(id);
    const label c = exits_.findLocalCell
    (
        meshPoint(x),
        hint == ownerCellHint_.end() ? -1 : hint->second,
        localBounds_
    );
    if (c < 0)
    {
        if (hint != ownerCellHint_.end())
        {
            ownerCellHint_.erase(hint);
        }
        return nscd::mpi::DecomposedSystem::notHere;
    }
    ownerCellHint_[id] = c;
    return Pstream::myProcNo();
}


nscd::StepReport Foam::grainCloud::advanceDecomposed(const scalar dt)
{
    nscd::StepReport rep = decomposed_->advance(dt, maxDisplacementFraction_);
    // the rank's contacts, cohesive contacts and overlap: the run's
    // (residual, converged and the sub-steps are the same on every rank)
    scalar contacts = rep.contacts;
    reduce(contacts, sumOp<scalar>());
    rep.contacts = int(contacts);
    scalar cohesive = rep.cohesiveContacts;
    reduce(cohesive, sumOp<scalar>());
    rep.cohesiveContacts = int(cohesive);
    reduce(rep.maxOverlap, maxOp<scalar>());
    return rep;
}


void Foam::grainCloud::checkDecomposedInsideMesh
(
    const std::vector<nscd::Vec3>& oldPositions,
    const std::vector<long>& oldIds
)
{
    // owned grains whose centre no rank's cells hold: their paths, on
    // every rank, for the exit diagnosis (exitPatches is collective)
    const std::vector<int>& lost = decomposed_->unclaimed();
    if (returnReduce(label(lost.size()), sumOp<label>()) == 0)
    {
        return;  // (every step: one reduction, not the lists' gather)
    }
    List<List<Pair<point>>> paths(Pstream::nProcs());
    List<Pair<point>>& mine = paths[Pstream::myProcNo()];
    mine.setSize(label(lost.size()));
    forAll(mine, k)
    {
        const label i = lost[k];
        const long id = system_->grainIds()[i];
        const auto old = std::find(oldIds.begin(), oldIds.end(), id);
        const point x1(meshPosition(i));
        mine[k] = Pair<point>
        (
            old == oldIds.end()
          ? x1
          : meshPoint(oldPositions[old - oldIds.begin()]),
            x1
        );
    }
    Pstream::gatherList(paths);
    Pstream::scatterList(paths);
    List<Pair<point>> all;
    label first = 0;
    forAll(paths, r)
    {
        if (r == Pstream::myProcNo())
        {
            first = all.size();
        }
        all.append(paths[r]);
    }
    const labelList exits(exits_.exitPatches(all, outletPatches_));
    DynamicList<label> outGrains, outPatches;
    forAll(mine, k)
    {
        const label i = lost[k];
        const label patch = exits[first + k];
        if (patch >= 0 && outletPatches_.found(patch))
        {
            outGrains.append(i);
            outPatches.append(patch);
            continue;
        }
        // the rank of the lost grain stops the run (FatalError: MPI_Abort)
        grainLeftMesh
        (
            i, system_->grainIds()[i], mine[k].first(), mine[k].second(), patch
        );
    }
    // removed by their owners, counted over the ranks (collective: every
    // rank is here when some grain of some rank left)
    removeOutletGrains(outGrains, outPatches);
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

bool Foam::grainCloud::owned(const label i) const
{
    return !decomposed_ || decomposed_->owned()[i];
}


Foam::scalar Foam::grainCloud::heatContent() const
{
    if (!decomposed_)
    {
        return system_->heatContent();
    }
    return returnReduce
    (
        system_->heatContent(&decomposed_->owned()),
        sumOp<scalar>()
    );
}


void Foam::grainCloud::sumOverCopies
(
    std::vector<double>& values,
    const int components
)
{
    if (decomposed_)
    {
        decomposed_->sumToOwners(values, components);
        decomposed_->copyToGhosts(values, components);
    }
    else
    {
        grainTools::sumOverRanks(values);
    }
}


template<class Type>
bool Foam::grainCloud::fromStartOrder
(
    const UList<Type>& whole,
    List<Type>& local
) const
{
    if (!decomposed_)
    {
        local = whole;
        return true;
    }
    if (whole.size() != label(startIds_.size()))
    {
        return false;
    }
    std::unordered_map<long, label> index;
    for (std::size_t k = 0; k < startIds_.size(); ++k)
    {
        index[startIds_[k]] = label(k);
    }
    const label n = system_->size();
    List<Type> out(n, Zero);
    for (label i = 0; i < n; ++i)
    {
        const auto it = index.find(system_->grainIds()[i]);
        if (it == index.end())
        {
            return false;
        }
        out[i] = whole[it->second];
    }
    local.transfer(out);
    return true;
}


// the per-grain list types of the coupling's old restart lists
template bool
Foam::grainCloud::fromStartOrder(const UList<scalar>&, List<scalar>&) const;
template bool
Foam::grainCloud::fromStartOrder(const UList<vector>&, List<vector>&) const;


Foam::label Foam::grainCloud::nGrainsTotal() const
{
    return
        decomposed_
      ? returnReduce(label(decomposed_->nOwned()), sumOp<label>())
      : label(system_->size());
}

// ************************************************************************* //
