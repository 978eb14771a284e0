// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainMeshExits (see grainMeshExits.H)

Description
    The cell of this rank holding a grain centre (its last cell, that
    cell's clear ball, pointInCell, the cell's neighbours, then a search)
    and, for a centre no rank holds after a step, the boundary face its
    path crossed first (exact point-in-face test, an outlet face winning a
    tie with another face at a shared edge).
\*---------------------------------------------------------------------------*/

#include "grainMeshExits.H"
#include "emptyPolyPatch.H"
#include "indexedOctree.H"
#include "treeDataFace.H"
#include "Random.H"

namespace
{
//- Bound of a cell's clear ball, in cell sizes (computeCellClearance)
constexpr Foam::scalar clearanceCellSizes = 16;
}

// * * * * * * * * * * * * * * * * Constructors  * * * * * * * * * * * * * * //

Foam::grainMeshExits::grainMeshExits
(
    const fvMesh& mesh,
    const label dimension,
    const scalar zMid
)
:
    mesh_(mesh),
    dimension_(dimension),
    zMid_(zMid)
{
    // The tet decomposition of pointInCell (CELL_TETS) is built by a
    // collective exchange: on every rank now (as OpenFOAM's Cloud does),
    // not at the first search of one rank
    if (Pstream::parRun())
    {
        (void)mesh_.tetBasePtIs();
    }
}


// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

void Foam::grainMeshExits::updateClearance()
{
    if (mesh_.changing())
    {
        clearCentres_.clear();
        clearRadiusSqr_.clear();
        planeCellTree_.clear();
    }
    else if (clearRadiusSqr_.size() != mesh_.nCells())
    {
        computeCellClearance();
    }
}


Foam::treeBoundBox Foam::grainMeshExits::searchBox(const label seed) const
{
    Random rndGen(seed);
    treeBoundBox bb(treeBoundBox(mesh_.points()).extend(rndGen, 1e-4));
    bb.min() -= point::uniform(ROOTVSMALL);
    bb.max() += point::uniform(ROOTVSMALL);
    if (dimension_ == 2)
    {
        // A one-cell-thick mesh: every cell and face spans the thickness,
        // so an octree on the flat box would put each in both halves of
        // every split and stop refining at its duplicity limit (leaves of
        // hundreds of cells or faces). On a box as deep as it is wide the
        // splits in z pass above the slab and the tree refines in x and y.
        bb.max().z() = bb.min().z() + cmptMax(bb.span());
    }
    return bb;
}


Foam::label Foam::grainMeshExits::findCell(const point& p) const
{
    if (dimension_ != 2 || mesh_.changing())
    {
        return mesh_.findCell(p);
    }
    if (mesh_.nCells() == 0)
    {
        return -1;
    }
    if (!planeCellTree_.valid())
    {
        // polyMesh::cellTree's data, limits and test (CELL_TETS)
        planeCellTree_.reset
        (
            new indexedOctree<treeDataCell>
            (
                treeDataCell(false, mesh_, polyMesh::CELL_TETS),
                searchBox(261782),
                8, 10, 5.0
            )
        );
    }
    return planeCellTree_().findInside(p);
}


Foam::label Foam::grainMeshExits::hintOrNeighbour
(
    const point& p,
    const label hint
) const
{
    if (hint < 0 || hint >= mesh_.nCells())
    {
        return -1;
    }
    if (mesh_.pointInCell(p, hint))
    {
        return hint;
    }
    // a grain that left its cell is most often in a neighbour: those
    // before a search of the whole rank
    for (const label nbr : mesh_.cellCells()[hint])
    {
        if (mesh_.pointInCell(p, nbr))
        {
            return nbr;
        }
    }
    return -1;
}


Foam::label Foam::grainMeshExits::findCellFrom
(
    const point& p,
    const label hint
) const
{
    const label c = hintOrNeighbour(p, hint);
    return c >= 0 ? c : findCell(p);
}


Foam::label Foam::grainMeshExits::findLocalCell
(
    const point& p,
    const label hint,
    const boundBox& local
) const
{
    if
    (
        hint >= 0
     && clearRadiusSqr_.size() == mesh_.nCells()
     && hint < mesh_.nCells()
     && magSqr(p - clearCentres_[hint]) < clearRadiusSqr_[hint]
    )
    {
        return hint;
    }
    const label c = hintOrNeighbour(p, hint);
    if (c >= 0)
    {
        return c;
    }
    return local.contains(p) ? findCell(p) : -1;
}


void Foam::grainMeshExits::computeCellClearance()
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
    const treeBoundBox bb(searchBox(123456));
    const indexedOctree<treeDataFace> tree
    (
        treeDataFace(false, mesh_, labelList(faces)),
        bb, 8, 10, 3.0
    );
    // The search is bounded by clearanceCellSizes of the cell's own size
    // (its largest centre-to-point distance, in the grains' plane in 2D): a
    // grain is looked for from its last cell and that cell's neighbours, so
    // a larger ball would save little, and an unbounded search visits every
    // face nearer than a cell's nearest one (most of the boundary for the
    // cells far from it); a ball that meets no face within the bound is
    // clear up to it.
    const pointField& pts = mesh_.points();
    const labelListList& cellPts = mesh_.cellPoints();
    forAll(clearCentres_, celli)
    {
        const point& c = clearCentres_[celli];
        scalar size2 = 0;
        for (const label pi : cellPts[celli])
        {
            vector d = pts[pi] - c;
            if (dimension_ == 2)
            {
                d.z() = 0;
            }
            size2 = max(size2, magSqr(d));
        }
        const scalar bound2 = sqr(clearanceCellSizes)*size2;
        const pointIndexHit hit = tree.findNearest(c, bound2);
        clearRadiusSqr_[celli] =
            sqr(0.9)*(hit.hit() ? magSqr(hit.hitPoint() - c) : bound2);
    }
}


Foam::labelList Foam::grainMeshExits::exitPatches
(
    const List<Pair<point>>& paths,
    const labelList& outletPatches
) const
{
    // first boundary face crossed by each path on this rank
    scalarList tFirst(paths.size(), GREAT);
    labelList patch(paths.size(), -1);
    forAll(paths, k)
    {
        firstCrossing
        (
            paths[k].first(), paths[k].second(), outletPatches, tFirst[k],
            patch[k]
        );
    }
    // the rank whose face is crossed first names the patch (the indices of
    // the non-processor patches are the same on every rank); on a tie
    // (crossing points within tieDistance(), e.g. a point on an edge
    // shared by faces of two ranks) an outlet patch wins, as in
    // firstCrossing.  Two list reductions for all the grains.
    scalarList tGlobal(tFirst);
    Pstream::listCombineGather(tGlobal, minEqOp<scalar>());
    Pstream::listCombineScatter(tGlobal);
    const label nPatches = mesh_.boundaryMesh().size();
    const scalar tie = tieDistance();
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
        else if (outletPatches.found(patch[k]))
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


Foam::scalar Foam::grainMeshExits::tieDistance() const
{
    // round-off of the crossing points is ~1e-16 of the coordinates; 1e-9
    // of the (global) mesh span is far above it and far below any grain
    return 1e-9*mag(mesh_.bounds().span());
}


void Foam::grainMeshExits::firstCrossing
(
    const point& x0,
    const point& x1,
    const labelList& outletPatches,
    scalar& tBest,
    label& patchBest
) const
{
    // Coupled and empty patches are skipped.  The crossing point must lie
    // in the face polygon (face::intersection, exact point-in-polygon on
    // the face-centre triangle fan, widened by 1e-6 of the face size so
    // that an edge shared by two faces is in both).  On a tie (crossing
    // points within tieDistance(), e.g. a point on the edge between an
    // orifice face and a floor face) an outlet patch wins over any other
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
    // tTol: tieDistance() in t, both the round-off allowed at x0 or x1
    // and the tie of two crossings
    const scalar tTol = tieDistance()/len;
    const pointField& points = mesh_.points();
    const polyBoundaryMesh& pbm = mesh_.boundaryMesh();
    bool bestIsOutlet = false;
    for (const polyPatch& pp : pbm)
    {
        if (pp.coupled() || isA<emptyPolyPatch>(pp))
        {
            continue;
        }
        const bool isOutlet = outletPatches.found(pp.index());
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
            // point to within tieDistance: an edge shared by two faces,
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

// ************************************************************************* //
