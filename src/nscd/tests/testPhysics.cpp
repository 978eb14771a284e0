// SPDX-License-Identifier: GPL-3.0-or-later
// Library-level physics: incline, drop, stack, pile at rest, walls.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace nscd;

namespace
{
constexpr double pi = 3.14159265358979323846;
constexpr double g0 = 9.81;

struct InclineResult
{
    double v;
    double slip;
    double x;
};

// grain of radius r resting on the plane y = 0, gravity tilted by theta:
// returns the down-slope velocity after T, the contact-point slip velocity
// and the displacement.
InclineResult incline(int dim, double thetaDeg, double mu, bool lockRotation, double T = 0.5)
{
    System s(dim);
    const int m = s.addMaterial({2500, mu});
    const double r = 0.01;
    s.addGrain(Vec3(0, r, 0), r, m);
    if (lockRotation) s.setRotationLocked(0);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    const double th = thetaDeg * pi / 180;
    s.setGravity(Vec3(g0 * std::sin(th), -g0 * std::cos(th), 0));
    const double dt = 1e-3;
    const int n = int(std::lround(T / dt));
    for (int k = 0; k < n; ++k)
    {
        const StepReport rep = s.step(dt);
        EXPECT_TRUE(rep.converged);
        EXPECT_LT(rep.maxOverlap, 1e-3 * r);
    }
    const Vec3 v = s.velocities()[0], w = s.angularVelocities()[0];
    // contact point at -r e_y: velocity v + w x (-r e_y)
    const Vec3 vc = v + w.cross(Vec3(0, -r, 0));
    return {v.x(), vc.x(), s.positions()[0].x()};
}

/// A column of n discs of radius r [m] (density 2500 kg/m^3, friction 0.4)
/// touching each other and the floor y = 0, under gravity, solver
/// tolerance 1e-9 d_min.
System discColumn(int n, double r)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    for (int k = 0; k < n; ++k) s.addGrain(Vec3(0, r * (2 * k + 1), 0), r, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -g0, 0));
    s.settings().tolerance = 1e-9;
    return s;
}
} // namespace

// Reference: sliding block on an incline, a = g (sin t - mu cos t) if
// tan t > mu, at rest otherwise (rotation locked). Tolerance 1% on a.
TEST(Incline, RotationLockedStickAndSlide)
{
    for (int dim : {2, 3})
    {
        const InclineResult st = incline(dim, 20, 0.5, true); // tan 20 = 0.364 < 0.5
        EXPECT_LT(std::abs(st.x), 1e-8) << "dim " << dim;
        EXPECT_LT(std::abs(st.v), 1e-8);
        const double th = 30 * pi / 180, mu = 0.3, T = 0.5;
        const InclineResult sl = incline(dim, 30, mu, true, T);
        const double a = g0 * (std::sin(th) - mu * std::cos(th));
        EXPECT_NEAR(sl.v, a * T, 0.01 * a * T) << "dim " << dim;
    }
}

// Reference: free disc/sphere on an incline (rigid body mechanics):
// rolls without slip with a = g sin t/(1 + I/(m r^2)) (2/3 disc, 5/7 sphere) if
// mu >= tan t/(1 + m r^2/I) ; slides with a = g (sin t - mu cos t) otherwise. 1%.
TEST(Incline, FreeRotationRollsOrSlides)
{
    const double T = 0.5;
    for (int dim : {2, 3})
    {
        const double k = dim == 2 ? 0.5 : 0.4; // I = k m r^2
        const double th = 20 * pi / 180;
        const InclineResult roll = incline(dim, 20, 0.5, false, T);
        const double aRoll = g0 * std::sin(th) / (1 + k);
        EXPECT_NEAR(roll.v, aRoll * T, 0.01 * aRoll * T) << "dim " << dim;
        EXPECT_LT(std::abs(roll.slip), 1e-6);
        const double th2 = 40 * pi / 180, mu = 0.05; // mu < tan(40) k/(1+k)
        const InclineResult slide = incline(dim, 40, mu, false, T);
        const double aSl = g0 * (std::sin(th2) - mu * std::cos(th2));
        EXPECT_NEAR(slide.v, aSl * T, 0.01 * aSl * T) << "dim " << dim;
        EXPECT_GT(slide.slip, 0.1);
    }
}

// Reference: inelastic impact (eq. 2.33) with gap-based Signorini: the grain
// lands with zero normal velocity (1e-9 m/s), never overlaps (< 1e-3 r).
TEST(Drop, StopsOnPlaneWithoutOverlap)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m = s.addMaterial({2500, 0.3});
        const double r = 0.01;
        s.addGrain(Vec3(0, 0.3, 0), r, m);
        s.velocities()[0] = Vec3(0.2, 0, 0);
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.setGravity(Vec3(0, -g0, 0));
        const double dt = 1e-3;
        double minY = 1;
        for (int k = 0; k < 600; ++k)
        {
            const StepReport rep = s.step(dt);
            EXPECT_LT(rep.maxOverlap, 1e-3 * r);
            minY = std::min(minY, s.positions()[0].y());
        }
        EXPECT_GT(minY, r * (1 - 1e-3));
        EXPECT_NEAR(s.positions()[0].y(), r, 1e-9);
        EXPECT_NEAR(s.velocities()[0].y(), 0.0, 1e-9);
    }
}

// Reference: static equilibrium; a resting column keeps its positions
// (displacement < 1e-6 r after 2 s) and overlaps below overlapTolerance*r;
// the floor carries the weight (1e-5 relative, solver tolerance 1e-9 d_min).
TEST(Rest, StackOfDiscsStaysAtRest)
{
    const double r = 0.005;
    const int n = 8;
    // xi = 1e-9 d_min: impulse error per contact ~ xi/(W dt^2 g) relative
    System s = discColumn(n, r);
    s.checkInitialOverlaps();
    const auto x0 = s.positions();
    for (int k = 0; k < 2000; ++k)
    {
        const StepReport rep = s.step(1e-3);
        EXPECT_TRUE(rep.converged);
        EXPECT_LT(rep.maxOverlap, 1e-3 * r);
    }
    for (int k = 0; k < n; ++k) EXPECT_LT((s.positions()[k] - x0[k]).norm(), 1e-6 * r);
    // the bottom contact carries the whole weight (1e-9 relative)
    double bottom = 0;
    for (const auto& c : s.contacts())
        if (c.j < 0) bottom = c.impulse.y();
    EXPECT_NEAR(bottom, n * s.mass(0) * g0 * 1e-3, 1e-5 * n * s.mass(0) * g0 * 1e-3);
}

namespace
{
// polydisperse pile in a box of planes, deposited, then checked for creep
void pile(int dim, int nx, int nz, double& creep, double& overlap, double rmin)
{
    System s(dim);
    const int m = s.addMaterial({2500, 0.4});
    std::mt19937 gen(1);
    std::uniform_real_distribution<double> U(rmin, 1.5 * rmin);
    const double h = 3.2 * rmin, L = nx * h;
    for (int a = 0; a < nx; ++a)
        for (int b = 0; b < 12; ++b)
            for (int c = 0; c < (dim == 3 ? nz : 1); ++c)
                s.addGrain(Vec3((a + 0.5) * h, (b + 0.5) * h, dim == 3 ? (c + 0.5) * h : 0.0), U(gen), m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
    s.addPlane(Vec3(L, 0, 0), Vec3(-1, 0, 0));
    if (dim == 3)
    {
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 0, 1));
        s.addPlane(Vec3(0, 0, nz * h), Vec3(0, 0, -1));
    }
    s.setGravity(Vec3(0, -g0, 0));
    s.checkInitialOverlaps();
    const double dt = 5e-4;
    for (int k = 0; k < 4000; ++k) s.step(dt);
    const auto x0 = s.positions();
    overlap = 0;
    for (int k = 0; k < 1000; ++k)
    {
        const StepReport rep = s.step(dt);
        overlap = std::max(overlap, rep.maxOverlap);
    }
    creep = 0;
    for (std::size_t k = 0; k < s.size(); ++k) creep = std::max(creep, (s.positions()[k] - x0[k]).norm());
    EXPECT_NO_THROW(s.checkInitialOverlaps());
}

// Reference: static equilibrium of a dense deposit; after settling, no grain
// moves by more than 1e-3 r_min in 0.5 s (no creep), overlaps < 1e-3 r_min.
void expectPileAtRest(int dim, int nx, int nz)
{
    double creep, overlap;
    const double rmin = 0.002;
    pile(dim, nx, nz, creep, overlap, rmin);
    EXPECT_LT(creep, 1e-3 * rmin);
    EXPECT_LT(overlap, 1e-3 * rmin);
}
} // namespace

TEST(Rest, DensePileStaysAtRest2D) { expectPileAtRest(2, 12, 1); }

TEST(Rest, DensePileStaysAtRest3D) { expectPileAtRest(3, 5, 5); }

// Moving wall: a plane pushing a grain at constant speed (no gravity) carries it.
TEST(Walls, MovingPlanePushesGrain)
{
    System s(2);
    const int m = s.addMaterial({1000, 0.3});
    s.addGrain(Vec3(0.1, 0, 0), 0.01, m);
    const int w = s.addPlane(Vec3(0.05, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0));
    for (int k = 0; k < 400; ++k) s.step(1e-3);
    EXPECT_NEAR(s.wallDisplacement(w).x(), 0.2, 1e-12);
    EXPECT_NEAR(s.positions()[0].x(), 0.05 + 0.2 + 0.01, 1e-9);
    EXPECT_NEAR(s.velocities()[0].x(), 0.5, 1e-9);
}

// 2D segment walls: a V-shaped funnel holds a disc; grains never cross.
TEST(Walls, SegmentsHoldDisc)
{
    System s(2);
    const int m = s.addMaterial({1000, 0.0});
    s.addGrain(Vec3(0.0, 0.5, 0), 0.05, m);
    s.addSegment(Vec3(-1, 1, 0), Vec3(0, 0, 0));
    s.addSegment(Vec3(0, 0, 0), Vec3(1, 1, 0));
    s.setGravity(Vec3(0, -g0, 0));
    for (int k = 0; k < 2000; ++k) EXPECT_LT(s.step(1e-3).maxOverlap, 1e-4);
    // rests where it touches both segments: centre height r*sqrt(2)
    EXPECT_NEAR(s.positions()[0].y(), 0.05 * std::sqrt(2.0), 1e-6);
    EXPECT_NEAR(s.positions()[0].x(), 0.0, 1e-6);
}

// 3D triangulated walls (CGAL AABB tree): a frictionless sphere slides into a
// box corner made of triangles and rests touching the three faces (1e-6 m).
TEST(Walls, TriangulatedFloorAndCorner)
{
    System s(3);
    const int m = s.addMaterial({1000, 0.0});
    const double r = 0.05;
    s.addGrain(Vec3(0.3, 0.4, 0.3), r, m);
    s.velocities()[0] = Vec3(-1.0, 0, -1.0);
    // floor y=0 and walls x=0, z=0 (two triangles each, one surface)
    std::vector<Vec3> v = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 0, 1), Vec3(0, 0, 1),
                           Vec3(0, 1, 0), Vec3(0, 1, 1), Vec3(1, 1, 0)};
    std::vector<std::array<int, 3>> t = {{0, 1, 2}, {0, 2, 3}, {0, 3, 5}, {0, 5, 4}, {0, 4, 6}, {0, 6, 1}};
    s.addTriangulatedSurface(v, t);
    s.setGravity(Vec3(0, -g0, 0));
    for (int k = 0; k < 1500; ++k) EXPECT_LT(s.step(1e-3).maxOverlap, 1e-3 * r);
    EXPECT_NEAR(s.positions()[0].x(), r, 1e-6);
    EXPECT_NEAR(s.positions()[0].y(), r, 1e-6);
    EXPECT_NEAR(s.positions()[0].z(), r, 1e-6);
}

// Solver variants (FIFO queue of section 2.3, symmetric sweeps, slop band,
// over-relaxation) all give the static solution of a resting column: floor
// impulse = weight (1e-5 relative at xi = 1e-9 d_min), overlap < slop + 1e-3 r.
TEST(Solver, VariantsGiveTheStaticColumn)
{
    struct Variant
    {
        System::Settings::Ordering o;
        double slop;
        double relax;
    };
    for (const Variant& v : {Variant{System::Settings::Ordering::Fifo, 0.0, 1.0},
                             Variant{System::Settings::Ordering::Symmetric, 0.0, 1.0},
                             Variant{System::Settings::Ordering::Symmetric, 1e-4, 1.0},
                             Variant{System::Settings::Ordering::Fifo, 1e-4, 1.3}})
    {
        const double r = 0.005;
        const int n = 8;
        System s = discColumn(n, r);
        s.settings().ordering = v.o;
        s.settings().overlapSlop = v.slop;
        s.settings().relaxation = v.relax;
        for (int k = 0; k < 500; ++k)
        {
            const StepReport rep = s.step(1e-3);
            EXPECT_TRUE(rep.converged);
            EXPECT_LT(rep.maxOverlap, (v.slop + 1e-3) * r);
        }
        double bottom = 0;
        for (const auto& c : s.contacts())
            if (c.j < 0) bottom = c.impulse.y();
        const double w = n * s.mass(0) * g0 * 1e-3;
        EXPECT_NEAR(bottom, w, 1e-5 * w) << "ordering " << int(v.o) << " slop " << v.slop;
    }
    System s(2);
    s.settings().relaxation = 2.5;
    EXPECT_THROW(s.step(1e-3), InputError);
}

// Over-relaxation near 2 cycles on the column's slow mode (successive
// over-relaxation contracts by |omega - 1| a sweep past its optimum: 0.99
// at 1.99, ~2,000 sweeps for the 1e-9 d_min tolerance); the safeguard of
// Settings::relaxation goes on with plain Gauss-Seidel after half of
// maxIterations, and the step converges to the static solution (floor
// impulse = weight of the column, 1e-5 relative).
TEST(Solver, OverRelaxationFallsBackToGaussSeidel)
{
    for (const double relax : {1.99, 1.0})
    {
        const int n = 4;
        System s = discColumn(n, 0.005);
        s.settings().overlapSlop = 0;
        s.settings().relaxation = relax;
        s.settings().maxIterations = 400;
        const StepReport rep = s.step(1e-3);
        EXPECT_TRUE(rep.converged) << "relaxation " << relax;
        EXPECT_EQ(rep.relaxationFallbacks, relax == 1.0 ? 0 : 1);
        if (relax != 1.0) EXPECT_GT(rep.sweeps, 200);
        double bottom = 0;
        for (const auto& c : s.contacts())
            if (c.j < 0) bottom = c.impulse.y();
        const double w = n * s.mass(0) * g0 * 1e-3;
        EXPECT_NEAR(bottom, w, 1e-5 * w) << "relaxation " << relax;
        std::printf("[ relaxation %g ] sweeps %d, fallbacks %d\n", relax, rep.sweeps,
                    rep.relaxationFallbacks);
    }
}
