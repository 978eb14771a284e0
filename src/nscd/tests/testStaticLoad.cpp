// SPDX-License-Identifier: GPL-3.0-or-later
// nscd::staticLoad and System::touchingContacts (nscd/StaticLoad.H): the
// frictionless contact forces of grains at rest under gravity, top down,
// checked against the statics of simple assemblies (analytical) and
// against the contact solver (a seeded bed at rest needs no sweeps).
#include "nscd/StaticLoad.H"
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>

using namespace nscd;

namespace
{
const double g0 = 9.81;

/// the contact of (a, b) in c (either way round), or nullptr
const System::ContactView* find(const std::vector<System::ContactView>& c, int a, int b)
{
    for (const auto& v : c)
        if ((v.i == a && v.j == b) || (v.i == b && v.j == a)) return &v;
    return nullptr;
}

/// force [N] (2D: N/m) of contact v along its normal, from its impulse
double force(const System::ContactView& v, double dt) { return v.impulse.dot(v.normal) / dt; }
} // namespace

// A column of 20 discs of different sizes on a floor: the contact under
// disc k carries the weight of discs k..19 (statics of a column).
TEST(StaticLoad, ColumnCarriesTheWeightAbove)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    double y = 0;
    for (int k = 0; k < 20; ++k)
    {
        const double r = 1e-3 * (1 + 0.03 * (k % 4));
        s.addGrain(Vec3(0, y + r, 0), r, m);
        y += 2 * r;
    }
    const int floor = s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -g0, 0));
    const double dt = 1e-4;
    const auto touching = s.touchingContacts(1e-9);
    ASSERT_EQ(touching.size(), 20u);
    const StaticLoad sl = staticLoad(s, touching, dt);
    EXPECT_EQ(sl.unbalanced, 0);
    EXPECT_LT(sl.maxImbalance, 1e-6);
    double above = 0;
    for (int k = 19; k >= 0; --k)
    {
        above += s.mass(k) * g0;
        const System::ContactView* c =
            k > 0 ? find(sl.contacts, k - 1, k) : find(sl.contacts, 0, -(floor + 1));
        ASSERT_NE(c, nullptr) << "contact under disc " << k;
        EXPECT_NEAR(force(*c, dt), above, 1e-6 * above) << "under disc " << k;
    }
}

// Three equal discs between two walls: two on the floor, touching each
// other and a wall each, one on top of them. Statics: each lower disc
// pushes the top one with m g / (2 cos 30 deg) = m g/sqrt(3); each wall
// takes its horizontal part m g/(2 sqrt(3)); the floor takes 3 m g/2 under
// each lower disc; the two lower discs do not press each other.
TEST(StaticLoad, ThreeDiscStackMatchesStatics)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    const double r = 1e-3;
    s.addGrain(Vec3(-r, r, 0), r, m);
    s.addGrain(Vec3(r, r, 0), r, m);
    s.addGrain(Vec3(0, r + std::sqrt(3.0) * r, 0), r, m);
    const int floor = s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    const int left = s.addPlane(Vec3(-2 * r, 0, 0), Vec3(1, 0, 0));
    const int right = s.addPlane(Vec3(2 * r, 0, 0), Vec3(-1, 0, 0));
    s.setGravity(Vec3(0, -g0, 0));
    const double dt = 1e-4, mg = s.mass(0) * g0;
    const StaticLoad sl = staticLoad(s, s.touchingContacts(1e-9), dt);
    EXPECT_EQ(sl.unbalanced, 0);
    ASSERT_EQ(sl.contacts.size(), 7u);
    EXPECT_NEAR(force(*find(sl.contacts, 0, 2), dt), mg / std::sqrt(3.0), 1e-6 * mg);
    EXPECT_NEAR(force(*find(sl.contacts, 1, 2), dt), mg / std::sqrt(3.0), 1e-6 * mg);
    EXPECT_NEAR(force(*find(sl.contacts, 0, -(left + 1)), dt), mg / (2 * std::sqrt(3.0)), 1e-6 * mg);
    EXPECT_NEAR(force(*find(sl.contacts, 1, -(right + 1)), dt), mg / (2 * std::sqrt(3.0)), 1e-6 * mg);
    EXPECT_NEAR(force(*find(sl.contacts, 0, -(floor + 1)), dt), 1.5 * mg, 1e-6 * mg);
    EXPECT_NEAR(force(*find(sl.contacts, 1, -(floor + 1)), dt), 1.5 * mg, 1e-6 * mg);
    EXPECT_NEAR(force(*find(sl.contacts, 0, 1), dt), 0, 1e-6 * mg);
}

// 3D: a sphere on three fixed spheres of the same size in a triangle
// (a regular tetrahedron of centres): each support pushes along its edge,
// at cos(theta) = sqrt(2/3) from the vertical: m g/(3 sqrt(2/3)).
TEST(StaticLoad, SphereOnThreeSpheres)
{
    System s(3);
    const int m = s.addMaterial({2500, 0.4});
    const double r = 1e-3, a = 2 * r, R = a / std::sqrt(3.0);
    for (int k = 0; k < 3; ++k)
    {
        const double t = 2 * M_PI * k / 3;
        s.addGrain(Vec3(R * std::cos(t), 0, R * std::sin(t)), r, m, true);
    }
    s.addGrain(Vec3(0, a * std::sqrt(2.0 / 3.0), 0), r, m);
    s.setGravity(Vec3(0, -g0, 0));
    const double dt = 1e-4, mg = s.mass(3) * g0;
    const StaticLoad sl = staticLoad(s, s.touchingContacts(1e-9), dt);
    EXPECT_EQ(sl.unbalanced, 0);
    for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(force(*find(sl.contacts, k, 3), dt), mg / (3 * std::sqrt(2.0 / 3.0)), 1e-6 * mg);
}

// A hexagonal bed of equal discs between two walls, 20 discs wide and 40
// rows deep: seeded with its static load, the first contact solve at
// tolerance 1e-6 converges at once and the bed stays at rest; from zero
// impulses the same solve needs many sweeps (the weight of 40 rows built
// by Gauss-Seidel) and the bed moves.
TEST(StaticLoad, SeededHexBedStartsAtRest)
{
    const double r = 1e-3, dt = 1e-4;
    auto build = [&](System& s)
    {
        const int m = s.addMaterial({2500, 0.4});
        const int n = 20;
        for (int row = 0; row < 40; ++row)
        {
            const bool odd = row % 2;
            const double y = r + row * std::sqrt(3.0) * r;
            for (int k = 0; k < (odd ? n - 1 : n); ++k)
                s.addGrain(Vec3((odd ? 2 : 1) * r + 2 * r * k, y, 0), r, m);
        }
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
        s.addPlane(Vec3(2 * r * n, 0, 0), Vec3(-1, 0, 0));
        s.setGravity(Vec3(0, -g0, 0));
        s.settings().maxIterations = 100000;
    };
    System seeded(2), cold(2);
    build(seeded);
    build(cold);
    const StaticLoad sl = staticLoad(seeded, seeded.touchingContacts(1e-9 * r), dt);
    EXPECT_EQ(sl.unbalanced, 0);
    // hexagonal: 3 contacts below each disc of a full row's interior ...
    EXPECT_GT(sl.contacts.size(), 2u * seeded.size());
    // global balance: the floor carries the whole weight
    double floorLoad = 0, weight = 0;
    for (const auto& c : sl.contacts)
        if (c.j == -1) floorLoad += force(c, dt) * c.normal.y();
    for (std::size_t i = 0; i < seeded.size(); ++i) weight += seeded.mass(i) * g0;
    EXPECT_NEAR(floorLoad, weight, 1e-6 * weight);

    seeded.setContactImpulses(sl.contacts, dt);
    const StepReport a = seeded.step(dt);
    const StepReport b = cold.step(dt);
    EXPECT_TRUE(a.converged);
    EXPECT_LE(a.sweeps, 2);
    EXPECT_GT(b.sweeps, 20 * std::max(1, a.sweeps));
    double va = 0;
    for (const Vec3& v : seeded.velocities()) va = std::max(va, v.norm());
    EXPECT_LT(va, 1e-3 * g0 * dt);
}

TEST(StaticLoad, Errors)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    s.addGrain(Vec3(0, 1e-3, 0), 1e-3, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    EXPECT_THROW(s.touchingContacts(-1), InputError);
    const auto t = s.touchingContacts(1e-9);
    EXPECT_THROW(staticLoad(s, t, 1e-4), InputError); // no gravity
    s.setGravity(Vec3(0, -g0, 0));
    EXPECT_THROW(staticLoad(s, t, 0), InputError);
    std::vector<System::ContactView> bad = t;
    bad[0].j = -5;
    EXPECT_THROW(staticLoad(s, bad, 1e-4), InputError);
}
