// Contact detection: uniform grid for grain pairs, walls (planes, segments,
// triangulated surfaces) and droplets; gap of a contact after the step.
#include "SystemImpl.H"

#include <algorithm>
#include <cmath>

namespace nscd
{

namespace
{
/// closest point of segment [a, b] to p
inline Vec3 closestSegment(const Vec3& p, const Vec3& a, const Vec3& b)
{
    const Vec3 ab = b - a;
    double t = (p - a).dot(ab)/ab.squaredNorm();
    t = std::min(1.0, std::max(0.0, t));
    return a + t*ab;
}
}

void System::Impl::detectWalls(int i, double dt, double margin, double alertFactor)
{
    const int N = int(x.size());
    const Vec3& xi = x[i];
    const double ri = rad[i];
    const double mu = materials[mat[i]].friction;
    const std::size_t first = newContacts.size();  // wall contacts of grain i start here
    triPoints.clear();
    for (int wi = 0; wi < int(walls.size()); ++wi)
    {
        const Wall& W = walls[wi];
        const double alert = alertFactor*dt*(speed[i] + W.velocity.norm()) + margin;
        auto push = [&](const Vec3& n, double gap)
        {
            Contact c;
            c.i = i;
            c.j = N + wi;
            c.n = n;
            c.gap = gap;
            c.mu = W.friction >= 0 ? W.friction : mu;
            newContacts.push_back(c);
        };
        if (W.type == PlaneWall)
        {
            const double gap = (xi - (W.p + W.displacement)).dot(W.n) - ri;
            if (gap < alert) push(W.n, gap);
        }
        else if (W.type == SegmentWall)
        {
            const Vec3 a = W.p + W.displacement, b = W.b + W.displacement;
            const Vec3 ab = b - a;
            const double t = (xi - a).dot(ab)/ab.squaredNorm();
            const int end = t <= 0 ? 0 : (t >= 1 ? 1 : -1);
            const int nb = end >= 0 ? W.segNb[end] : -1;
            if (nb >= 0 && walls[nb].displacement == W.displacement)
            {
                if (W.segFlat[end])
                {
                    // joint with a collinear neighbour: beyond it the
                    // neighbour's interior contact carries the grain; at the
                    // joint itself, contact with the line (no tilted normal)
                    if (t < -1e-9 || t > 1 + 1e-9) continue;
                    Vec3 n(-ab.y(), ab.x(), 0.0);
                    n.normalize();
                    double s = (xi - a).dot(n);
                    if (s < 0) { s = -s; n = -n; }
                    if (s - ri < alert && s > 0) push(n, s - ri);
                    continue;
                }
                // convex corner shared with a lower-numbered segment: if its
                // closest point is the same corner, it already gave this contact
                if (nb < wi)
                {
                    const Wall& T = walls[nb];
                    const Vec3 corner = end == 0 ? a : b;
                    const Vec3 ct = closestSegment(xi, T.p + T.displacement, T.b + T.displacement);
                    if ((ct - corner).norm() <= 1e-9*ab.norm()) continue;
                }
            }
            const Vec3 cp = a + std::min(1.0, std::max(0.0, t))*ab;
            const Vec3 d = xi - cp;
            const double dn = d.norm();
            if (dn - ri < alert && dn > 0) push(d/dn, dn - ri);
        }
        else
        {
            const Vec3 xl = xi - W.displacement;  // tree coordinates
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
                    cp = xl - sd*fn;
                }
                if (!(dn > 0) || dn - ri >= alert) continue;
                triPoints.push_back({dn, cp + W.displacement, wi});
            }
        }
    }
    // triangle candidates of all triangulated walls, nearest first: a
    // candidate is kept only if it lies strictly in front of every kept
    // contact plane of this grain (any wall) and has a distinct normal. This
    // merges the face contacts of neighbouring (also flat) triangles, also
    // across patches, removes shadowed edge points, keeps genuine convex edges.
    if (triPoints.empty()) return;
    std::sort(triPoints.begin(), triPoints.end(),
              [](const TriPoint& a, const TriPoint& b) { return a.d < b.d; });
    const double eps = 1e-9*ri;
    for (const TriPoint& tp : triPoints)
    {
        const Vec3 n = (xi - tp.c)/tp.d;
        bool keep = true;
        for (std::size_t k = first; k < newContacts.size() && keep; ++k)
        {
            const Vec3 ck = xi - (newContacts[k].gap + ri)*newContacts[k].n;
            if ((tp.c - ck).dot(newContacts[k].n) <= eps || newContacts[k].n.dot(n) > 1.0 - 1e-6) keep = false;
        }
        if (keep)
        {
            Contact c;
            c.i = i;
            c.j = N + tp.wall;
            c.n = n;
            c.gap = tp.d - ri;
            c.mu = walls[tp.wall].friction >= 0 ? walls[tp.wall].friction : mu;
            newContacts.push_back(c);
        }
    }
}

void System::Impl::detect(double dt)
{
    const int N = int(x.size());
    newContacts.clear();
    if (N == 0) return;
    const Settings& S = settings;
    const double rmin = rMin(), rmax = rMax();
    const double margin = S.alertMargin*rmin;
    double smax = 0;
    for (int i = 0; i < N; ++i) smax = std::max(smax, speed[i]);
    const double alertMax = S.alertDistanceFactor*dt*2*smax + margin;
    double h = 2*rmax + alertMax;

    // bounding box
    Vec3 lo = x[0], hi = x[0];
    for (int i = 1; i < N; ++i) { lo = lo.cwiseMin(x[i]); hi = hi.cwiseMax(x[i]); }
    const int D = dim;
    auto ncells = [&](double hh, long dims[3])
    {
        long tot = 1;
        for (int d = 0; d < 3; ++d)
        {
            dims[d] = (d < D) ? long((hi[d] - lo[d])/hh) + 1 : 1;
            tot *= dims[d];
        }
        return tot;
    };
    long dims[3];
    long tot = ncells(h, dims);
    const long cap = std::max<long>(4L*N, 64);
    while (tot > cap) { h *= 1.5; tot = ncells(h, dims); }
    const double ih = 1.0/h;

    // counting sort of grains into cells
    cellOf.resize(N);
    cellStart.assign(tot + 1, 0);
    for (int i = 0; i < N; ++i)
    {
        long c[3] = {0, 0, 0};
        for (int d = 0; d < D; ++d) c[d] = std::min(dims[d] - 1, long((x[i][d] - lo[d])*ih));
        const int cell = int(c[0] + dims[0]*(c[1] + dims[1]*c[2]));
        cellOf[i] = cell;
        ++cellStart[cell + 1];
    }
    for (long c = 0; c < tot; ++c) cellStart[c + 1] += cellStart[c];
    cellItems.resize(N);
    {
        // use adjStart as a temporary cursor array
        adjStart.assign(cellStart.begin(), cellStart.end() - 1);
        for (int i = 0; i < N; ++i) cellItems[adjStart[cellOf[i]]++] = i;
    }

    const double af = S.alertDistanceFactor;
    const bool hasWalls = !walls.empty();
    for (int i = 0; i < N; ++i)
    {
        const int cell = cellOf[i];
        const long cx = cell % dims[0];
        const long cy = (cell/dims[0]) % dims[1];
        const long cz = cell/(dims[0]*dims[1]);
        const Vec3 xi = x[i];
        const double ri = rad[i];
        const double si = speed[i];
        const bool fi = fix[i];
        const double mui = materials[mat[i]].friction;
        const long z0 = std::max(0L, cz - 1), z1 = std::min(dims[2] - 1, cz + 1);
        const long y0 = std::max(0L, cy - 1), y1 = std::min(dims[1] - 1, cy + 1);
        const long x0 = std::max(0L, cx - 1), x1 = std::min(dims[0] - 1, cx + 1);
        for (long zz = z0; zz <= z1; ++zz)
        for (long yy = y0; yy <= y1; ++yy)
        {
            const long row = dims[0]*(yy + dims[1]*zz);
            const int b = cellStart[row + x0], e = cellStart[row + x1 + 1];
            for (int k = b; k < e; ++k)
            {
                const int j = cellItems[k];
                if (j <= i) continue;
                if (fi && fix[j]) continue;
                const Vec3 d = xi - x[j];
                const double sum = ri + rad[j];
                const double alert = af*dt*(si + speed[j]) + margin;
                const double lim = sum + alert;
                const double d2 = d.squaredNorm();
                if (d2 >= lim*lim) continue;
                const double dn = std::sqrt(d2);
                if (!(dn > 0)) continue;
                Contact c;
                c.i = i;
                c.j = j;
                c.n = d/dn;
                c.gap = dn - sum;
                c.mu = 0.5*(mui + materials[mat[j]].friction);
                newContacts.push_back(c);
            }
        }
        if (hasWalls && !fi) detectWalls(i, dt, margin, af);
    }
}

void System::Impl::detectDroplets(double dt)
{
    const int N = int(x.size());
    const int NW = int(walls.size());
    const Settings& S = settings;
    const double margin = S.alertMargin*rMin();
    for (int k = 0; k < int(droplets.size()); ++k)
    {
        const System::Droplet& D = droplets[k];
        if (!(D.surfaceTension > 0)) continue;
        const Body& B = body[N + NW + k];
        const double sd = B.v.norm();
        for (int i = 0; i < N; ++i)
        {
            const Vec3 d = x[i] - D.centre;
            const double dn = d.norm();
            const double ri = rad[i];
            const double gap = dn - D.radius - ri;
            const double alert = S.alertDistanceFactor*dt*(speed[i] + sd) + margin;
            if (!(gap > -2*ri) || gap >= alert || !(dn > 0)) continue;
            if (fix[i] && B.im == 0) continue;   // neither body can move
            Contact c;
            c.i = i;
            c.j = N + NW + k;
            c.n = d/dn;
            c.gap = gap;
            c.mu = 0;
            c.cap = System::capillaryEntryForce(dim, D.surfaceTension, ri, -gap)*dt;
            newContacts.push_back(c);
        }
    }
}

double System::Impl::contactGapNow(const Contact& c) const
{
    const int N = int(x.size());
    if (c.j < N) return (x[c.i] - x[c.j]).norm() - rad[c.i] - rad[c.j];
    const Wall& W = walls[c.j - N];
    if (W.type == PlaneWall) return (x[c.i] - (W.p + W.displacement)).dot(W.n) - rad[c.i];
    if (W.type == SegmentWall)
        return (x[c.i] - closestSegment(x[c.i], W.p + W.displacement, W.b + W.displacement)).norm() - rad[c.i];
    // triangles: linearised with the contact normal
    const Vec3 du = v[c.i] - W.velocity - rad[c.i]*w[c.i].cross(c.n);
    return c.gap + du.dot(c.n)*lastDt;
}

} // namespace nscd
