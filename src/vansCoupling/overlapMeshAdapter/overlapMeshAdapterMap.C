// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: overlapMeshAdapter, the grain -> cell mapping: owner ranks,
  the library's map of the owned grains, halo overlaps of grains straddling
  a processor boundary, grain volumes, W_g and phi_c (see overlapMeshAdapter.H)
\*---------------------------------------------------------------------------*/

#include "overlapMeshAdapter.H"
#include "foamTools.H"

#include "Pstream.H"
#include "ops.H"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace om = overlapMapping;

// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::overlapMeshAdapter::checkRadii
(
    const double* radii,
    label n
) const
{
    // Radii must be valid everywhere (the library checks only mapped grains)
    for (label g = 0; g < n; ++g)
    {
        if (!(radii[g] > 0) || !std::isfinite(radii[g]))
        {
            FatalErrorInFunction
                << "Grain " << g << " has a non-positive or non-finite radius "
                << radii[g] << exit(FatalError);
        }
    }
}


Foam::labelList Foam::overlapMeshAdapter::grainOwners
(
    const om::Vec3* centres,
    label n
) const
{
    labelList owner(n, labelMax);
    if (sumOverCopies_)
    {
        // decomposed grains: this rank's if its cells hold the centre, else
        // a ghost mapped by the processor-boundary search
        const label me = Pstream::myProcNo();
        for (label g = 0; g < n; ++g)
        {
            om::Vec3 x(centres[g]);
            if (twoD_)
            {
                x[2] = zMid();
            }
            owner[g] = cellMesh_->findCell(x) >= 0 ? me : labelMin;
        }
    }
    else if (Pstream::parRun())
    {
        const label me = Pstream::myProcNo();
        for (label g = 0; g < n; ++g)
        {
            om::Vec3 x(centres[g]);
            if (twoD_)
            {
                x[2] = zMid();
            }
            if (cellMesh_->findCell(x) >= 0)
            {
                owner[g] = me;
            }
        }
        Pstream::listCombineGather(owner, minEqOp<label>());
        Pstream::listCombineScatter(owner);
    }
    else
    {
        owner = Pstream::myProcNo();
    }
    return owner;
}


void Foam::overlapMeshAdapter::mapOwned
(
    const om::Vec3* centres,
    const double* radii,
    label n,
    labelList& owner
)
{
    std::vector<label> owned;
    owned.reserve(n);
    centres_.clear();
    radii_.clear();
    for (label g = 0; g < n; ++g)
    {
        if (owner[g] == Pstream::myProcNo())
        {
            owned.push_back(g);
            centres_.push_back(centres[g]);
            if (twoD_)
            {
                centres_.back()[2] = zMid();   // nscd discs lie at z = 0
            }
            radii_.push_back(radii[g]);
        }
    }
    try
    {
        mapper_->map(centres_, radii_);
    }
    catch (const std::exception& err)
    {
        FatalErrorInFunction
            << "overlapMapping: " << err.what() << exit(FatalError);
    }
    const std::vector<om::label>& gc = mapper_->grainCell();
    for (std::size_t i = 0; i < owned.size(); ++i)
    {
        if (gc[i] < 0)
        {
            owner[owned[i]] = labelMax;   // reported by checkOutside
        }
    }
    const std::size_t ne = mapper_->nEntries();
    entryGrain_.reserve(ne);
    for (std::size_t e = 0; e < ne; ++e)
    {
        entryGrain_.push_back(owned[mapper_->entryGrain()[e]]);
        entryCell_.push_back(mapper_->entryCell()[e]);
        entryVolume_.push_back(mapper_->entryVolume()[e]);
    }
}


void Foam::overlapMeshAdapter::checkOutside
(
    const om::Vec3* centres,
    const double* radii,
    label n,
    const labelList& owner
) const
{
    for (label g = 0; g < n; ++g)
    {
        if (owner[g] == labelMax)
        {
            const om::Vec3& x = centres[g];
            FatalErrorInFunction
                << "Grain " << g << " at (" << x[0] << ' ' << x[1] << ' '
                << (twoD_ ? zMid() : x[2]) << ") (radius " << radii[g]
                << ") has its centre outside the mesh " << mesh_.bounds()
                << nl << "    Fix: move the grain inside the domain (check"
                << " the grain state and the mesh: grainDeposit writes grains"
                << " inside the mesh; a grain may also have escaped through a"
                << " gap between wall patches)" << exit(FatalError);
        }
    }
}


void Foam::overlapMeshAdapter::mapHalo
(
    label g,
    const om::Vec3& c,
    double r
)
{
    // Quick reject: the grain misses every processor-boundary cell
    const int nd = twoD_ ? 2 : 3;
    for (int k = 0; k < nd; ++k)
    {
        if (c[k] + r < procMin_[k] || c[k] - r > procMax_[k])
        {
            return;
        }
    }

    const om::CellMesh& m = *cellMesh_;
    if (++stamp_ == 0)
    {
        std::fill(visited_.begin(), visited_.end(), 0u);
        stamp_ = 1;
    }
    auto near = [&](om::label j)
    {
        const om::Vec3& bc = m.boundCentre(j);
        const double R = m.boundRadius(j) + r;
        double d2 =
            (bc[0] - c[0])*(bc[0] - c[0]) + (bc[1] - c[1])*(bc[1] - c[1]);
        if (!twoD_)
        {
            d2 += (bc[2] - c[2])*(bc[2] - c[2]);
        }
        return d2 < R*R;
    };

    // Seeds: processor-boundary cells near the grain; then breadth-first
    // through face neighbours while the overlap is non-zero (as the library)
    std::vector<om::label> queue;
    for (const om::label j : procCells_)
    {
        if (near(j))
        {
            visited_[j] = stamp_;
            queue.push_back(j);
        }
    }
    const double depth = m.depth();
    const om::Vec2 c2(c[0], c[1]);
    std::size_t head = 0;
    while (head < queue.size())
    {
        const om::label k = queue[head++];
        double vol = 0;
        if (twoD_)
        {
            if (m.convex(k) && m.outsideDistance2D(k, c[0], c[1]) >= r)
            {
                continue;
            }
            vol = om::discPolygonMoments
            (
                c2, r, m.polygon(k), m.polygonSize(k)
            ).area*depth;
        }
        else
        {
            vol = om::sphereCellOverlap(m, k, c, r, false).volume;
        }
        if (!(vol > 0.0))
        {
            continue;
        }
        entryGrain_.push_back(g);
        entryCell_.push_back(k);
        entryVolume_.push_back(vol);
        for
        (
            const om::label* nb = m.neighboursBegin(k);
            nb != m.neighboursEnd(k);
            ++nb
        )
        {
            if (visited_[*nb] != stamp_)
            {
                visited_[*nb] = stamp_;
                if (near(*nb))
                {
                    queue.push_back(*nb);
                }
            }
        }
    }
}


void Foam::overlapMeshAdapter::setGrainVolumes(const double* radii, label n)
{
    const double k = settings_.effectiveDiameterFactor;
    grainVolume_.resize(n);
    for (label g = 0; g < n; ++g)
    {
        const double r = k*radii[g];
        grainVolume_[g] = twoD_
            ? om::pi*r*r*cellMesh_->depth()
            : om::sphereVolume(r);
    }
}


void Foam::overlapMeshAdapter::finishMap()
{
    // W_g summed over ranks
    mappedVolume_.assign(nGrains_, 0.0);
    for (std::size_t e = 0; e < entryCell_.size(); ++e)
    {
        mappedVolume_[entryGrain_[e]] += entryVolume_[e];
    }
    sumOverRanks(mappedVolume_, 1);

    // phi_c = sum_g V_gc / V_c
    phi_.assign(mesh_.nCells(), 0.0);
    for (std::size_t e = 0; e < entryCell_.size(); ++e)
    {
        phi_[entryCell_[e]] += entryVolume_[e];
    }
    const scalarField& V = mesh_.V();
    forAll(V, c)
    {
        phi_[c] /= V[c];
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::overlapMeshAdapter::sumOverRanks
(
    std::vector<double>& values,
    const int components
) const
{
    if (sumOverCopies_)
    {
        sumOverCopies_(values, components);
    }
    else
    {
        foamTools::sumOverRanks(values);
    }
}


void Foam::overlapMeshAdapter::setDecomposedGrains
(
    std::function<void(std::vector<double>&, int)> sum
)
{
    if (!sum)
    {
        FatalErrorInFunction
            << "no sum function for the decomposed grains" << abort(FatalError);
    }
    sumOverCopies_ = std::move(sum);
}


void Foam::overlapMeshAdapter::map
(
    const om::Vec3* centres,
    const double* radii,
    label n
)
{
    nGrains_ = n;
    entryGrain_.clear();
    entryCell_.clear();
    entryVolume_.clear();

    checkRadii(radii, n);
    labelList owner(grainOwners(centres, n));
    mapOwned(centres, radii, n, owner);
    if (!sumOverCopies_)
    {
        checkOutside(centres, radii, n, owner);
    }

    // Grains straddling a processor boundary from another rank
    if
    (
        Pstream::parRun()
     && settings_.method != om::MappingMethod::ParticleCentroid
    )
    {
        const double k = settings_.effectiveDiameterFactor;
        for (label g = 0; g < n; ++g)
        {
            if (owner[g] != Pstream::myProcNo())
            {
                mapHalo(g, centres[g], k*radii[g]);
            }
        }
    }

    setGrainVolumes(radii, n);
    finishMap();
}


void Foam::overlapMeshAdapter::map(const nscd::System& grains)
{
    const std::vector<nscd::Vec3>& x = grains.positions();
    const std::vector<double>& r = grains.radii();
    std::vector<om::Vec3> c(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
    {
        c[i] = om::Vec3(x[i].x(), x[i].y(), x[i].z());
    }
    map(c.data(), r.data(), label(x.size()));
}


// ************************************************************************* //
