// SPDX-License-Identifier: GPL-3.0-or-later
// Wall contacts at internal edges of flat triangulated / segmented walls,
// genuine convex edges, and fixed grains against walls.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

using namespace nscd;

namespace
{
constexpr double g0 = 9.81;
constexpr double theta = 30.0 * 3.14159265358979323846 / 180.0;

/// Floor y = 0, x in [0, L], z in [0, W], nx x nz quads, each split into 2 triangles.
void addTriangulatedFloor(System& s, double L, double W, int nx, int nz, double x0 = 0)
{
    std::vector<Vec3> v;
    std::vector<std::array<int, 3>> t;
    for (int k = 0; k <= nz; ++k)
        for (int i = 0; i <= nx; ++i) v.emplace_back(x0 + L * i / nx, 0.0, W * k / nz);
    auto id = [&](int i, int k) { return k * (nx + 1) + i; };
    for (int k = 0; k < nz; ++k)
        for (int i = 0; i < nx; ++i)
        {
            // alternate the diagonal so that both edge orientations occur
            if ((i + k) % 2 == 0)
            {
                t.push_back({id(i, k), id(i, k + 1), id(i + 1, k + 1)});
                t.push_back({id(i, k), id(i + 1, k + 1), id(i + 1, k)});
            }
            else
            {
                t.push_back({id(i, k), id(i, k + 1), id(i + 1, k)});
                t.push_back({id(i + 1, k), id(i, k + 1), id(i + 1, k + 1)});
            }
        }
    s.addTriangulatedSurface(v, t);
}

/// Slide a grain from x = x0 along +x under gravity tilted by theta; return
/// the mean acceleration between t1 and t2 (from the velocity).
double slide(System& s, double dt, double t1, double t2)
{
    s.setGravity(g0 * Vec3(std::sin(theta), -std::cos(theta), 0));
    const int n1 = int(std::lround(t1 / dt)), n2 = int(std::lround(t2 / dt));
    double v1 = 0;
    for (int k = 0; k < n2; ++k)
    {
        const StepReport r = s.step(dt);
        EXPECT_LT(r.maxOverlap, 1e-3 * s.radii()[0]);
        if (k + 1 == n1) v1 = s.velocities()[0].x();
    }
    EXPECT_NEAR(s.velocities()[0].y(), 0.0, 1e-6);
    return (s.velocities()[0].x() - v1) / (t2 - t1);
}
} // namespace

// A sphere sliding across a 20 x 2-quad triangulated floor (80 triangles, the
// internal edges and vertices are flat) is not braked at the edges:
// a = g (sin theta - mu cos theta) within 0.5 %.
TEST(WallEdges, SphereSlidesAcrossTriangulatedFloor)
{
    const double mu = 0.1, r = 0.01;
    const double ref = g0 * (std::sin(theta) - mu * std::cos(theta));
    for (int patches : {1, 2})
    {
        System s(3);
        const int m = s.addMaterial({2500, mu});
        s.addGrain(Vec3(0.02, r, 0.025), r, m); // on the middle line z = W/2 (edges and vertices)
        if (patches == 1)
            addTriangulatedFloor(s, 1.0, 0.05, 20, 2);
        else // the same floor as two surfaces (two mesh patches) meeting at x = 0.3
        {
            addTriangulatedFloor(s, 0.3, 0.05, 6, 2);
            addTriangulatedFloor(s, 0.7, 0.05, 14, 2, 0.3);
        }
        const double a = slide(s, 1e-4, 0.05, 0.6);
        std::printf("patches %d: a = %.5f (g (sin - mu cos) = %.5f)\n", patches, a, ref);
        EXPECT_NEAR(a, ref, 5e-3 * ref);
        EXPECT_GT(s.positions()[0].x(), 0.6); // crossed many triangles
        int n = 0;
        for (const auto& c : s.contacts())
        {
            ++n;
            EXPECT_NEAR(c.normal.y(), 1.0, 1e-9);
        }
        EXPECT_EQ(n, 1);
    }
}

// Same with the floor itself inclined by 30 degrees (vertical gravity) and its
// vertices rounded to 6 significant digits, as in an ASCII mesh: the
// triangles are coplanar only to ~1e-6 rad, and the grain runs off the
// middle line (it crosses the diagonals).
TEST(WallEdges, SphereSlidesAcrossInclinedRoundedMesh)
{
    const double mu = 0.1, r = 0.01;
    System s(3);
    const int m = s.addMaterial({2500, mu});
    const Eigen::Matrix3d R = Eigen::AngleAxisd(-theta, Vec3::UnitZ()).toRotationMatrix();
    const int nx = 20, nz = 2;
    const double L = 1.0, W = 0.05;
    std::vector<Vec3> v;
    std::vector<std::array<int, 3>> t;
    auto round6 = [](double a)
    {
        char b[32];
        std::snprintf(b, sizeof b, "%.6g", a);
        return std::atof(b);
    };
    for (int k = 0; k <= nz; ++k)
        for (int i = 0; i <= nx; ++i)
        {
            const Vec3 p = R * Vec3(L * i / nx, 0.0, W * k / nz) + Vec3(0.1, 0.7, 0);
            v.emplace_back(round6(p.x()), round6(p.y()), round6(p.z()));
        }
    auto id = [&](int i, int k) { return k * (nx + 1) + i; };
    for (int k = 0; k < nz; ++k)
        for (int i = 0; i < nx; ++i)
        {
            t.push_back({id(i, k), id(i, k + 1), id(i + 1, k + 1)});
            t.push_back({id(i, k), id(i + 1, k + 1), id(i + 1, k)});
        }
    s.addTriangulatedSurface(v, t);
    const Vec3 down = R * Vec3(0, -1, 0), along = R * Vec3(1, 0, 0);
    s.addGrain(R * Vec3(0.02, r * (1 + 1e-5), 0.013) + Vec3(0.1, 0.7, 0), r, m);
    s.setGravity(Vec3(0, -g0, 0));
    const double dt = 1e-4;
    double v1 = 0;
    for (int k = 0; k < 6000; ++k)
    {
        EXPECT_LT(s.step(dt).maxOverlap, 1e-3 * r);
        if (k + 1 == 500) v1 = s.velocities()[0].dot(along);
    }
    const double a = (s.velocities()[0].dot(along) - v1) / 0.55;
    const double ref = g0 * (std::sin(theta) - mu * std::cos(theta));
    std::printf("inclined rounded mesh: a = %.5f (g (sin - mu cos) = %.5f)\n", a, ref);
    EXPECT_NEAR(a, ref, 5e-3 * ref);
    EXPECT_NEAR(s.velocities()[0].dot(down), 0.0, 1e-3);
}

// Disc sliding across 20 collinear segments.
TEST(WallEdges, DiscSlidesAcrossCollinearSegments)
{
    const double mu = 0.1, r = 0.01;
    System s(2);
    const int m = s.addMaterial({2500, mu});
    s.addGrain(Vec3(0.02, r, 0), r, m);
    for (int k = 0; k < 20; ++k) s.addSegment(Vec3(0.05 * k, 0, 0), Vec3(0.05 * (k + 1), 0, 0));
    const double a = slide(s, 1e-4, 0.05, 0.6);
    const double ref = g0 * (std::sin(theta) - mu * std::cos(theta));
    std::printf("segments: a = %.5f (g (sin - mu cos) = %.5f)\n", a, ref);
    EXPECT_NEAR(a, ref, 5e-3 * ref);
    EXPECT_GT(s.positions()[0].x(), 0.6);
    EXPECT_EQ(s.nContacts(), 1u);
}

// Genuine convex edges keep their contact: a sphere resting on the edge of a
// triangulated box (gravity towards the edge), a disc on the corner of two
// perpendicular segments.
TEST(WallEdges, ConvexEdgesStillContact)
{
    const double r = 0.01;
    {
        System s(3);
        const int m = s.addMaterial({2500, 0.5});
        // box [-1, 0] x [-1, 0] x [0, 1]: top y = 0 and side x = 0 (2 triangles each)
        std::vector<Vec3> v = {Vec3(-1, 0, 0), Vec3(0, 0, 0),  Vec3(0, 0, 1),
                               Vec3(-1, 0, 1), Vec3(0, -1, 0), Vec3(0, -1, 1)};
        std::vector<std::array<int, 3>> t = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
        s.addTriangulatedSurface(v, t);
        const Vec3 n = Vec3(1, 1, 0).normalized();
        s.addGrain(Vec3(0, 0, 0.5) + r * n, r, m);
        s.checkInitialOverlaps();
        s.setGravity(-g0 * n);
        for (int k = 0; k < 200; ++k) s.step(1e-4);
        ASSERT_EQ(s.nContacts(), 1u);
        EXPECT_NEAR(s.contacts()[0].normal.dot(n), 1.0, 1e-9);
        EXPECT_NEAR((s.positions()[0] - (Vec3(0, 0, 0.5) + r * n)).norm(), 0.0, 1e-3 * r);
        // the sphere at the end of the box's top edge (a convex vertex)
        System s2(3);
        s2.addMaterial({2500, 0.5});
        s2.addTriangulatedSurface(v, t);
        const Vec3 n2 = Vec3(1, 1, -1).normalized();
        s2.addGrain(r * n2, r, m);
        s2.setGravity(-g0 * n2);
        for (int k = 0; k < 200; ++k) s2.step(1e-4);
        ASSERT_EQ(s2.nContacts(), 1u);
        EXPECT_NEAR(s2.contacts()[0].normal.dot(n2), 1.0, 1e-9);
        EXPECT_NEAR((s2.positions()[0] - r * n2).norm(), 0.0, 1e-3 * r);
    }
    {
        System s(2);
        const int m = s.addMaterial({2500, 0.5});
        s.addSegment(Vec3(-1, 0, 0), Vec3(0, 0, 0));
        s.addSegment(Vec3(0, 0, 0), Vec3(0, -1, 0));
        const Vec3 n = Vec3(1, 1, 0).normalized();
        s.addGrain(r * n, r, m);
        s.setGravity(-g0 * n);
        for (int k = 0; k < 200; ++k) s.step(1e-4);
        ASSERT_EQ(s.nContacts(), 1u);
        EXPECT_NEAR(s.contacts()[0].normal.dot(n), 1.0, 1e-9);
        EXPECT_NEAR((s.positions()[0] - r * n).norm(), 0.0, 1e-3 * r);
    }
}

// Fixed grains never contact walls or other fixed grains (a rough floor of
// fixed grains may cut a wall or a gate plane), and checkInitialOverlaps does
// not report such pairs; a free grain overlapping them is still reported.
TEST(WallEdges, FixedGrainsIgnoreWallsAndEachOther)
{
    const double r = 0.01;
    {
        System s(2);
        const int m = s.addMaterial({2500, 0.3});
        s.addGrain(Vec3(0, 0, 0), r, m, true);       // cut by the plane and the segment
        s.addGrain(Vec3(1.5 * r, 0, 0), r, m, true); // overlaps grain 0
        s.addPlane(Vec3(0, 0.5 * r, 0), Vec3(0, 1, 0));
        s.addSegment(Vec3(-1, 0, 0), Vec3(1, 0, 0));
        s.setGravity(Vec3(0, -g0, 0));
        EXPECT_NO_THROW(s.checkInitialOverlaps());
        s.step(1e-4);
        EXPECT_EQ(s.nContacts(), 0u);
        EXPECT_EQ(s.positions()[0], Vec3(0, 0, 0));
        s.addGrain(Vec3(0, 1.2 * r, 0), r, m); // free grain: overlaps plane and grain 0
        try
        {
            s.checkInitialOverlaps();
            FAIL() << "free grain overlap not reported";
        }
        catch (const InputError& e)
        {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("grains 0 and 2"), std::string::npos) << msg;
            EXPECT_NE(msg.find("grain 2 and wall 0"), std::string::npos) << msg;
            EXPECT_EQ(msg.find("grains 0 and 1"), std::string::npos) << msg;
            EXPECT_EQ(msg.find("grain 0 and wall"), std::string::npos) << msg;
            EXPECT_EQ(msg.find("grain 1 and wall"), std::string::npos) << msg;
        }
    }
    {
        System s(3);
        const int m = s.addMaterial({2500, 0.3});
        s.addGrain(Vec3(0.5, 0, 0.5), r, m, true);
        s.addGrain(Vec3(0.5 + r, 0, 0.5), r, m, true);
        addTriangulatedFloor(s, 1.0, 1.0, 4, 4);
        s.addPlane(Vec3(0, 0, 0.5), Vec3(0, 0, 1));
        EXPECT_NO_THROW(s.checkInitialOverlaps());
        s.setGravity(Vec3(0, -g0, 0));
        s.step(1e-4);
        EXPECT_EQ(s.nContacts(), 0u);
    }
}

// Per-wall friction: a frictionless incline under a frictional grain; the
// setting survives an HDF5 round trip; negative restores the grain's friction.
TEST(WallEdges, WallFriction)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    const double r = 0.01;
    s.addGrain(Vec3(0, r, 0), r, m);
    s.setRotationLocked(0);
    const int w = s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    EXPECT_LT(s.wallFriction(w), 0);
    s.setWallFriction(w, 0.0);
    EXPECT_THROW(s.setWallFriction(5, 0.1), InputError);
    s.setGravity(g0 * Vec3(std::sin(theta), -std::cos(theta), 0));
    for (int k = 0; k < 1000; ++k) s.step(1e-4);
    EXPECT_NEAR(s.velocities()[0].x(), g0 * std::sin(theta) * 0.1, 1e-6);
    s.writeHDF5("wallFriction.h5");
    System t = System::readHDF5("wallFriction.h5");
    EXPECT_EQ(t.wallFriction(w), 0.0);
    t.setWallFriction(w, -3);
    EXPECT_LT(t.wallFriction(w), 0);
    for (int k = 0; k < 1000; ++k) t.step(1e-4); // tan 30 > 0.4: slides with the grain's mu
    const double a = g0 * (std::sin(theta) - 0.4 * std::cos(theta));
    EXPECT_NEAR(t.velocities()[0].x(), g0 * std::sin(theta) * 0.1 + a * 0.1, 1e-6);
    std::remove("wallFriction.h5");
}

// setContactImpulses seeds the warm start: a copy of a resting column given
// the contact impulses of the original needs about one sweep (each contact
// found converged), a cold copy rebuilds the forces from zero; bad input is
// rejected.
TEST(WarmStart, SetContactImpulsesSeedsACopy)
{
    auto column = [](System& s)
    {
        const int m = s.addMaterial({2500, 0.4});
        for (int k = 0; k < 30; ++k) s.addGrain(Vec3(0, 0.01 * (2 * k + 1), 0), 0.01, m);
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.setGravity(Vec3(0, -g0, 0));
    };
    System a(2);
    column(a);
    for (int k = 0; k < 200; ++k) a.step(1e-4);
    System warm(2), cold(2);
    column(warm);
    column(cold);
    warm.positions() = cold.positions() = a.positions();
    auto views = a.contacts();
    std::swap(views[3].i, views[3].j); // either way round for grain pairs
    views[3].normal = -views[3].normal;
    views[3].impulse = -views[3].impulse;
    warm.setContactImpulses(views, 1e-4);
    const StepReport rw = warm.step(1e-4), rc = cold.step(1e-4);
    EXPECT_LE(rw.localSolves, long(2 * rw.contacts)); // the seeded impulses are the solution
    EXPECT_GT(rc.localSolves, 2 * rw.localSolves);
    double fa = 0, fw = 0;
    for (const auto& c : a.contacts())
        if (c.j == -1) fa = c.impulse.y();
    for (const auto& c : warm.contacts())
        if (c.j == -1) fw = c.impulse.y();
    EXPECT_NEAR(fw, fa, 1e-3 * fa);
    std::vector<System::ContactView> bad(1, views[0]);
    bad[0].j = -5;
    EXPECT_THROW(warm.setContactImpulses(bad, 1e-4), InputError);
    EXPECT_THROW(warm.setContactImpulses(views, 0.0), InputError);
}

// setMaterial scales the warm start of a packing at rest by the density
// ratio: the contact forces of a column under gravity alone are its weights
// (statics: the floor holds the whole column, m g dt per step), so after
// halving the density the first step needs about one sweep, its floor
// impulse is half the old one, and nothing moves. Without the scaling the
// step rebuilds the column's forces from twice their value.
TEST(WarmStart, SetMaterialScalesTheImpulsesOfARestingColumn)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    const int n = 30;
    const double r = 0.01, dt = 1e-4;
    for (int k = 0; k < n; ++k) s.addGrain(Vec3(0, r * (2 * k + 1), 0), r, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -g0, 0));
    for (int k = 0; k < 2000; ++k) s.step(dt);
    const auto floorImpulse = [&s]
    {
        for (const auto& c : s.contacts())
            if (c.j == -1) return c.impulse.y();
        return 0.0;
    };
    // statics, up to the solver's penetration correction (measured 1.9 %)
    const double before = floorImpulse();
    EXPECT_NEAR(before, n * 2500 * M_PI * r * r * g0 * dt, 0.03 * n * 2500 * M_PI * r * r * g0 * dt);
    const auto x0 = s.positions();
    s.setMaterial(m, {1250, 0.4});
    const StepReport rep = s.step(dt);
    EXPECT_LE(rep.localSolves, long(2 * rep.contacts));       // the warm start is the solution
    EXPECT_NEAR(floorImpulse(), 0.5 * before, 1e-3 * before); // half the weight
    for (int k = 0; k < n; ++k) EXPECT_NEAR(s.positions()[k].y(), x0[k].y(), 1e-5 * r);
}
