// SPDX-License-Identifier: GPL-3.0-or-later
// Contact detection: uniform grid for grain pairs, walls (planes, segments,
// triangulated surfaces) and droplets; gap of a contact after the step.
//
// Contacts and large displacements in System::step: a pair (i, j) is a
// candidate when its gap is below its own alert distance (Settings::alertDistanceFactor);
// the few grains much faster than the rest are paired in a separate pass
// so that the detection stays O(N). Each candidate obeys the gap-based
// Signorini law n.(x_ij + dt u_ij) >= r_i + r_j with a unit normal n such
// that the start satisfies it: the end of the step cannot overlap
// (|x| >= n.x) and the straight path from the start cannot cross the other
// grain (both ends lie in the half-space n.x >= r_i + r_j, which the ball
// does not meet), whatever the displacement. For pairs moving far in the
// step, n is the normal at the first touch of the free relative path, or
// the direction of its closest point if it misses (no spurious impact of
// a grain passing beside another). Undetected pairs: after
// the solve, a grain whose displacement |v_i^+| dt exceeds its reach
// alertDistanceFactor dt s_i + alertMargin r_min/2 has its reach raised
// to its solved speed and the step's contacts are detected and solved
// again, at most 4 times (StepReport::redetections): then no undetected
// pair (gap >= the sum of the reaches + alertMargin r_min) can overlap
// at the end of the step.
#include "ContactLaws.H"
#include "DetectPair.H"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

namespace nscd
{

namespace
{
/// closest point of segment [a, b] to p
inline Vec3 closestSegment(const Vec3& p, const Vec3& a, const Vec3& b)
{
    const Vec3 ab = b - a;
    double t = (p - a).dot(ab) / ab.squaredNorm();
    t = std::min(1.0, std::max(0.0, t));
    return a + t * ab;
}

/// detectWalls stage: append to I.newContacts the contact of slot i with
/// wall wi, unit normal n (from the wall to the grain), gap [m], the wall's
/// friction (the grain's if the wall has none).
inline void pushWallContact(System::Impl& I, int i, int wi, const Vec3& n, double gap)
{
    const Wall& W = I.walls[wi];
    Contact c;
    c.i = i;
    c.j = int(I.x.size()) + wi;
    c.n = n;
    c.gap = gap;
    c.mu = W.friction >= 0 ? W.friction : I.packed[i].mu;
    I.newContacts.push_back(c);
}

} // namespace

void System::Impl::detectSegment(int i, int wi, double alert)
{
    const Wall& W = walls[wi];
    const Vec3& xi = packed[i].x;
    const double ri = packed[i].r;
    const Vec3 a = W.p + W.displacement, b = W.b + W.displacement;
    const Vec3 ab = b - a;
    const double t = (xi - a).dot(ab) / ab.squaredNorm();
    const int end = t <= 0 ? 0 : (t >= 1 ? 1 : -1);
    const int nb = end >= 0 ? W.segNb[end] : -1;
    if (nb >= 0 && walls[nb].displacement == W.displacement)
    {
        if (W.segFlat[end])
        {
            // joint with a collinear neighbour: beyond it the
            // neighbour's interior contact carries the grain; at the
            // joint itself, contact with the line (no tilted normal)
            if (t < -1e-9 || t > 1 + 1e-9) return;
            Vec3 n(-ab.y(), ab.x(), 0.0);
            n.normalize();
            double s = (xi - a).dot(n);
            if (s < 0)
            {
                s = -s;
                n = -n;
            }
            if (s - ri < alert && s > 0) pushWallContact(*this, i, wi, n, s - ri);
            return;
        }
        // convex corner shared with a lower-numbered segment: if its
        // closest point is the same corner, it already gave this contact
        if (nb < wi)
        {
            const Wall& T = walls[nb];
            const Vec3 corner = end == 0 ? a : b;
            const Vec3 ct = closestSegment(xi, T.p + T.displacement, T.b + T.displacement);
            if ((ct - corner).norm() <= 1e-9 * ab.norm()) return;
        }
    }
    const Vec3 cp = a + std::min(1.0, std::max(0.0, t)) * ab;
    const Vec3 d = xi - cp;
    const double dn = d.norm();
    if (dn - ri < alert && dn > 0) pushWallContact(*this, i, wi, d / dn, dn - ri);
}

void System::Impl::triangleCandidates(int i, int wi, double alert)
{
    const Wall& W = walls[wi];
    const double ri = packed[i].r;
    const Vec3 xl = packed[i].x - W.displacement; // tree coordinates
    trianglesNear(*W.tree, xl, ri + alert, triCandidates);
    // candidate closest points (filtered below, after all walls). A
    // closest point on a flat edge or vertex (shared by coplanar
    // triangles, see buildTriangleFeatures) is replaced by the
    // face-plane contact, so that no tilted normal brakes a grain
    // crossing internal edges of a triangulated plane.
    for (int t : triCandidates)
    {
        const auto& f = W.triangles[t];
        int feat = -1;
        Vec3 cp = closestPointTriangle(xl, W.vertices[f[0]], W.vertices[f[1]], W.vertices[f[2]], feat);
        double dn = (xl - cp).norm();
        if (feat >= 0 && ((W.triFlat[t] >> (feat < 3 ? 3 + feat : feat - 3)) & 1u))
        {
            const Vec3& fn = W.triNormal[t];
            const double sd = (xl - W.vertices[f[0]]).dot(fn);
            dn = std::abs(sd);
            cp = xl - sd * fn;
        }
        if (!(dn > 0) || dn - ri >= alert) continue;
        triPoints.push_back({dn, cp + W.displacement, wi});
    }
}

void System::Impl::keepTrianglePoints(int i, std::size_t first)
{
    // triangle candidates of all triangulated walls, nearest first: a
    // candidate is kept only if it lies strictly in front of every kept
    // contact plane of this grain (any wall) and has a distinct normal. This
    // merges the face contacts of neighbouring (also flat) triangles, also
    // across patches, removes shadowed edge points, keeps genuine convex edges.
    if (triPoints.empty()) return;
    const Vec3& xi = packed[i].x;
    const double ri = packed[i].r;
    std::sort(triPoints.begin(), triPoints.end(),
              [](const TriPoint& a, const TriPoint& b) { return a.d < b.d; });
    const double eps = 1e-9 * ri;
    for (const TriPoint& tp : triPoints)
    {
        const Vec3 n = (xi - tp.c) / tp.d;
        bool keep = true;
        for (std::size_t k = first; k < newContacts.size() && keep; ++k)
        {
            const Vec3 ck = xi - (newContacts[k].gap + ri) * newContacts[k].n;
            if ((tp.c - ck).dot(newContacts[k].n) <= eps || newContacts[k].n.dot(n) > 1.0 - 1e-6)
                keep = false;
        }
        if (keep) pushWallContact(*this, i, tp.wall, n, tp.d - ri);
    }
}

void System::Impl::detectWalls(int i, double dt, double margin, double alertFactor)
{
    const Vec3& xi = packed[i].x;
    const double ri = packed[i].r;
    const std::size_t first = newContacts.size(); // wall contacts of grain i start here
    triPoints.clear();
    for (int wi = 0; wi < int(walls.size()); ++wi)
    {
        const Wall& W = walls[wi];
        const double alert = alertFactor * dt * (speed[i] + W.velocity.norm()) + margin;
        if (W.type == PlaneWall)
        {
            const double gap = (xi - (W.p + W.displacement)).dot(W.n) - ri;
            if (gap < alert) pushWallContact(*this, i, wi, W.n, gap);
        }
        else if (W.type == SegmentWall)
            detectSegment(i, wi, alert);
        else
            triangleCandidates(i, wi, alert);
    }
    keepTrianglePoints(i, first);
}

bool System::Impl::nearWalls(int i, double dt, double margin, double alertFactor)
{
    const Vec3& xi = packed[i].x;
    const double ri = packed[i].r;
    for (const Wall& W : walls)
    {
        const double alert = alertFactor * dt * (speed[i] + W.velocity.norm()) + margin;
        if (W.type == PlaneWall)
        {
            if ((xi - (W.p + W.displacement)).dot(W.n) - ri < alert) return true;
        }
        else if (W.type == SegmentWall)
        {
            // the distance to the segment, less the parameter tolerance of
            // a flat joint (detectSegment tests the line there)
            const Vec3 a = W.p + W.displacement, b = W.b + W.displacement;
            const double dn = (xi - closestSegment(xi, a, b)).norm() - 1e-9 * (b - a).norm();
            if (dn - ri < alert) return true;
        }
        else
        {
            trianglesNear(*W.tree, xi - W.displacement, ri + alert, triCandidates);
            if (!triCandidates.empty()) return true;
        }
    }
    return false;
}

void System::Impl::selectFastGrains(DetectGrid& g)
{
    // fast grains: reach af dt s above rmax/4 (a cell grows by at most half
    // a radius for the slow ones), and at most maxFast of them (the fastest)
    const int N = int(x.size());
    const double af = g.af, dt = g.dt;
    const int maxFast = std::max(32, int(std::sqrt(double(N))));
    double sCut = af * dt > 0 ? 0.25 * g.rmax / (af * dt) : std::numeric_limits<double>::infinity();
    int nFast = 0;
    for (int i = 0; i < N; ++i) nFast += speed[i] > sCut;
    if (nFast > maxFast)
    {
        fastScratch.assign(speed.begin(), speed.end());
        std::nth_element(fastScratch.begin(), fastScratch.begin() + maxFast, fastScratch.end(),
                         std::greater<double>());
        sCut = fastScratch[maxFast]; // the (maxFast+1)-th largest: at most maxFast are above
    }
    fastGrains.clear();
    double sSlow = 0; // largest speed of a slow grain
    for (int i = 0; i < N; ++i)
    {
        if (speed[i] > sCut)
            fastGrains.push_back(i);
        else
            sSlow = std::max(sSlow, speed[i]);
    }
    if (int(fastGrains.size()) == N)
    {
        // every grain fast (a few grains in flight): one grid for all, as if slow
        fastGrains.clear();
        sCut = std::numeric_limits<double>::infinity();
        for (int i = 0; i < N; ++i) sSlow = std::max(sSlow, speed[i]);
    }
    g.sCut = sCut;
    g.sSlow = sSlow;
}

void System::Impl::detectGridGeometry(DetectGrid& g) const
{
    const int N = int(x.size());
    const GrainSlot* const P = packed.data();
    const double sCut = g.sCut;
    double h = 2 * g.rmax + g.af * g.dt * 2 * g.sSlow + g.margin;

    // bounding box of the slow grains
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max()), hi = -lo;
    for (int i = 0; i < N; ++i)
        if (speed[i] <= sCut)
        {
            lo = lo.cwiseMin(P[i].x);
            hi = hi.cwiseMax(P[i].x);
        }
    const int D = dim;
    auto ncells = [&](double hh, long dims[3])
    {
        long tot = 1;
        for (int d = 0; d < 3; ++d)
        {
            dims[d] = (d < D) ? long((hi[d] - lo[d]) / hh) + 1 : 1;
            tot *= dims[d];
        }
        return tot;
    };
    long* const dims = g.dims;
    long tot = ncells(h, dims);
    const long cap = std::max<long>(4L * N, 64);
    while (tot > cap)
    {
        h *= 1.5;
        tot = ncells(h, dims);
    }
    g.lo = lo;
    g.tot = tot;
    g.ih = 1.0 / h;
}

void System::Impl::buildDetectGrid(DetectGrid& g)
{
    detectGridGeometry(g);
    const int N = int(x.size());
    const double sCut = g.sCut;
    const long tot = g.tot;
    // counting sort of the slow grains into cells (fast ones: cellOf = -1)
    cellOf.resize(N);
    cellStart.assign(tot + 1, 0);
    for (int i = 0; i < N; ++i)
    {
        if (speed[i] > sCut)
        {
            cellOf[i] = -1;
            continue;
        }
        const int cell = int(detectCell(g, packed[i].x, dim));
        cellOf[i] = cell;
        ++cellStart[cell + 1];
    }
    for (long c = 0; c < tot; ++c) cellStart[c + 1] += cellStart[c];
    cellItems.resize(cellStart[tot]);
    {
        // use adjStart as a temporary cursor array
        adjStart.assign(cellStart.begin(), cellStart.end() - 1);
        for (int i = 0; i < N; ++i)
            if (cellOf[i] >= 0) cellItems[adjStart[cellOf[i]]++] = i;
    }
}

namespace
{
/// scanGrid's pair test of slots i < j: the candidate contact (detectPair),
/// or, for the Verlet list (Candidates), the bare pair (i, j) if it passes
/// pairInReach.
template <bool Candidates>
inline void testPair(const System::Impl& I, int i, int j, const System::Impl::DetectGrid& g,
                     std::vector<Contact>& out)
{
    if (!Candidates)
    {
        detectPair(I, i, j, g, out);
        return;
    }
    if (!pairInReach(I, i, j, g)) return;
    Contact c;
    c.i = i;
    c.j = j;
    out.push_back(c);
}

/// scanGrid stage: the pairs with a fast grain (fast-fast directly,
/// fast-slow through the cells its alert sphere covers) into
/// I.fastContacts, sorted by (i, j).
template <bool Candidates>
void detectFastPairs(System::Impl& I, const System::Impl::DetectGrid& g)
{
    std::vector<Contact>& out = I.fastContacts;
    out.clear();
    const std::vector<int>& fast = I.fastGrains;
    if (fast.empty()) return;
    const GrainSlot* const P = I.packed.data();
    const double af = g.af, dt = g.dt, margin = g.margin, ih = g.ih;
    const long* const dims = g.dims;
    const Vec3& lo = g.lo;
    const int D = I.dim;
    for (std::size_t a = 0; a < fast.size(); ++a)
    {
        const int f = fast[a];
        for (std::size_t b = a + 1; b < fast.size(); ++b)
            testPair<Candidates>(I, f, fast[b], g, out); // fastGrains is sorted: f < fast[b]
        // every slow j with a gap below af dt (s_f + s_j) + margin lies within R of x_f
        const double R = P[f].r + g.rmax + af * dt * (I.speed[f] + g.sSlow) + margin;
        long c0[3] = {0, 0, 0}, c1[3] = {0, 0, 0};
        bool outside = false;
        for (int d = 0; d < D; ++d)
        {
            const double a0 = std::floor((P[f].x[d] - R - lo[d]) * ih),
                         a1 = std::floor((P[f].x[d] + R - lo[d]) * ih);
            if (a1 < 0 || a0 > double(dims[d] - 1))
            {
                outside = true;
                break;
            }
            c0[d] = long(std::max(0.0, a0));
            c1[d] = long(std::min(double(dims[d] - 1), a1));
        }
        if (outside) continue;
        for (long zz = c0[2]; zz <= c1[2]; ++zz)
            for (long yy = c0[1]; yy <= c1[1]; ++yy)
            {
                const long row = dims[0] * (yy + dims[1] * zz);
                for (int k = I.cellStart[row + c0[0]], e = I.cellStart[row + c1[0] + 1]; k < e; ++k)
                {
                    const int j = I.cellItems[k];
                    if (j < f)
                        testPair<Candidates>(I, j, f, g, out);
                    else
                        testPair<Candidates>(I, f, j, g, out);
                }
            }
    }
    std::sort(out.begin(), out.end(),
              [](const Contact& p, const Contact& q) { return p.i < q.i || (p.i == q.i && p.j < q.j); });
}

/// System::Impl::scanGrid for Candidates (the Verlet list's pairs) or not
/// (the contacts of the step, with the walls).
template <bool Candidates>
void scanGridPairs(System::Impl& I, System::Impl::DetectGrid& g)
{
    const int N = int(I.x.size());
    I.buildDetectGrid(g);
    // pairs with a fast grain, sorted by (i, j), merged below into the grain loop
    detectFastPairs<Candidates>(I, g);

    const long* const dims = g.dims;
    const bool hasWalls = !Candidates && !I.walls.empty();
    const std::vector<int>& cellStart = I.cellStart;
    const std::vector<int>& cellItems = I.cellItems;
    std::vector<Contact>& out = I.newContacts;
    std::size_t nextFast = 0;
    for (int i = 0; i < N; ++i)
    {
        const int cell = I.cellOf[i];
        if (cell >= 0)
        {
            const long cx = cell % dims[0];
            const long cy = (cell / dims[0]) % dims[1];
            const long cz = cell / (dims[0] * dims[1]);
            const long z0 = std::max(0L, cz - 1), z1 = std::min(dims[2] - 1, cz + 1);
            const long y0 = std::max(0L, cy - 1), y1 = std::min(dims[1] - 1, cy + 1);
            const long x0 = std::max(0L, cx - 1), x1 = std::min(dims[0] - 1, cx + 1);
            for (long zz = z0; zz <= z1; ++zz)
                for (long yy = y0; yy <= y1; ++yy)
                {
                    const long row = dims[0] * (yy + dims[1] * zz);
                    const int b = cellStart[row + x0], e = cellStart[row + x1 + 1];
                    for (int k = b; k < e; ++k)
                    {
                        const int j = cellItems[k];
                        if (j > i) testPair<Candidates>(I, i, j, g, out);
                    }
                }
        }
        // pairs of i with fast grains (or of fast grain i), already sorted
        while (nextFast < I.fastContacts.size() && I.fastContacts[nextFast].i == i)
            out.push_back(I.fastContacts[nextFast++]);
        if (hasWalls && !I.packed[i].fix) I.detectWalls(i, g.dt, g.margin, g.af);
    }
}
} // namespace

void System::Impl::scanGrid(DetectGrid& g, bool candidates)
{
    if (candidates)
        scanGridPairs<true>(*this, g);
    else
        scanGridPairs<false>(*this, g);
}

void System::Impl::detect(double dt)
{
    // Per-pair alert distances (the reach of each body from its own free
    // velocity, as LMGC90's alert distance): grains i, j are a candidate
    // contact when their gap is below af dt (s_i + s_j) + margin, s_i =
    // speed[i]. A uniform grid sized for the largest reach would make one
    // fast grain enlarge every cell (O(N^2) pair tests for a bed at rest).
    // Instead the grid is sized for the slow grains (s_i <= sCut) only, and
    // the few fast ones (at most maxFast) are paired in a separate pass: each
    // scans the cells its alert sphere covers, and fast-fast pairs are tested
    // directly. Cost O(N + sum over fast grains of their covered cells +
    // F^2), O(N) for a bed with a few fast grains (see selectFastGrains).
    // With Settings::verletSkin > 0 the grid scan only builds the Verlet
    // list of candidate pairs, whose pairs are then re-tested each step in
    // the order of the scan (Verlet.cpp).
    const int N = int(x.size());
    newContacts.clear();
    if (N == 0) return;
    const Settings& S = settings;
    DetectGrid g;
    g.dt = dt;
    g.af = S.alertDistanceFactor;
    g.margin = S.alertMargin * rMin();
    g.rmax = rMax();
    selectFastGrains(g);
    if (S.verletSkin > 0)
        detectListed(g);
    else
        scanGrid(g, false);
}

void System::Impl::detectDroplets(double dt)
{
    const int N = int(x.size());
    const int NW = int(walls.size());
    const Settings& S = settings;
    const double margin = S.alertMargin * rMin();
    for (int k = 0; k < int(droplets.size()); ++k)
    {
        const System::Droplet& D = droplets[k];
        if (!(D.surfaceTension > 0)) continue;
        const Body& B = body[N + NW + k];
        const double sd = B.v.norm();
        for (int i = 0; i < N; ++i)
        {
            const Vec3 d = packed[i].x - D.centre;
            const double dn = d.norm();
            const double ri = packed[i].r;
            const double gap = dn - D.radius - ri;
            const double alert = S.alertDistanceFactor * dt * (speed[i] + sd) + margin;
            if (!(gap > -2 * ri) || gap >= alert || !(dn > 0)) continue;
            if (packed[i].fix && B.im == 0) continue; // neither body can move
            Contact c;
            c.i = i;
            c.j = N + NW + k;
            c.n = d / dn;
            c.gap = gap;
            c.mu = law::CapillaryCap::friction;
            c.cap = law::CapillaryCap::cap(System::capillaryEntryForce(dim, D.surfaceTension, ri, -gap), dt);
            newContacts.push_back(c);
        }
    }
}

double System::Impl::contactGapNow(const Contact& c) const
{
    // (c in slots: grain pairs from the packed records, which integrate()
    // keeps at the end-of-step centres; walls from the per-grain arrays)
    const int N = int(x.size());
    if (c.j < N)
    {
        const GrainSlot& A = packed[c.i];
        const GrainSlot& B = packed[c.j];
        return (A.x - B.x).norm() - A.r - B.r;
    }
    const int i = order[c.i];
    const Wall& W = walls[c.j - N];
    if (W.type == PlaneWall) return (x[i] - (W.p + W.displacement)).dot(W.n) - rad[i];
    if (W.type == SegmentWall)
        return (x[i] - closestSegment(x[i], W.p + W.displacement, W.b + W.displacement)).norm() - rad[i];
    // triangles: linearised with the contact normal
    const Vec3 du = v[i] - W.velocity - rad[i] * w[i].cross(c.n);
    return c.gap + du.dot(c.n) * lastDt;
}

} // namespace nscd
