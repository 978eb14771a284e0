// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: grainCloud walls (see grainCloud.H)

Description
    The grains' walls: the mesh wall patches turned into nscd walls (2D: one
    segment per wall face in the plane z = 0, collinear touching segments
    merged; 3D: one triangulated surface per patch), the wall ids of each
    patch, their friction (wallFriction), movingWalls (a wall patch with a
    prescribed velocity [m/s] over a time window) and the grain-only gates,
    and their velocities before each step.
\*---------------------------------------------------------------------------*/

#include "grainCloud.H"
#include "grainDictionaryTools.H"
#include "grainVectorTools.H"
#include "wallPolyPatch.H"

#include <algorithm>
#include <cmath>
#include <utility>

using Foam::grainTools::toVec3;
using Foam::grainTools::toVector;

// * * * * * * * * * * * * * * * Local Functions * * * * * * * * * * * * * * //

namespace
{
    Foam::labelList wallPatchIds
    (
        const Foam::fvMesh& mesh,
        const Foam::dictionary& dict
    )
    {
        using namespace Foam;
        const polyBoundaryMesh& pbm = mesh.boundaryMesh();
        labelList ids;
        if (dict.found("wallPatches"))
        {
            ids = grainTools::patchIds
            (
                pbm, dict, "wallPatches", "the grains would fall through it"
            );
            if (ids.empty())
            {
                FatalIOErrorInFunction(dict)
                    << "wallPatches "
                    << flatOutput(dict.get<wordRes>("wallPatches"))
                    << " in "
                    << dict.name() << " matches no patch of the mesh. Patches: "
                    << flatOutput(pbm.names()) << exit(FatalIOError);
            }
        }
        else
        {
            DynamicList<label> w;
            forAll(pbm, patchi)
            {
                if (isA<wallPolyPatch>(pbm[patchi]))
                {
                    w.append(patchi);
                }
            }
            ids.transfer(w);
        }
        return ids;
    }
}


namespace
{
    //- The 2D wall segments of a patch of a one-cell-thick mesh: the back-plane
    //  edge of every face, with collinear edges that touch or overlap merged
    //  into one segment (a straight wall is one segment, so no spurious
    //  corner contacts appear where two faces meet).
    std::vector<std::pair<nscd::Vec3, nscd::Vec3>> patchSegments
    (
        const Foam::polyMesh& mesh,
        const Foam::polyPatch& pp,
        const Foam::scalar zMid
    )
    {
        using namespace Foam;
        struct line
        {
            nscd::Vec3 o, t;
            std::vector<std::pair<double, double>> iv;
        };
        std::vector<line> lines;
        const scalar tol = 1e-9*mag(mesh.bounds().span());

        // back-plane edges of the patch faces, from every rank (the grains
        // see the whole wall on every rank)
        List<List<point>> edges(Pstream::nProcs());
        DynamicList<point> mine;
        for (const face& f : pp)
        {
            DynamicList<nscd::Vec3> back(2);
            for (const label pointi : f)
            {
                const point& p = mesh.points()[pointi];
                if (p.z() < zMid)
                {
                    back.append(nscd::Vec3(p.x(), p.y(), 0));
                }
            }
            if (back.size() != 2)
            {
                FatalErrorInFunction
                    << "Wall face of patch " << pp.name() << " has "
                    << back.size() << " points on the back plane; a 2D"
                    << " mesh must be one cell thick in z with empty"
                    << " front and back patches." << exit(FatalError);
            }
            mine.append(point(back[0].x(), back[0].y(), 0));
            mine.append(point(back[1].x(), back[1].y(), 0));
        }
        edges[Pstream::myProcNo()] = mine;
        Pstream::gatherList(edges);
        Pstream::scatterList(edges);
        for (const List<point>& ed : edges)
        for (label k = 0; k + 1 < ed.size(); k += 2)
        {
            const nscd::Vec3 a(ed[k].x(), ed[k].y(), 0);
            const nscd::Vec3 b(ed[k + 1].x(), ed[k + 1].y(), 0);
            line* found = nullptr;
            for (line& l : lines)
            {
                const nscd::Vec3 da = a - l.o, db = b - l.o;
                if
                (
                    std::abs(da.x()*l.t.y() - da.y()*l.t.x()) < tol
                 && std::abs(db.x()*l.t.y() - db.y()*l.t.x()) < tol
                )
                {
                    found = &l;
                    break;
                }
            }
            if (!found)
            {
                lines.push_back({a, (b - a).normalized(), {}});
                found = &lines.back();
            }
            double sa = (a - found->o).dot(found->t);
            double sb = (b - found->o).dot(found->t);
            if (sa > sb) std::swap(sa, sb);
            found->iv.push_back({sa, sb});
        }
        std::vector<std::pair<nscd::Vec3, nscd::Vec3>> segs;
        for (line& l : lines)
        {
            std::sort(l.iv.begin(), l.iv.end());
            double s0 = l.iv[0].first, s1 = l.iv[0].second;
            for (std::size_t k = 1; k <= l.iv.size(); ++k)
            {
                if (k < l.iv.size() && l.iv[k].first <= s1 + tol)
                {
                    s1 = std::max(s1, l.iv[k].second);
                    continue;
                }
                nscd::Vec3 a = l.o + s0*l.t, b = l.o + s1*l.t;
                if (b.x() < a.x() || (b.x() == a.x() && b.y() < a.y()))
                {
                    std::swap(a, b);
                }
                segs.push_back({a, b});
                if (k < l.iv.size())
                {
                    s0 = l.iv[k].first;
                    s1 = l.iv[k].second;
                }
            }
        }
        // canonical order, independent of the face order and decomposition
        const scalar q = 1e-6*mag(mesh.bounds().span());
        auto key = [q](const nscd::Vec3& v)
        {
            return std::llround(v.x()/q)*1000003LL + std::llround(v.y()/q);
        };
        std::sort
        (
            segs.begin(), segs.end(),
            [&key](const auto& u, const auto& v)
            {
                const long long ku = key(u.first), kv = key(v.first);
                return ku != kv ? ku < kv : key(u.second) < key(v.second);
            }
        );
        return segs;
    }
}


// * * * * * * * * * * * * * Private Member Functions  * * * * * * * * * * * //

void Foam::grainCloud::computePatchWallIds()
{
    patchWalls_.clear();
    const labelList ids(wallPatchIds(mesh_, dict_));
    label wallId = 0;
    for (const label patchi : ids)
    {
        const polyPatch& pp = mesh_.boundaryMesh()[patchi];
        labelList walls;
        if (dimension_ == 2)
        {
            const label n = patchSegments(mesh_, pp, zMid_).size();
            walls = identity(n, wallId);
            wallId += n;
        }
        else
        {
            walls = labelList(1, wallId++);
        }
        patchWalls_.insert(pp.name(), walls);
    }
}


void Foam::grainCloud::addMeshWalls()
{
    const labelList ids(wallPatchIds(mesh_, dict_));
    for (const label patchi : ids)
    {
        const polyPatch& pp = mesh_.boundaryMesh()[patchi];
        if (dimension_ == 2)
        {
            for (const auto& seg : patchSegments(mesh_, pp, zMid_))
            {
                system_->addSegment(seg.first, seg.second);
            }
        }
        else
        {
            std::vector<nscd::Vec3> vertices;
            std::vector<std::array<int, 3>> triangles;
            const pointField& lp = pp.localPoints();
            vertices.reserve(lp.size());
            for (const point& p : lp)
            {
                vertices.push_back(toVec3(p));
            }
            for (const face& f : pp.localFaces())
            {
                for (label k = 1; k + 1 < f.size(); ++k)
                {
                    triangles.push_back({f[0], f[k], f[k + 1]});
                }
            }
            system_->addTriangulatedSurface(vertices, triangles);
        }
    }
}


void Foam::grainCloud::readMovingWalls()
{
    movingWalls_.clear();
    if (!dict_.found("movingWalls"))
    {
        return;
    }
    const dictionary& mw = dict_.subDict("movingWalls");
    for (const entry& e : mw)
    {
        if (!e.isDict() || !patchWalls_.found(e.keyword()))
        {
            FatalIOErrorInFunction(mw)
                << "movingWalls entry '" << e.keyword() << "' in "
                << mw.name() << " must be a dictionary named after a wall"
                << " patch. Wall patches: "
                << flatOutput(patchWalls_.sortedToc())
                << exit(FatalIOError);
        }
        const dictionary& d = e.dict();
        grainTools::checkKeywords(d, {"velocity", "startTime", "endTime"});
        movingWall w;
        w.patch = e.keyword();
        w.velocity = d.get<vector>("velocity");
        w.startTime = d.getOrDefault<scalar>("startTime", -GREAT);
        w.endTime = d.getOrDefault<scalar>("endTime", GREAT);
        w.wallIds = patchWalls_[w.patch];
        if (dimension_ == 2 && mag(w.velocity.z()) > 0)
        {
            FatalIOErrorInFunction(d)
                << "velocity of moving wall " << w.patch << " has a z"
                << " component in a 2D case" << exit(FatalIOError);
        }
        movingWalls_.append(w);
    }
}


void Foam::grainCloud::readWallFriction()
{
    // a friction saved in a state is replaced (the dictionary rules; the
    // gates' friction too);
    // FatalIOError naming the entry: not '<patch> <mu>;', mu negative or
    // not finite, or an entry matching no wall patch
    const wordList patches(patchWalls_.sortedToc());
    HashTable<scalar> mu;
    if (dict_.found("wallFriction"))
    {
        mu = grainTools::patchValues
        (
            dict_.subDict("wallFriction"), patches, "friction coefficient", 0
        );
    }
    try
    {
        // -1: the grain's material friction (nscd::System::setWallFriction)
        for (const word& p : patches)
        {
            for (const label id : patchWalls_[p])
            {
                system_->setWallFriction(id, mu.found(p) ? mu[p] : -1);
            }
            if (mu.found(p))
            {
                Info<< "grainCloud: wall patch " << p << " friction " << mu[p]
                    << nl;
            }
        }
        // the gates (read before): their own friction, else the grain's
        for (const gate& g : gates_)
        {
            system_->setWallFriction(g.wallId, g.friction);
            if (g.friction >= 0)
            {
                Info<< "grainCloud: gate " << g.name << " friction "
                    << g.friction << nl;
            }
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction
            << "Grain system: " << err.what() << exit(FatalError);
    }
}


void Foam::grainCloud::readGates(const label nMeshWalls)
{
    gates_.clear();
    if (dict_.found("gates"))
    {
        const dictionary& gd = dict_.subDict("gates");
        for (const entry& e : gd)
        {
            if (!e.isDict())
            {
                FatalIOErrorInFunction(gd)
                    << "gates entry '" << e.keyword() << "' in " << gd.name()
                    << " must be a dictionary { start (x y z); end (x y z);"
                    << " velocity (u v w); startTime t0; endTime t1; }"
                    << exit(FatalIOError);
            }
            const dictionary& d = e.dict();
            grainTools::checkKeywords
            (
                d,
                {"start", "end", "velocity", "startTime", "endTime", "friction"}
            );
            gate g;
            g.name = e.keyword();
            g.start = d.get<vector>("start");
            g.end = d.get<vector>("end");
            g.velocity = d.get<vector>("velocity");
            g.startTime = d.getOrDefault<scalar>("startTime", -GREAT);
            g.endTime = d.getOrDefault<scalar>("endTime", GREAT);
            g.friction = d.getOrDefault<scalar>("friction", -1);
            if
            (
                d.found("friction")
             && !(g.friction >= 0 && std::isfinite(g.friction))
            )
            {
                FatalIOErrorInFunction(d)
                    << "friction " << g.friction << " of gate " << g.name
                    << " in " << d.name() << " must be a finite value >= 0."
                    << " Fix: give the Coulomb coefficient of the"
                    << " grain-gate contacts, or leave it out (the grain's"
                    << " material friction)." << exit(FatalIOError);
            }
            g.wallId = nMeshWalls + gates_.size();
            if (dimension_ == 2 && mag(g.velocity.z()) > 0)
            {
                FatalIOErrorInFunction(d)
                    << "velocity of gate " << g.name << " in " << d.name()
                    << " has a z component in a 2D case (x-y plane)"
                    << exit(FatalIOError);
            }
            vector seg(g.end - g.start);
            seg.z() = 0;
            if (mag(seg) < SMALL)
            {
                FatalIOErrorInFunction(d)
                    << "gate " << g.name << " in " << d.name() << ": start "
                    << g.start << " and end " << g.end << " coincide in the"
                    << " x-y plane. Fix: give two distinct points (2D: the"
                    << " segment; 3D: the rectangle's bottom and top edge"
                    << " ends, swept over the mesh depth)."
                    << exit(FatalIOError);
            }
            if (!(g.endTime > g.startTime))
            {
                FatalIOErrorInFunction(d)
                    << "gate " << g.name << " in " << d.name() << ": endTime "
                    << g.endTime << " must be > startTime " << g.startTime
                    << exit(FatalIOError);
            }
            gates_.append(g);
        }
    }

    const label nWalls = system_->nWalls();
    if (nWalls == nMeshWalls + gates_.size() && nWalls > nMeshWalls)
    {
        // state written with the gates (their displacement is restored)
        return;
    }
    if (nWalls != nMeshWalls)
    {
        FatalErrorInFunction
            << "The grain state has " << nWalls << " walls but the wall"
            << " patches give " << nMeshWalls << " and 'gates' "
            << gates_.size() << "." << nl
            << "    The mesh, wallPatches or gates changed since the state"
            << " was written: re-run grainDeposit." << exit(FatalError);
    }
    try
    {
        for (const gate& g : gates_)
        {
            label id = -1;
            if (dimension_ == 2)
            {
                id = system_->addSegment(toSystem(g.start), toSystem(g.end));
            }
            else
            {
                const scalar z0 = mesh_.bounds().min().z();
                const scalar z1 = mesh_.bounds().max().z();
                const std::vector<nscd::Vec3> v
                {
                    nscd::Vec3(g.start.x(), g.start.y(), z0),
                    nscd::Vec3(g.end.x(), g.end.y(), z0),
                    nscd::Vec3(g.end.x(), g.end.y(), z1),
                    nscd::Vec3(g.start.x(), g.start.y(), z1)
                };
                id = system_->addTriangulatedSurface(v, {{0, 1, 2}, {0, 2, 3}});
            }
            if (id != g.wallId)
            {
                FatalErrorInFunction
                    << "gate " << g.name << " got wall id " << id
                    << " instead of " << g.wallId << exit(FatalError);
            }
        }
    }
    catch (const nscd::InputError& err)
    {
        FatalErrorInFunction
            << "Grain system (gates): " << err.what() << exit(FatalError);
    }
}


void Foam::grainCloud::setWallVelocities(const scalar dt)
{
    const scalar t0 = mesh_.time().value() - dt;
    for (const movingWall& w : movingWalls_)
    {
        const bool on = (t0 >= w.startTime - SMALL && t0 < w.endTime - SMALL);
        const nscd::Vec3 v = on ? toVec3(w.velocity) : nscd::Vec3::Zero();
        for (const label id : w.wallIds)
        {
            system_->setWallVelocity(id, v);
        }
    }

    // gates: the velocity is weighted by the part of [t0, t0 + dt] inside
    // [startTime, endTime] so that the displacement is exactly
    // velocity*(min(t, endTime) - startTime) whatever the time steps
    for (const gate& g : gates_)
    {
        const scalar t1 = t0 + dt;
        const scalar on =
            max(scalar(0), min(t1, g.endTime) - max(t0, g.startTime));
        const scalar f = dt > 0 ? min(on/dt, scalar(1)) : 0;
        system_->setWallVelocity(g.wallId, toVec3(f*g.velocity));
    }
}

// * * * * * * * * * * * * * * * Member Functions  * * * * * * * * * * * * * //

Foam::vector Foam::grainCloud::gateDisplacement(const label gatei) const
{
    return toVector(system_->wallDisplacement(gates_[gatei].wallId));
}

// ************************************************************************* //
