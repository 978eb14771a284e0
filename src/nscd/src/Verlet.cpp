// SPDX-License-Identifier: GPL-3.0-or-later
// Verlet list of candidate grain pairs (System::Settings::verletSkin; the
// argument in Verlet.H): built by the grid scan with the reach enlarged by
// the skin, its pairs re-tested each step in the order of the grid scan,
// rebuilt when a grain leaves its cover.
#include "DetectPair.H"

#include <cmath>
#include <cstdint>

namespace nscd
{

namespace
{
/// Share of the half skin a grain may use (Verlet.H, eq. 3): the
/// rest, 1e-6 S/2, absorbs the round-off of the distance tests.
constexpr double halfSkinUsable = 1 - 1e-6;
/// A list is built only if a grain at the fastest speed would cross half
/// the skin in no fewer than this many detections, 2D and 3D (Verlet.H,
/// "When a list is built").
constexpr double minListLife2D = 3, minListLife3D = 1;
} // namespace

void System::Impl::detectListed(DetectGrid& g)
{
    const double skin = settings.verletSkin * rMin();
    const bool current = verlet.valid && verlet.start.size() == x.size() + 1 && verlet.skin == skin
                         && g.margin <= verlet.margin;
    if (current && detectFromList(g)) return;
    newContacts.clear();
    // a list that would not outlive a few detections costs more than the
    // grid scan it saves (Verlet.H, "When a list is built")
    if (!listWorthBuilding(g, skin))
    {
        verlet.invalidate();
        scanGrid(g, false);
        return;
    }
    buildVerletList(g);
    // a list just built covers the step, unless a centre or speed is not
    // finite: then the grid scan, as without the list
    if (!detectFromList(g))
    {
        newContacts.clear();
        scanGrid(g, false);
    }
}

bool System::Impl::listWorthBuilding(const DetectGrid& g, double skin) const
{
    // the fastest translation of a body this step (free velocities): a
    // new list covers about (S/2) / (dt v_max) detections (Verlet.H, eq. 3)
    // (a non-finite speed: built, and its cover test sends the detection
    // to the grid scan, as before the rule; tested before any comparison,
    // which would raise FE_INVALID)
    const int N = int(x.size());
    double v2 = 0;
    auto fastest = [&v2](const Vec3& v)
    {
        const double q = v.squaredNorm();
        if (!std::isfinite(q)) return false;
        v2 = q > v2 ? q : v2;
        return true;
    };
    for (int s = 0; s < N; ++s)
        if (!fastest(body[s].v)) return true;
    for (const Wall& W : walls)
        if (!fastest(W.velocity)) return true;
    const double reach = (dim == 2 ? minListLife2D : minListLife3D) * g.dt * std::sqrt(v2);
    return reach <= 0.5 * skin * halfSkinUsable;
}

void System::Impl::buildVerletList(const DetectGrid& g)
{
    const int N = int(x.size());
    VerletList& L = verlet;
    ++L.builds;
    L.skin = settings.verletSkin * rMin();
    L.margin = g.margin;
    // eq. 2 of Verlet.H: the grid scan's test with the margin m + S (the
    // fast grains of this step paired in their own pass, as by detect())
    DetectGrid gl = g;
    gl.margin = g.margin + L.skin;
    newContacts.clear();
    scanGrid(gl, true);
    // the pairs (scanGrid emits them grouped by i, in increasing i) into
    // rows of partners, each sorted by partner
    L.start.assign(N + 1, 0);
    for (const Contact& c : newContacts) ++L.start[c.i + 1];
    for (int i = 0; i < N; ++i) L.start[i + 1] += L.start[i];
    L.items.resize(newContacts.size());
    for (std::size_t k = 0; k < newContacts.size(); ++k) L.items[k] = newContacts[k].j;
    for (int i = 0; i < N; ++i) std::sort(L.items.begin() + L.start[i], L.items.begin() + L.start[i + 1]);
    newContacts.clear();
    L.ref.resize(N);
    const double afdt = g.af * g.dt;
    const bool hasWalls = !walls.empty();
    for (int i = 0; i < N; ++i)
    {
        VerletList::Reference& R = L.ref[i];
        R.x = packed[i].x;
        R.r = packed[i].r;
        R.reach = afdt * speed[i];
        R.fix = packed[i].fix;
        R.nearWall = hasWalls && !R.fix && nearWalls(i, g.dt, gl.margin, g.af);
    }
    L.wallRef.resize(walls.size());
    for (std::size_t w = 0; w < walls.size(); ++w)
    {
        L.wallRef[w].displacement = walls[w].displacement;
        L.wallRef[w].reach = afdt * walls[w].velocity.norm();
    }
    L.valid = true;
}

bool System::Impl::detectFromList(DetectGrid& g)
{
    // this step's grid (the cells only: no sort, no scan), which orders the
    // slow pairs of a grain as scanGrid does
    detectGridGeometry(g);
    const int N = int(x.size());
    const VerletList& L = verlet;
    const double sCut = g.sCut, afdt = g.af * g.dt;
    const double half = 0.5 * L.skin * halfSkinUsable;
    // the walls' part of the cover (Verlet.H)
    if (L.wallRef.size() != walls.size()) return false;
    for (std::size_t w = 0; w < walls.size(); ++w)
    {
        const double room = half - std::max(0.0, afdt * walls[w].velocity.norm() - L.wallRef[w].reach);
        if (!(room >= 0)
            || !((walls[w].displacement - L.wallRef[w].displacement).squaredNorm() <= room * room))
            return false;
    }
    std::vector<std::uint64_t>& keys = verlet.keys;
    for (int i = 0; i < N; ++i)
    {
        const GrainSlot& A = packed[i];
        {
            // the cover of the list (Verlet.H, eq. 3)
            const VerletList::Reference& R = L.ref[i];
            const double room = half - std::max(0.0, afdt * speed[i] - R.reach);
            if (A.r != R.r || A.fix != R.fix || !(room >= 0) || !((A.x - R.x).squaredNorm() <= room * room))
                return false;
        }
        const bool slowI = speed[i] <= sCut;
        bool fastPairs = !slowI; // some pair of i with a fast grain
        const int b = L.start[i], e = L.start[i + 1];
        if (slowI)
        {
            // the pairs with slow grains, by (cell, slot) of the partner
            keys.clear();
            for (int k = b; k < e; ++k)
            {
                const int j = L.items[k];
                if (speed[j] > sCut)
                {
                    fastPairs = true;
                    continue;
                }
                if (pairInReach(*this, i, j, g))
                    keys.push_back(std::uint64_t(detectCell(g, packed[j].x, dim)) << 32 | std::uint32_t(j));
            }
            for (std::size_t a = 1; a < keys.size(); ++a) // insertion sort: a few keys, mostly in order
            {
                const std::uint64_t key = keys[a];
                std::size_t c = a;
                for (; c > 0 && keys[c - 1] > key; --c) keys[c] = keys[c - 1];
                keys[c] = key;
            }
            for (const std::uint64_t key : keys)
                pushPairContact(*this, i, int(key & 0xffffffffu), g, newContacts);
        }
        if (fastPairs) // then those with a fast grain, by partner
            for (int k = b; k < e; ++k)
            {
                const int j = L.items[k];
                if (!slowI || speed[j] > sCut) detectPair(*this, i, j, g, newContacts);
            }
        if (L.ref[i].nearWall) detectWalls(i, g.dt, g.margin, g.af);
    }
    return true;
}

} // namespace nscd
