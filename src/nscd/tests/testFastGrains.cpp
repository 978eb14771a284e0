// SPDX-License-Identifier: GPL-3.0-or-later
// Fast grains without global sub-steps: per-pair alert
// distances, the separate broad-phase pass of fast grains, the swept normal
// of far-moving pairs and the re-detection of grains that leave their reach.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace nscd;

namespace
{
constexpr double r0 = 1e-3; // radius [m]
constexpr double d0 = 2 * r0;
constexpr double dt = 1e-3;        // [s]
constexpr double V = 50 * d0 / dt; // 50 diameters per step

/// Smallest distance between grains along the straight relative paths of a
/// step, relative to the contact distance: min over pairs and t in [0, 1] of
/// |s0 + t (s1 - s0)| / (r_i + r_j) - 1, s0, s1 the centre separations at the
/// start and end of the step (the motion of a step is a straight line at
/// the end velocity). Negative: the pair passed into each other (a
/// tunnelling pair has a large negative value even if it ends apart).
double minPathClearance(const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                        const std::vector<double>& r)
{
    double c = 1e300;
    for (std::size_t i = 0; i < x0.size(); ++i)
        for (std::size_t j = i + 1; j < x0.size(); ++j)
        {
            const Vec3 a = x0[i] - x0[j], b = x1[i] - x1[j], e = b - a;
            const double t = e.squaredNorm() > 0 ? std::clamp(-a.dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
            c = std::min(c, (a + t * e).norm() / (r[i] + r[j]) - 1);
        }
    return c;
}

/// Largest grain-grain and grain-plane overlap [m] (brute force; planes
/// given as point + unit normal).
double maxOverlap(const System& s, const std::vector<std::pair<Vec3, Vec3>>& planes)
{
    const auto& x = s.positions();
    const auto& r = s.radii();
    double ov = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
    {
        for (std::size_t j = i + 1; j < x.size(); ++j) ov = std::max(ov, r[i] + r[j] - (x[i] - x[j]).norm());
        for (const auto& p : planes) ov = std::max(ov, r[i] - (x[i] - p.first).dot(p.second));
    }
    return ov;
}

/// A dense hexagonal layer of nx x ny (>= 2) discs/spheres of radius r0
/// (touching), lowest row at y = r0, centred on x = 0; returns the top of
/// the layer. box: with a floor and side walls touching the layer (3D: and
/// front and back walls touching it, z = -+r0).
double hexLayer(System& s, int m, int nx, int ny, bool box = false)
{
    if (box)
    {
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.addPlane(Vec3(-(0.5 * nx + 0.5) * d0, 0, 0), Vec3(1, 0, 0));
        s.addPlane(Vec3(0.5 * nx * d0, 0, 0), Vec3(-1, 0, 0));
        if (s.dimension() == 3)
        {
            s.addPlane(Vec3(0, 0, -r0), Vec3(0, 0, 1));
            s.addPlane(Vec3(0, 0, r0), Vec3(0, 0, -1));
        }
    }
    double top = 0;
    for (int b = 0; b < ny; ++b)
        for (int a = 0; a < nx; ++a)
        {
            const Vec3 p(d0 * (a - 0.5 * nx + 0.5 * (b % 2)), r0 + b * std::sqrt(3.0) * r0, 0);
            s.addGrain(p, r0, m);
            top = std::max(top, p.y() + r0);
        }
    return top;
}
} // namespace

// Reference: a rigid grain cannot pass through a rigid plane (no tunnelling),
// and with restitution 0 (NSCD, Signorini) its normal velocity is 0 once it
// rests on the plane. A sphere/disc 20 diameters above a floor moving down at
// 50 diameters per step: one step, no sub-step; it ends on the floor (gap law:
// exactly touching) and stays there; the overlap is below overlapTolerance.
TEST(FastGrains, NoTunnellingThroughAWall)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m = s.addMaterial({2500, 0.4});
        s.addGrain(Vec3(0, 20 * d0, 0), r0, m);
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.velocities()[0] = Vec3(0.3 * V, -V, 0); // oblique: it also slides
        const StepReport r = s.advance(dt, 0.1);
        EXPECT_EQ(r.substeps, 1);
        EXPECT_NEAR(s.positions()[0].y(), r0, 1e-6 * r0) << "dim " << dim;
        for (int k = 0; k < 5; ++k) s.advance(dt, 0.1);
        EXPECT_NEAR(s.velocities()[0].y(), 0.0, 1e-9 * V);
        EXPECT_GT(s.positions()[0].y(), r0 - s.settings().overlapTolerance * r0);
        EXPECT_NO_THROW(s.checkInitialOverlaps());
    }
}

// Reference: no tunnelling, rigid bodies with restitution 0. A fast grain
// (50 d per step) shot down at a dense layer of 20 x 6 touching grains in a
// box that confines it (no gravity): one step of advance(); the impulse
// reaches the floor through the layer within the step, so the grain ends
// resting in the hollow of the top row, at sqrt(3) r0 above it (nothing can
// move: all rigid, restitution 0, jammed), to the overlap tolerance; in
// the following steps it stays on the layer (to the overlap tolerance per
// row), no pair passes into another along a step and no overlap exceeds
// overlapTolerance. (Stopping a grain at 60 m/s on a jammed lattice is a
// hard problem for the Gauss-Seidel solver: the second step may stop at
// maxIterations with ~0.2 m/s left in the lattice.)
TEST(FastGrains, NoTunnellingThroughAConfinedLayer)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m = s.addMaterial({2500, 0.4});
        const double top = hexLayer(s, m, 20, 6, true);
        // above the hollow between two top-row grains (x = -+r0)
        const int f = s.addGrain(Vec3(0, top + 30 * d0, 0), r0, m);
        s.velocities()[f] = Vec3(0, -V, 0);
        for (int k = 0; k < 3; ++k)
        {
            const auto x0 = s.positions();
            const StepReport r = s.advance(dt, 0.1);
            if (k == 0)
            {
                EXPECT_EQ(r.substeps, 1); // the impact step (later steps may sub-step, see advance())
                EXPECT_NEAR(s.positions()[f].y(), top - r0 + std::sqrt(3.0) * r0,
                            s.settings().overlapTolerance * r0);
            }
            EXPECT_LT(r.maxOverlap, s.settings().overlapTolerance * r0) << "dim " << dim << " step " << k;
            EXPECT_GT(s.positions()[f].y(),
                      top - r0 + std::sqrt(3.0) * r0 - 6 * s.settings().overlapTolerance * r0)
                << "dim " << dim << " step " << k;
            if (r.substeps == 1) // straight paths: one step
                EXPECT_GT(minPathClearance(x0, s.positions(), s.radii()), -s.settings().overlapTolerance);
        }
        EXPECT_NO_THROW(s.checkInitialOverlaps());
    }
}

// Reference: no tunnelling; the momentum of a free system (no wall, no
// gravity) is conserved exactly (Newton's third law in every local update,
// eq. 2.26-2.27). A fast grain (50 d per step) shot at a free dense layer of
// 20 x 6 touching grains pushes grains aside: one step of advance() for
// the impact (the grains then slide past each other: later calls may
// sub-step, see advance()); along every step no pair of grains passes into
// each other (straight relative paths, minPathClearance), the total momentum
// is the fast grain's initial one, and no overlap exceeds overlapTolerance.
TEST(FastGrains, NoTunnellingThroughAFreeDenseLayer)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m = s.addMaterial({2500, 0.4});
        const double top = hexLayer(s, m, 20, 6);
        const int f = s.addGrain(Vec3(0.25 * d0, top + 30 * d0, 0), r0, m);
        s.velocities()[f] = Vec3(0, -V, 0);
        const Vec3 p0 = s.mass(f) * s.velocities()[f];
        for (int k = 0; k < 4; ++k)
        {
            const auto x0 = s.positions();
            const StepReport r = s.advance(dt, 0.1);
            if (k == 0) EXPECT_EQ(r.substeps, 1); // the impact step
            EXPECT_TRUE(r.converged);
            EXPECT_LT(r.maxOverlap, s.settings().overlapTolerance * r0) << "dim " << dim << " step " << k;
            if (r.substeps == 1) // straight paths: one step
                EXPECT_GT(minPathClearance(x0, s.positions(), s.radii()), -s.settings().overlapTolerance)
                    << "dim " << dim << " step " << k;
            EXPECT_LT(maxOverlap(s, {}), s.settings().overlapTolerance * r0)
                << "dim " << dim << " step " << k;
            Vec3 p = Vec3::Zero();
            for (std::size_t i = 0; i < s.size(); ++i) p += s.mass(i) * s.velocities()[i];
            EXPECT_LT((p - p0).norm(), 1e-10 * p0.norm()) << "dim " << dim;
        }
        EXPECT_LT(maxOverlap(s, {}), s.settings().overlapTolerance * r0);
    }
}

// Reference: head-on perfectly inelastic collision of two equal spheres
// (restitution 0, frictionless): final common velocity = mean of the initial
// velocities (momentum conservation), kinetic energy halved; the centre of
// mass moves at the mean velocity throughout. Grain A at 50 d per step,
// B at rest 20 d ahead: one step each, they touch at the end of the first
// step, and from the second on both move at V/2.
TEST(FastGrains, HeadOnInelasticCollision)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m = s.addMaterial({2500, 0.0});
        s.addGrain(Vec3(0, 0, 0), r0, m);
        s.addGrain(Vec3(21 * d0, 0, 0), r0, m);
        s.velocities()[0] = Vec3(V, 0, 0);
        const double xc0 = 0.5 * (s.positions()[0].x() + s.positions()[1].x());
        const double E0 = 0.5 * s.mass(0) * V * V;
        for (int k = 1; k <= 3; ++k)
        {
            EXPECT_EQ(s.advance(dt, 0.1).substeps, 1);
            const auto& x = s.positions();
            const auto& v = s.velocities();
            EXPECT_NEAR(0.5 * (x[0].x() + x[1].x()), xc0 + 0.5 * V * k * dt, 1e-9 * d0);
            EXPECT_NEAR(v[0].x() + v[1].x(), V, 1e-9 * V);
            EXPECT_NEAR(x[1].x() - x[0].x(), d0, 1e-6 * d0) << "touching after step " << k;
            if (k >= 2)
            {
                EXPECT_NEAR(v[0].x(), 0.5 * V, 1e-9 * V);
                EXPECT_NEAR(v[1].x(), 0.5 * V, 1e-9 * V);
                const double E = 0.5 * s.mass(0) * (v[0].squaredNorm() + v[1].squaredNorm());
                EXPECT_NEAR(E, 0.5 * E0, 1e-8 * E0);
            }
        }
    }
}

// Reference: free flight. A grain skimming over a row of grains at 50 d
// per step, 0.5 d above their tops, never touches them (its path misses every
// grain by 0.5 d), so its velocity must stay exactly the same. With the
// contact normal taken at the step start, the grains ahead of it would put
// the end of the step in their forbidden half-space: a spurious impact.
TEST(FastGrains, SkimmingGrainIsNotBraked)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m = s.addMaterial({2500, 0.4});
        for (int a = 0; a < 200; ++a) s.addGrain(Vec3(a * d0, 0, 0), r0, m, true); // fixed row
        const int f = s.addGrain(Vec3(0, 1.5 * d0, 0), r0, m);
        const Vec3 v0(V, 0, 0);
        s.velocities()[f] = v0;
        for (int k = 0; k < 3; ++k)
        {
            const StepReport r = s.advance(dt, 0.1);
            EXPECT_EQ(r.substeps, 1);
            EXPECT_GT(r.contacts, 0); // candidates were detected
        }
        EXPECT_EQ(s.velocities()[f], v0) << "dim " << dim;
        EXPECT_NEAR(s.positions()[f].x(), 3 * V * dt, 1e-12);
    }
}

// Reference: the rule of advance() (System.H) - a velocity does not
// sub-step, and the former rule (|v_max| dt_sub <= 0.1 d_min, thesis 5.1.3)
// would have taken 500 sub-steps here - and, for the bed, the same step
// without the fast grain (which flies over it without touching it). A bed of
// 300 grains (60 x 5) at rest in a box with one grain flying over it at 50 d per
// step: ONE step of advance(), no re-detection, and the bed moves as without
// the fast grain (to the solver tolerance).
TEST(FastGrains, BedAtRestWithOneFastGrainTakesOneStep)
{
    for (int dim : {2, 3})
    {
        double top = 0;
        auto bed = [&]()
        {
            System b(dim);
            const int m = b.addMaterial({2500, 0.4});
            top = hexLayer(b, m, 60, 5, true); // box x in [-30.5, 30] d
            b.setGravity(Vec3(0, -9.81, 0));
            for (int k = 0; k < 20; ++k) b.step(dt); // settle the touching layer
            return b;
        };
        System ref = bed();
        ref.advance(dt, 0.1);
        System s = bed();
        const int f = s.addGrain(Vec3(-28 * d0, top + 3 * d0, 0), r0, 0);
        s.velocities()[f] = Vec3(V, 0, 0);
        const StepReport r = s.advance(dt, 0.1);
        EXPECT_EQ(r.substeps, 1);
        EXPECT_EQ(r.redetections, 0);
        EXPECT_TRUE(r.converged);
        double moved = 0;
        for (std::size_t i = 0; i < ref.size(); ++i)
            moved = std::max(moved, (s.positions()[i] - ref.positions()[i]).norm());
        EXPECT_LT(moved, 1e-4 * d0); // solver tolerance 1e-6 d per contact, 5 rows
        EXPECT_NEAR(s.positions()[f].x(), -28 * d0 + V * dt, 1e-9 * d0);
    }
}
