// SPDX-License-Identifier: GPL-3.0-or-later
// nscd::System: construction, grain/wall/droplet state and accessors.
// (Detection: Detect.cpp; the step in stages: Step.cpp, its solver rows
// ContactRows.cpp, contact solve ContactSolver*.cpp, end of step
// Integrate.cpp; sub-steps and views: SystemExtra.cpp.)
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

} // namespace

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
    if (!(m.compliance >= 0) || !std::isfinite(m.compliance))
        fail("compliance", ">= 0 and finite [m/N] (0: hard contact)", m.compliance);
    if (!(m.relativeCompliance >= 0) || !std::isfinite(m.relativeCompliance))
        fail("relativeCompliance", ">= 0 and finite (0: hard contact)", m.relativeCompliance);
    if (m.compliance > 0 && m.relativeCompliance > 0)
        fail("relativeCompliance", "0 when compliance is given (give one of the two)", m.relativeCompliance);
}
} // namespace

int System::addMaterial(const Material& m)
{
    checkMaterial("addMaterial", m);
    impl_->materials.push_back(m);
    return int(impl_->materials.size()) - 1;
}

// The masses and inertias follow the new density (2D: rho pi r^2 per unit
// depth, r^2/2; 3D: rho 4/3 pi r^3, 2 r^2/5). The warm-start impulses of the
// contacts whose movable grains are all of this material are scaled by the
// density ratio: the contact forces of a packing at rest under gravity alone
// are proportional to the grain masses, so a bed settled with one density
// stays a converged warm start with another (the solution of the next step
// does not depend on the warm start, only its number of sweeps).
void System::setMaterial(int id, const Material& m)
{
    if (id < 0 || id >= int(impl_->materials.size()))
        throw InputError("nscd::System::setMaterial: unknown material id " + std::to_string(id));
    checkMaterial("setMaterial", m);
    Impl& I = *impl_;
    const double ratio = m.density / I.materials[id].density;
    if (ratio != 1.0)
    {
        // warm start of a packing under gravity: impulses scale with the masses
        // (contact records index grains by slot: I.order maps them to grains)
        I.syncKeptContacts();
        const int N = int(I.x.size());
        auto grain = [&](int b) { return b < N ? I.order[b] : -1; };
        auto other = [&](int g) { return g < 0 || I.fix[g] || I.mat[g] == id; };
        auto mine = [&](int g) { return g >= 0 && !I.fix[g] && I.mat[g] == id; };
        for (Contact& c : I.contacts)
        {
            const int a = grain(c.i), b = grain(c.j);
            if ((mine(a) || mine(b)) && other(a) && other(b))
            {
                c.rn *= ratio;
                c.rt *= ratio;
            }
        }
        I.impulseScaledMaterial = id;
        I.materialImpulseScale = ratio;
    }
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

std::size_t System::Impl::appendRow()
{
    columns.grow(1);
    const std::size_t i = x.size() - 1;
    ids[i] = nextId++;
    order.push_back(int(i)); // a new grain takes the last slot
    slotOf.push_back(int(i));
    // the kept contacts name a wall or droplet as body N + k: one more grain
    // shifts them (as Remove.cpp's compaction does the other way), once,
    // when they are next used (keptContactsN)
    if (keptContactsN < 0 && !contacts.empty()) keptContactsN = int(i);
    verlet.invalidate();
    return i;
}

void System::Impl::addGrainRaw(const Vec3& c, double r, int m, bool fixed)
{
    const std::size_t i = appendRow();
    x[i] = c;
    if (dim == 2) x[i].z() = 0;
    rad[i] = r;
    mat[i] = m;
    fix[i] = fixed ? 1 : 0;
    setMassInertia(i);
}

void System::Impl::setMassInertia(std::size_t i)
{
    // 2D: disc per unit depth, 3D: sphere
    const double rho = materials[mat[i]].density, r = rad[i];
    const double ms = dim == 2 ? rho * pi * r * r : rho * 4.0 / 3.0 * pi * r * r * r;
    mass[i] = ms;
    inertia[i] = (dim == 2 ? 0.5 : 0.4) * ms * r * r;
}

int System::addGrain(const Vec3& centre, double radius, int material, bool fixed)
{
    if (!(radius > 0) || !std::isfinite(radius))
    {
        std::ostringstream os;
        os << "nscd::System::addGrain: radius must be > 0, got " << radius << " for grain "
           << impl_->x.size();
        throw InputError(os.str());
    }
    if (material < 0 || material >= int(impl_->materials.size()))
    {
        std::ostringstream os;
        os << "nscd::System::addGrain: unknown material " << material << " for grain " << impl_->x.size()
           << " (" << impl_->materials.size() << " materials defined)";
        throw InputError(os.str());
    }
    if (!finite(centre)) throw InputError("nscd::System::addGrain: non-finite centre");
    impl_->addGrainRaw(centre, radius, material, fixed);
    return int(impl_->x.size()) - 1;
}

std::size_t System::size() const { return impl_->x.size(); }
const std::vector<long>& System::grainIds() const { return impl_->ids; }
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
    return impl_->dim == 2 ? pi * r * r : 4.0 / 3.0 * pi * r * r * r;
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

void System::setFluidDrag(std::size_t i, double coefficient, const Vec3& fluidVelocity)
{
    if (i >= impl_->x.size())
        throw InputError("nscd::System::setFluidDrag: unknown grain " + std::to_string(i));
    if (!(coefficient >= 0) || !std::isfinite(coefficient) || !fluidVelocity.allFinite())
    {
        std::ostringstream os;
        os << "nscd::System::setFluidDrag: grain " << i << ": the drag coefficient must be >= 0 and"
           << " finite and the fluid velocity finite, got " << coefficient << " kg/s and ("
           << fluidVelocity.transpose() << ") m/s";
        throw InputError(os.str());
    }
    impl_->dragCoefficient[i] = coefficient;
    impl_->dragVelocity[i] = fluidVelocity;
    impl_->dragImpulse[i].setZero();
}

double System::fluidDragCoefficient(std::size_t i) const
{
    if (i >= impl_->x.size())
        throw InputError("nscd::System::fluidDragCoefficient: unknown grain " + std::to_string(i));
    return impl_->dragCoefficient[i];
}

const std::vector<Vec3>& System::fluidDragImpulses() const { return impl_->dragImpulse; }

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
    if (impl_->dim == 2)
    {
        w.p.z() = 0;
        w.n.z() = 0;
        w.velocity.z() = 0;
        if (!(w.n.norm() > 0)) throw InputError("nscd::System::addPlane: normal along z in 2D");
        w.n.normalize();
    }
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
                                   const std::vector<std::array<int, 3>>& triangles, const Vec3& velocity)
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

// droplets (capillary entry barrier, Droplet.H)

void checkDroplet(const System::Droplet& d, const char* where)
{
    const bool ok = std::isfinite(d.radius) && d.radius > 0 && std::isfinite(d.mass) && d.mass >= 0
                    && std::isfinite(d.surfaceTension) && d.surfaceTension >= 0 && d.centre.allFinite()
                    && d.velocity.allFinite() && d.force.allFinite();
    if (!ok)
    {
        std::ostringstream os;
        os << where << ": invalid droplet (need radius > 0, mass >= 0, surfaceTension >= 0, finite"
           << " centre/velocity/force), got radius " << d.radius << ", mass " << d.mass << ", surfaceTension "
           << d.surfaceTension;
        throw InputError(os.str());
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
    const double Fmax = dimension == 2 ? 2 * sigma : 2 * M_PI * sigma * r;
    if (h <= r) return Fmax;    // threshold (rising branch replaced)
    if (h >= 2 * r) return 0.0; // fully inside
    const double c = 1 - h / r; // cos(phi), phi in (pi/2, pi)
    const double s2 = std::max(0.0, 1 - c * c);
    return dimension == 2 ? Fmax * std::sqrt(s2) : Fmax * s2;
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
    if (rMinOfStep > 0) return rMinOfStep;
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

double System::minDiameter() const { return 2 * impl_->rMin(); }

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

} // namespace nscd
