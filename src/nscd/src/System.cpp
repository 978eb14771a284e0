#include "SystemImpl.H"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace nscd
{

namespace
{
constexpr double pi = 3.14159265358979323846;

bool finite(const Vec3& a) { return std::isfinite(a.x()) && std::isfinite(a.y()) && std::isfinite(a.z()); }

/// Exact rotation update q <- exp(w dt / 2) q (w in the global frame), renormalised.
Eigen::Quaterniond rotate(const Eigen::Quaterniond& q, const Vec3& w, double dt)
{
    const double a = w.norm()*dt;
    if (a == 0.0) return q;
    const Eigen::Quaterniond dq(Eigen::AngleAxisd(a, w/w.norm()));
    Eigen::Quaterniond r = dq*q;
    r.normalize();
    return r;
}
}

// ============================================================================
// construction / state
// ============================================================================

System::System(int dimension) : impl_(std::make_unique<Impl>())
{
    if (dimension != 2 && dimension != 3)
        throw InputError("nscd::System: dimension must be 2 or 3, got " + std::to_string(dimension));
    impl_->dim = dimension;
}

System::~System() = default;
System::System(System&&) noexcept = default;
System& System::operator=(System&&) noexcept = default;

int System::dimension() const { return impl_->dim; }

namespace
{
/// Throws InputError naming caller and field if m is not a valid material.
void checkMaterial(const char* caller, const Material& m)
{
    auto fail = [caller](const char* what, const char* must, double a)
    {
        std::ostringstream os;
        os << "nscd::System::" << caller << ": " << what << " must be " << must << ", got " << a;
        throw InputError(os.str());
    };
    if (!(m.density > 0) || !std::isfinite(m.density)) fail("density", "> 0", m.density);
    if (!(m.friction >= 0) || !std::isfinite(m.friction)) fail("friction", ">= 0", m.friction);
    if (!(m.youngModulus >= 0) || !std::isfinite(m.youngModulus))
        fail("youngModulus", ">= 0 and finite", m.youngModulus);
    if (!(m.conductivity >= 0) || !std::isfinite(m.conductivity))
        fail("conductivity", ">= 0 and finite", m.conductivity);
    if (!(m.heatCapacity >= 0) || !std::isfinite(m.heatCapacity))
        fail("heatCapacity", ">= 0 and finite", m.heatCapacity);
    if (!(m.poissonRatio > -1 && m.poissonRatio <= 0.5)) fail("poissonRatio", "in (-1, 0.5]", m.poissonRatio);
}
}

int System::addMaterial(const Material& m)
{
    checkMaterial("addMaterial", m);
    impl_->materials.push_back(m);
    return int(impl_->materials.size()) - 1;
}

void System::setMaterial(int id, const Material& m)
{
    if (id < 0 || id >= int(impl_->materials.size()))
        throw InputError("nscd::System::setMaterial: unknown material id " + std::to_string(id));
    checkMaterial("setMaterial", m);
    Impl& I = *impl_;
    I.materials[id] = m;
    for (std::size_t i = 0; i < I.x.size(); ++i)
        if (I.mat[i] == id) I.setMassInertia(i);
}

int System::nMaterials() const { return int(impl_->materials.size()); }

const Material& System::material(int id) const
{
    if (id < 0 || id >= int(impl_->materials.size()))
        throw InputError("nscd::System::material: unknown material id " + std::to_string(id));
    return impl_->materials[id];
}

void System::Impl::addGrainRaw(const Vec3& c, double r, int m, bool fixed)
{
    Vec3 cc = c;
    if (dim == 2) cc.z() = 0;
    x.push_back(cc);
    v.push_back(Vec3::Zero());
    w.push_back(Vec3::Zero());
    q.push_back(Eigen::Quaterniond::Identity());
    rad.push_back(r);
    mat.push_back(m);
    fix.push_back(fixed ? 1 : 0);
    rotLock.push_back(0);
    force.push_back(Vec3::Zero());
    torque.push_back(Vec3::Zero());
    T.push_back(defaultT);
    heatQ.push_back(0);
    heatH.push_back(0);
    heatTf.push_back(0);
    fixT.push_back(0);
    mass.push_back(0);
    inertia.push_back(0);
    setMassInertia(x.size() - 1);
}

void System::Impl::setMassInertia(std::size_t i)
{
    // 2D: disc per unit depth, 3D: sphere
    const double rho = materials[mat[i]].density, r = rad[i];
    const double ms = dim == 2 ? rho*pi*r*r : rho*4.0/3.0*pi*r*r*r;
    mass[i] = ms;
    inertia[i] = (dim == 2 ? 0.5 : 0.4)*ms*r*r;
}

int System::addGrain(const Vec3& centre, double radius, int material, bool fixed)
{
    if (!(radius > 0) || !std::isfinite(radius))
    {
        std::ostringstream os;
        os << "nscd::System::addGrain: radius must be > 0, got " << radius
           << " for grain " << impl_->x.size();
        throw InputError(os.str());
    }
    if (material < 0 || material >= int(impl_->materials.size()))
    {
        std::ostringstream os;
        os << "nscd::System::addGrain: unknown material " << material << " for grain "
           << impl_->x.size() << " (" << impl_->materials.size() << " materials defined)";
        throw InputError(os.str());
    }
    if (!finite(centre)) throw InputError("nscd::System::addGrain: non-finite centre");
    impl_->addGrainRaw(centre, radius, material, fixed);
    return int(impl_->x.size()) - 1;
}

std::size_t System::size() const { return impl_->x.size(); }
const std::vector<Vec3>& System::positions() const { return impl_->x; }
std::vector<Vec3>& System::positions() { return impl_->x; }
const std::vector<Vec3>& System::velocities() const { return impl_->v; }
std::vector<Vec3>& System::velocities() { return impl_->v; }
const std::vector<Vec3>& System::angularVelocities() const { return impl_->w; }
std::vector<Vec3>& System::angularVelocities() { return impl_->w; }
const std::vector<Eigen::Quaterniond>& System::orientations() const { return impl_->q; }
const std::vector<double>& System::radii() const { return impl_->rad; }
const std::vector<int>& System::materials() const { return impl_->mat; }
bool System::fixed(std::size_t i) const { return impl_->fix.at(i) != 0; }
bool System::rotationLocked(std::size_t i) const { return impl_->rotLock.at(i) != 0; }
void System::setRotationLocked(std::size_t i, bool locked)
{
    if (i >= impl_->x.size())
        throw InputError("nscd::System::setRotationLocked: unknown grain " + std::to_string(i));
    impl_->rotLock[i] = locked ? 1 : 0;
}
double System::mass(std::size_t i) const { return impl_->mass.at(i); }
double System::inertia(std::size_t i) const { return impl_->inertia.at(i); }
double System::volume(std::size_t i) const
{
    const double r = impl_->rad.at(i);
    return impl_->dim == 2 ? pi*r*r : 4.0/3.0*pi*r*r*r;
}

void System::setGravity(const Vec3& g)
{
    impl_->g = g;
    if (impl_->dim == 2) impl_->g.z() = 0;
}
const Vec3& System::gravity() const { return impl_->g; }

void System::setExternalForce(std::size_t i, const Vec3& f, const Vec3& t)
{
    if (i >= impl_->x.size())
        throw InputError("nscd::System::setExternalForce: unknown grain " + std::to_string(i));
    impl_->force[i] = f;
    impl_->torque[i] = t;
}

// ============================================================================
// walls
// ============================================================================

int System::addPlane(const Vec3& point, const Vec3& normal, const Vec3& velocity)
{
    if (!(normal.norm() > 0)) throw InputError("nscd::System::addPlane: zero normal");
    Wall w;
    w.type = PlaneWall;
    w.p = point;
    w.n = normal.normalized();
    w.velocity = velocity;
    if (impl_->dim == 2) { w.p.z() = 0; w.n.z() = 0; w.velocity.z() = 0;
        if (!(w.n.norm() > 0)) throw InputError("nscd::System::addPlane: normal along z in 2D");
        w.n.normalize(); }
    impl_->walls.push_back(std::move(w));
    return int(impl_->walls.size()) - 1;
}

int System::addSegment(const Vec3& a, const Vec3& b, const Vec3& velocity)
{
    if (impl_->dim != 2) throw InputError("nscd::System::addSegment: segments are 2D walls");
    Wall w;
    w.type = SegmentWall;
    w.p = Vec3(a.x(), a.y(), 0);
    w.b = Vec3(b.x(), b.y(), 0);
    if (!((w.b - w.p).norm() > 0)) throw InputError("nscd::System::addSegment: degenerate segment");
    w.velocity = Vec3(velocity.x(), velocity.y(), 0);
    impl_->walls.push_back(std::move(w));
    linkSegment(impl_->walls, int(impl_->walls.size()) - 1);
    return int(impl_->walls.size()) - 1;
}

int System::addTriangulatedSurface(const std::vector<Vec3>& vertices,
                                   const std::vector<std::array<int, 3>>& triangles,
                                   const Vec3& velocity)
{
    if (impl_->dim != 3) throw InputError("nscd::System::addTriangulatedSurface: 3D walls only");
    if (vertices.empty() || triangles.empty())
        throw InputError("nscd::System::addTriangulatedSurface: empty surface");
    for (std::size_t k = 0; k < triangles.size(); ++k)
        for (int c : triangles[k])
            if (c < 0 || c >= int(vertices.size()))
                throw InputError("nscd::System::addTriangulatedSurface: triangle " + std::to_string(k)
                                 + " has vertex index " + std::to_string(c) + " out of range");
    Wall w;
    w.type = TriangleWall;
    w.vertices = vertices;
    w.triangles = triangles;
    w.velocity = velocity;
    w.tree = buildTriangleTree(vertices, triangles);
    buildTriangleFeatures(w);
    impl_->walls.push_back(std::move(w));
    return int(impl_->walls.size()) - 1;
}

void System::setWallVelocity(int wall, const Vec3& vel)
{
    if (wall < 0 || wall >= int(impl_->walls.size()))
        throw InputError("nscd::System::setWallVelocity: unknown wall " + std::to_string(wall));
    impl_->walls[wall].velocity = vel;
    if (impl_->dim == 2) impl_->walls[wall].velocity.z() = 0;
}

void System::setWallFriction(int wall, double mu)
{
    if (wall < 0 || wall >= int(impl_->walls.size()))
        throw InputError("nscd::System::setWallFriction: unknown wall " + std::to_string(wall));
    if (!std::isfinite(mu)) throw InputError("nscd::System::setWallFriction: non-finite friction");
    impl_->walls[wall].friction = mu < 0 ? -1.0 : mu;
}

double System::wallFriction(int wall) const
{
    if (wall < 0 || wall >= int(impl_->walls.size()))
        throw InputError("nscd::System::wallFriction: unknown wall " + std::to_string(wall));
    return impl_->walls[wall].friction;
}

int System::nWalls() const { return int(impl_->walls.size()); }

// droplets (capillary entry barrier, System.H)

namespace
{
void checkDroplet(const System::Droplet& d, const char* where)
{
    const bool ok = std::isfinite(d.radius) && d.radius > 0 && std::isfinite(d.mass) && d.mass >= 0
                    && std::isfinite(d.surfaceTension) && d.surfaceTension >= 0
                    && d.centre.allFinite() && d.velocity.allFinite() && d.force.allFinite();
    if (!ok)
    {
        std::ostringstream os;
        os << where << ": invalid droplet (need radius > 0, mass >= 0, surfaceTension >= 0, finite"
           << " centre/velocity/force), got radius " << d.radius << ", mass " << d.mass
           << ", surfaceTension " << d.surfaceTension;
        throw InputError(os.str());
    }
}
}

int System::addDroplet(const Droplet& d)
{
    checkDroplet(d, "nscd::System::addDroplet");
    impl_->droplets.push_back(d);
    return int(impl_->droplets.size()) - 1;
}

System::Droplet& System::droplet(int id)
{
    if (id < 0 || id >= int(impl_->droplets.size()))
        throw InputError("nscd::System::droplet: unknown droplet " + std::to_string(id));
    return impl_->droplets[id];
}

const System::Droplet& System::droplet(int id) const
{
    if (id < 0 || id >= int(impl_->droplets.size()))
        throw InputError("nscd::System::droplet: unknown droplet " + std::to_string(id));
    return impl_->droplets[id];
}

int System::nDroplets() const { return int(impl_->droplets.size()); }

double System::capillaryEntryForce(int dimension, double sigma, double r, double h)
{
    const double Fmax = dimension == 2 ? 2*sigma : 2*M_PI*sigma*r;
    if (h <= r) return Fmax;              // threshold (rising branch replaced)
    if (h >= 2*r) return 0.0;             // fully inside
    const double c = 1 - h/r;             // cos(phi), phi in (pi/2, pi)
    const double s2 = std::max(0.0, 1 - c*c);
    return dimension == 2 ? Fmax*std::sqrt(s2) : Fmax*s2;
}

Vec3 System::wallDisplacement(int wall) const
{
    if (wall < 0 || wall >= int(impl_->walls.size()))
        throw InputError("nscd::System::wallDisplacement: unknown wall " + std::to_string(wall));
    return impl_->walls[wall].displacement;
}

System::Settings& System::settings() { return impl_->settings; }
const System::Settings& System::settings() const { return impl_->settings; }
double System::time() const { return impl_->time; }

double System::Impl::rMin() const
{
    double r = std::numeric_limits<double>::max();
    for (double a : rad) r = std::min(r, a);
    return rad.empty() ? 0.0 : r;
}

double System::Impl::rMax() const
{
    double r = 0;
    for (double a : rad) r = std::max(r, a);
    return r;
}

double System::minDiameter() const { return 2*impl_->rMin(); }

void System::setCohesion(std::function<bool(int, int)> predicate, double force)
{
    if (!(force >= 0) || !std::isfinite(force))
    {
        std::ostringstream os;
        os << "nscd::System::setCohesion: force must be >= 0 and finite, got " << force;
        throw InputError(os.str());
    }
    impl_->cohesionPredicate = std::move(predicate);
    impl_->cohesionForce = force;
}

// ============================================================================
// detection
// ============================================================================

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

// ============================================================================
// step
// ============================================================================

StepReport System::step(double dt)
{
    if (!(dt > 0) || !std::isfinite(dt))
        throw InputError("nscd::System::step: dt must be > 0, got " + std::to_string(dt));
    Impl& I = *impl_;
    {
        const Settings& S = I.settings;
        if (!(S.tolerance > 0) || S.maxIterations < 1 || !(S.relaxation > 0 && S.relaxation < 2)
            || !(S.overlapSlop >= 0) || !(S.alertDistanceFactor >= 0) || !(S.alertMargin >= 0))
            throw InputError("nscd::System::step: invalid settings (need tolerance > 0, maxIterations >= 1, "
                             "0 < relaxation < 2, overlapSlop >= 0, alert factors >= 0)");
        if (!(S.heatTolerance > 0) || S.heatMaxIterations < 1)
            throw InputError("nscd::System::step: invalid settings (need heatTolerance > 0, heatMaxIterations >= 1)");
        if (S.cohesionMinAge < 0)
            throw InputError("nscd::System::step: invalid settings (need cohesionMinAge >= 0, got "
                             + std::to_string(S.cohesionMinAge) + ")");
    }
    for (const Droplet& d : I.droplets) checkDroplet(d, "nscd::System::step");
    for (Droplet& d : I.droplets)
        if (d.grainImpulse.size() != I.x.size()) d.grainImpulse.assign(I.x.size(), 0.0);
    const bool heat = I.heatCheck();  // throws before anything is changed
    const int N = int(I.x.size());
    const int NW = int(I.walls.size());
    const int ND = int(I.droplets.size());
    const int NB = N + NW + ND;  // bodies: grains, walls, droplets
    const bool twoD = I.dim == 2;
    StepReport rep;
    rep.substeps = 1;

    // ---- free velocity (eq. 2.11) ----
    I.body.resize(NB);
    I.speed.resize(N);
    for (int i = 0; i < N; ++i)
    {
        Body& B = I.body[i];
        Vec3 v = I.v[i], w = I.w[i];
        if (I.fix[i])
        {
            B.im = 0;
            B.ii = 0;
        }
        else
        {
            B.im = 1.0/I.mass[i];
            B.ii = I.rotLock[i] ? 0.0 : 1.0/I.inertia[i];
            v += dt*(I.g + B.im*I.force[i]);
            w += dt*B.ii*I.torque[i];
        }
        if (twoD) { v.z() = 0; w.x() = 0; w.y() = 0; }
        B.v = v;
        B.w = w;
        B.r = I.rad[i];
        I.speed[i] = v.norm() + B.r*w.norm();
    }
    for (int k = 0; k < NW; ++k)
    {
        Body& B = I.body[N + k];
        B.v = I.walls[k].velocity;
        B.w.setZero();
        B.im = B.ii = B.r = 0;
    }
    for (int k = 0; k < ND; ++k)
    {
        // droplet: translation only, its own forces (no System gravity)
        const Droplet& D = I.droplets[k];
        Body& B = I.body[N + NW + k];
        B.im = D.mass > 0 ? 1.0/D.mass : 0.0;
        B.v = D.velocity + dt*B.im*D.force;
        if (twoD) B.v.z() = 0;
        B.w.setZero();
        B.ii = B.r = 0;
    }

    // ---- detection ----
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    I.detect(dt);
    const int NC0 = int(I.newContacts.size());  // grain-grain and grain-wall contacts
    I.detectDroplets(dt);                        // then grain-droplet ones
    const auto t1 = clock::now();
    rep.detectSeconds = std::chrono::duration<double>(t1 - t0).count();
    std::vector<Contact>& C = I.newContacts;
    const int NC = int(C.size());

    // ---- contact constants, cohesion, warm start ----
    const double rmin = I.rMin();
    const double dmin = 2*rmin;
    const double cohDist = I.settings.cohesionDistance*rmin;
    const double slop = I.settings.overlapSlop*rmin;
    const bool cohesion = I.cohesionForce > 0 && bool(I.cohesionPredicate);
    const int minAge = I.settings.cohesionMinAge;
    // previous contacts indexed by i: matched for the warm start and the
    // contact age (the age is tracked also without warm start)
    const std::vector<Contact>& P = I.contacts;
    const bool match = !P.empty();
    const bool warm = I.settings.warmStart && match && I.lastDt > 0;
    if (match)
    {
        I.prevStart.assign(N + 1, 0);
        for (const Contact& c : P) if (c.i < N) ++I.prevStart[c.i + 1];
        for (int i = 0; i < N; ++i) I.prevStart[i + 1] += I.prevStart[i];
    }
    const double scale = warm ? dt/I.lastDt : 0.0;
    for (int k = 0; k < NC; ++k)
    {
        Contact& c = C[k];
        const Body& A = I.body[c.i];
        const Body& B = I.body[c.j];
        c.wnn = A.im + B.im;
        c.wtt = A.im + B.im + A.r*A.r*A.ii + B.r*B.r*B.ii;
        c.iwnn = c.wnn > 0 ? 1.0/c.wnn : 0.0;
        c.iwtt = c.wtt > 0 ? 1.0/c.wtt : 0.0;
        // gap-based Signorini (eq. 2.37 with the gap): u_n^+ >= -g/dt; overlaps
        // within the slop band are only held (u_n^+ >= 0), larger ones are
        // pushed back to the band edge in one step.
        c.bias = c.gap >= 0 || k >= NC0 ? c.gap/dt : (c.gap > -slop ? 0.0 : (c.gap + slop)/dt);
        c.rn = 0;
        c.rt.setZero();
        c.change = 0;
        c.coh = 0;
        c.age = 0;
        // the same contact in the previous step: same bodies, normal within 60 degrees
        int best = -1;
        if (match)
        {
            double bestDot = 0.5;
            for (int p = I.prevStart[c.i]; p < I.prevStart[c.i + 1]; ++p)
            {
                if (P[p].j != c.j) continue;
                const double dd = P[p].n.dot(c.n);
                if (dd > bestDot) { bestDot = dd; best = p; }
            }
            if (best >= 0) c.age = P[best].age;
        }
        // cohesion (eq. 4.18): close, persistent, and the user's condition
        if (cohesion && k < NC0 && c.gap <= cohDist && c.age >= minAge)
        {
            const int jj = c.j < N ? c.j : -(c.j - N + 1);
            if (I.cohesionPredicate(c.i, jj)) c.coh = I.cohesionForce*dt;
        }
        if (warm)
        {
            if (best >= 0)
            {
                const Vec3 imp = scale*(P[best].rn*P[best].n + P[best].rt);
                c.rn = std::max(-c.coh, imp.dot(c.n));
                c.rt = imp - imp.dot(c.n)*c.n;
                const double lim = c.mu*(c.rn + c.coh);
                const double tn = c.rt.norm();
                if (tn > lim) c.rt *= (tn > 0 ? lim/tn : 0.0);
            }
        }
    }
    // apply warm-start impulses
    if (warm)
    {
        for (int k = 0; k < NC; ++k)
        {
            Contact& c = C[k];
            if (c.rn == 0 && c.rt.isZero()) continue;
            Body& A = I.body[c.i];
            Body& B = I.body[c.j];
            const Vec3 Pm = c.rn*c.n + c.rt;
            const Vec3 nxt = c.n.cross(c.rt);
            A.v += A.im*Pm;
            A.w -= A.ii*A.r*nxt;
            B.v -= B.im*Pm;
            B.w -= B.ii*B.r*nxt;
        }
    }

    // ---- adjacency (contacts of each movable grain) ----
    // (bodies of all kinds; walls and fixed grains have none, a movable
    // droplet lists its contacts: a change of its velocity re-flags them)
    auto movableB = [&](int j) { return j < N ? !I.fix[j] : I.body[j].im > 0; };
    I.adjStart.assign(NB + 1, 0);
    for (int k = 0; k < NC; ++k)
    {
        const Contact& c = C[k];
        if (!I.fix[c.i]) ++I.adjStart[c.i + 1];
        if (movableB(c.j)) ++I.adjStart[c.j + 1];
    }
    for (int i = 0; i < NB; ++i) I.adjStart[i + 1] += I.adjStart[i];
    I.adjItems.resize(I.adjStart[NB]);
    {
        I.cellOf.assign(I.adjStart.begin(), I.adjStart.end() - 1);  // cursor
        for (int k = 0; k < NC; ++k)
        {
            const Contact& c = C[k];
            if (!I.fix[c.i]) I.adjItems[I.cellOf[c.i]++] = k;
            if (movableB(c.j)) I.adjItems[I.cellOf[c.j]++] = k;
        }
    }

    // ---- nonlinear Gauss-Seidel with contact queue (Algorithm 2, section 2.3) ----
    const double xi = I.settings.tolerance*dmin;
    const long maxSolves = long(I.settings.maxIterations)*long(std::max(NC, 1));
    long solves = 0;
    Body* body = I.body.data();
    Contact* cs = C.data();
    const int* adjS = I.adjStart.data();
    const int* adjI = I.adjItems.data();
    // One local update (Algorithm 2 body); returns true if the contact had not
    // converged (its impulse was changed), false if |W dr| dt < xi (the
    // previous impulse is kept, as in Algorithm 2).
    const double xi2 = xi*xi, dt2 = dt*dt;
    const double omega = I.settings.relaxation;
    // 2D: scalar tangential impulse along t = z x n (same law, fewer flops)
    if (twoD)
        for (int k = 0; k < NC; ++k)
            cs[k].rts = cs[k].rt.dot(Vec3(-cs[k].n.y(), cs[k].n.x(), 0.0));
    auto solveOne2D = [&](int k) -> bool
    {
        ++solves;
        Contact& c = cs[k];
        Body& A = body[c.i];
        Body& B = body[c.j];
        const double nx = c.n.x(), ny = c.n.y();
        const double dvx = A.v.x() - B.v.x(), dvy = A.v.y() - B.v.y();
        // du.n and du.t with t = (-n_y, n_x): eq. 2.14-2.18 with w = w_z e_z
        const double un = dvx*nx + dvy*ny;
        const double ut = dvy*nx - dvx*ny - A.r*A.w.z() - B.r*B.w.z();
        const double unFree = un - c.wnn*c.rn + c.bias;
        const double utFree = ut - c.wtt*c.rts;
        // eq. 2.38 (stick), 2.39-2.40 (slip forward/backward), 2.41 (W_nt = 0)
        double rn = -unFree*c.iwnn;
        if (rn < -c.coh) rn = -c.coh;
        if (rn > c.cap) rn = c.cap;  // droplet contacts: capillary entry impulse
        double lim = c.mu*(rn + c.coh);
        double rt = -utFree*c.iwtt;
        if (rt > lim) rt = lim;
        else if (rt < -lim) rt = -lim;
        if (omega != 1.0)
        {
            rn = c.rn + omega*(rn - c.rn);
            if (rn < -c.coh) rn = -c.coh;
            if (rn > c.cap) rn = c.cap;
            lim = c.mu*(rn + c.coh);
            rt = c.rts + omega*(rt - c.rts);
            if (rt > lim) rt = lim;
            else if (rt < -lim) rt = -lim;
        }
        const double dn = rn - c.rn;
        const double dtt = rt - c.rts;
        const double ch = (c.wnn*c.wnn*dn*dn + c.wtt*c.wtt*dtt*dtt)*dt2;
        c.change = ch;
        if (ch < xi2) return false;  // converged: keep the previous impulse (Algorithm 2)
        c.rn = rn;
        c.rts = rt;
        const double px = dn*nx - dtt*ny, py = dn*ny + dtt*nx;
        A.v.x() += A.im*px;
        A.v.y() += A.im*py;
        A.w.z() -= A.ii*A.r*dtt;
        B.v.x() -= B.im*px;
        B.v.y() -= B.im*py;
        B.w.z() -= B.ii*B.r*dtt;
        return true;
    };
    auto solveOne3D = [&](int k) -> bool
    {
        ++solves;
        Contact& c = cs[k];
        Body& A = body[c.i];
        Body& B = body[c.j];
        const Vec3& n = c.n;
        // relative velocity at the contact point (eq. 2.14-2.18, 2.28)
        const Vec3 du = A.v - B.v - (A.r*A.w + B.r*B.w).cross(n);
        const double un = du.dot(n);
        // free local velocity: remove this contact's own impulse (Algorithm 2)
        const double unFree = un - c.wnn*c.rn + c.bias;
        const Vec3 utFree = (du - un*n) - c.wtt*c.rt;
        // local law, closed form for diagonal W (same as solveLocalDiagonal,
        // with precomputed inverses): eq. 2.38-2.41
        double rn = -unFree*c.iwnn;
        if (rn < -c.coh) rn = -c.coh;
        if (rn > c.cap) rn = c.cap;  // droplet contacts: capillary entry impulse
        const double rnt = rn + c.coh;
        Vec3 rt;
        if (rnt <= 0.0) rt.setZero();
        else
        {
            rt = utFree*(-c.iwtt);
            const double lim = c.mu*rnt;
            const double n2 = rt.squaredNorm();
            if (n2 > lim*lim) rt *= lim/std::sqrt(n2);
        }
        if (omega != 1.0)
        {
            // projected over-relaxation: r <- Proj_K(r_old + omega (r_solved - r_old))
            rn = c.rn + omega*(rn - c.rn);
            if (rn < -c.coh) rn = -c.coh;
            if (rn > c.cap) rn = c.cap;
            rt = c.rt + omega*(rt - c.rt);
            const double lim = c.mu*(rn + c.coh);
            const double n2 = rt.squaredNorm();
            if (n2 > lim*lim) rt *= (n2 > 0 ? lim/std::sqrt(n2) : 0.0);
        }
        const double dn = rn - c.rn;
        const Vec3 dtv = rt - c.rt;
        // squared change of the contact-point displacement |W dr|^2 dt^2
        const double ch = (c.wnn*c.wnn*dn*dn + c.wtt*c.wtt*dtv.squaredNorm())*dt2;
        c.change = ch;
        if (ch < xi2) return false;  // converged: keep the previous impulse (Algorithm 2)
        c.rn = rn;
        c.rt = rt;
        const Vec3 Pm = dn*n + dtv;
        const Vec3 nxt = n.cross(dtv);
        A.v += A.im*Pm;
        A.w -= A.ii*A.r*nxt;
        B.v -= B.im*Pm;
        B.w -= B.ii*B.r*nxt;
        return true;
    };
    auto solveOne = [&](int k) -> bool { return twoD ? solveOne2D(k) : solveOne3D(k); };
    I.inQueue.assign(NC, 1);
    char* inQ = I.inQueue.data();
    int count = NC;
    if (I.settings.ordering == Settings::Ordering::Fifo)
    {
        // FIFO contact queue (section 2.3): a non-converged contact and the
        // contacts sharing its bodies are (re-)appended to the queue.
        I.queue.resize(NC);
        for (int k = 0; k < NC; ++k) I.queue[k] = k;
        int head = 0;
        int* queue = I.queue.data();
        auto push = [&](int kk)
        {
            if (inQ[kk]) return;
            inQ[kk] = 1;
            int tail = head + count;
            if (tail >= NC) tail -= NC;
            queue[tail] = kk;
            ++count;
        };
        while (count > 0 && solves < maxSolves)
        {
            const int k = queue[head];
            head = (head + 1 == NC) ? 0 : head + 1;
            --count;
            inQ[k] = 0;
            if (!solveOne(k)) continue;
            push(k);
            const Contact& c = cs[k];
            for (int p = adjS[c.i]; p < adjS[c.i + 1]; ++p) push(adjI[p]);
            for (int p = adjS[c.j]; p < adjS[c.j + 1]; ++p) push(adjI[p]);
        }
    }
    else
    {
        // Same queue as a flag set, traversed in alternating (symmetric)
        // sweeps: forward then backward over the contact list (sorted by grain).
        // Only flagged contacts are solved; a non-converged contact flags
        // itself and the contacts sharing its bodies. Alternating directions
        // propagate forces through deep piles in both directions.
        auto mark = [&](int kk) { if (!inQ[kk]) { inQ[kk] = 1; ++count; } };
        int lo = 0, hi = NC - 1;  // range that may contain flagged contacts
        bool forward = true;
        while (count > 0 && solves < maxSolves)
        {
            int nlo = NC, nhi = -1;
            auto visit = [&](int k)
            {
                if (!inQ[k]) return;
                inQ[k] = 0;
                --count;
                if (!solveOne(k)) return;
                mark(k);
                nlo = std::min(nlo, k); nhi = std::max(nhi, k);
                const Contact& c = cs[k];
                for (int p = adjS[c.i]; p < adjS[c.i + 1]; ++p)
                { const int kk = adjI[p]; mark(kk); nlo = std::min(nlo, kk); nhi = std::max(nhi, kk); }
                for (int p = adjS[c.j]; p < adjS[c.j + 1]; ++p)
                { const int kk = adjI[p]; mark(kk); nlo = std::min(nlo, kk); nhi = std::max(nhi, kk); }
            };
            if (forward) for (int k = lo; k <= hi && solves < maxSolves; ++k) visit(k);
            else for (int k = hi; k >= lo && solves < maxSolves; --k) visit(k);
            lo = nlo; hi = nhi;
            forward = !forward;
        }
    }
    if (twoD)
        for (int k = 0; k < NC; ++k)
            cs[k].rt = cs[k].rts*Vec3(-cs[k].n.y(), cs[k].n.x(), 0.0);
    double res = 0;
    for (int k = 0; k < NC; ++k) res = std::max(res, C[k].change);
    res = std::sqrt(res);
    for (int k = 0; k < NC; ++k) C[k].change = std::sqrt(C[k].change);
    rep.solveSeconds = std::chrono::duration<double>(clock::now() - t1).count();
    rep.contacts = NC;
    rep.localSolves = solves;
    rep.sweeps = NC > 0 ? int((solves + NC - 1)/NC) : 0;
    rep.residual = dmin > 0 ? res/dmin : 0;
    rep.converged = count == 0;

    // ---- velocities and positions (eq. 2.9, 5.4), exact rotation ----
    for (int i = 0; i < N; ++i)
    {
        const Body& B = I.body[i];
        I.v[i] = B.v;
        I.w[i] = B.w;
        I.x[i] += dt*B.v;
        I.q[i] = rotate(I.q[i], B.w, dt);
    }
    for (int k = 0; k < NW; ++k) I.walls[k].displacement += dt*I.walls[k].velocity;
    for (int k = 0; k < ND; ++k)
    {
        Droplet& D = I.droplets[k];
        if (D.mass > 0) D.velocity = I.body[N + NW + k].v;
        D.centre += dt*D.velocity;
    }
    for (int k = NC0; k < NC; ++k)  // impulse -r on the droplet (body B)
    {
        Droplet& D = I.droplets[C[k].j - N - NW];
        D.impulse -= C[k].rn*C[k].n;
        D.grainImpulse[C[k].i] += C[k].rn;
    }
    I.time += dt;

    // ---- final overlap, contact age (closed: loaded or touching) ----
    I.lastDt = dt;
    double ov = 0;
    int nCoh = 0;
    for (int k = 0; k < NC0; ++k)
    {
        Contact& c = C[k];
        const double gapNow = I.contactGapNow(c);
        ov = std::max(ov, -gapNow);
        const bool closed = c.rn + c.coh > 0 || gapNow <= xi;
        c.age = closed ? c.age + 1 : 0;
        if (c.coh > 0) ++nCoh;
    }
    rep.maxOverlap = ov;
    rep.cohesiveContacts = nCoh;

    // droplet contacts are not kept (no warm start, views, heat or I/O)
    C.resize(NC0);
    std::swap(I.contacts, I.newContacts);

    // ---- temperatures (eq. 4.1-4.3), with this step's impulses ----
    if (heat)
    {
        const auto t2 = clock::now();
        I.heatStep(dt, rep);
        rep.heatSeconds = std::chrono::duration<double>(clock::now() - t2).count();
    }
    return rep;
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
