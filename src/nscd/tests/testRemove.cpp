// SPDX-License-Identifier: GPL-3.0-or-later
// System::removeGrains (grains leaving through outlets):
// per-grain state, contact records and warm start after a removal, ids.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace nscd;

namespace
{
constexpr double r = 0.005, g = 9.81, rho = 2500, dt = 1e-3;

/// Stack of three touching discs on the floor y = 0 (x = 0), preceded by
/// `extra` isolated discs resting on the floor at x = 1, 2, ... (indices
/// 0 ... extra-1): they touch only the floor.
System stack(int extra)
{
    System s(2);
    const int m = s.addMaterial({rho, 0.4});
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    for (int k = 0; k < extra; ++k) s.addGrain(Vec3(1.0 + k, r, 0), r, m);
    for (int k = 0; k < 3; ++k) s.addGrain(Vec3(0, r + 2 * r * k, 0), r, m);
    s.setGravity(Vec3(0, -g, 0));
    return s;
}

double weight() { return rho * 3.14159265358979323846 * r * r * g; } // N per metre of depth
} // namespace

// The isolated disc 0 is removed after 20 steps: the stack (renumbered 0-2,
// the floor contacts renumbered from wall body 4 to 3) must continue exactly
// as a stack that never had it (equivalence: the removed disc touched only the
// floor), and its contact impulses are the statics of the stack
// (independent reference: floor carries 3 mg dt, the contacts above 2 mg dt and mg dt).
TEST(RemoveGrains, StackContinuesAsWithoutTheRemovedGrain)
{
    System a = stack(1), ref = stack(0);
    for (int k = 0; k < 20; ++k)
    {
        a.step(dt);
        ref.step(dt);
    }
    ASSERT_EQ(a.nContacts(), 4u); // isolated-floor, floor-0, 0-1, 1-2
    const std::vector<std::size_t> removed = a.removeGrains({0});
    ASSERT_EQ(removed, std::vector<std::size_t>{0});
    ASSERT_EQ(a.size(), 3u);
    EXPECT_EQ(a.grainIds(), (std::vector<long>{1, 2, 3}));

    const auto ca = a.contacts(), cr = ref.contacts();
    ASSERT_EQ(ca.size(), cr.size());
    for (std::size_t k = 0; k < ca.size(); ++k)
    {
        EXPECT_EQ(ca[k].i, cr[k].i);
        EXPECT_EQ(ca[k].j, cr[k].j);
        EXPECT_EQ(ca[k].impulse, cr[k].impulse);
        EXPECT_EQ(ca[k].age, cr[k].age);
    }
    // statics of the stack: the floor pushes grain 0 up by the weight of the
    // three grains (times dt); grain j pushes grain i < j down by the weight
    // of grains j and above (0.1 %: 20 steps of settling)
    for (const auto& c : ca)
    {
        const double carried = (c.j < 0 ? 3 : -(3 - c.j)) * weight() * dt;
        EXPECT_NEAR(c.impulse.y(), carried, 1e-3 * std::abs(carried)) << c.i << " " << c.j;
    }

    // warm start: the next steps take the same sweeps and give the same state
    for (int k = 0; k < 5; ++k)
    {
        const StepReport ra = a.step(dt), rr = ref.step(dt);
        EXPECT_EQ(ra.sweeps, rr.sweeps);
        EXPECT_EQ(ra.contacts, rr.contacts);
    }
    for (std::size_t i = 0; i < 3; ++i)
    {
        EXPECT_EQ(a.positions()[i], ref.positions()[i]);
        EXPECT_EQ(a.velocities()[i], ref.velocities()[i]);
    }
}

// Removing the middle disc of the stack drops every contact it had; the
// remaining records keep their impulses (bottom disc on the floor) and the
// top disc (index 2 -> 1) loses its support: it falls freely in the next step.
TEST(RemoveGrains, DropsTheContactsOfRemovedGrains)
{
    System s = stack(0);
    for (int k = 0; k < 20; ++k) s.step(dt);
    ASSERT_EQ(s.nContacts(), 3u);
    double floorImpulse = 0;
    for (const auto& c : s.contacts())
        if (c.j == -1) floorImpulse = c.impulse.y();
    s.removeGrains({1});
    ASSERT_EQ(s.size(), 2u);
    const auto c = s.contacts();
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].i, 0);
    EXPECT_EQ(c[0].j, -1); // wall 0
    EXPECT_EQ(c[0].impulse.y(), floorImpulse);
    const double v0 = s.velocities()[1].y();
    s.step(dt);
    // free fall of the top disc over one step (no contact within reach of the
    // gap 2r): v = v0 - g dt (analytical)
    EXPECT_NEAR(s.velocities()[1].y(), v0 - g * dt, 1e-12);
}

TEST(RemoveGrains, IdsAreNeverReusedAndSurviveTheState)
{
    System s = stack(2); // ids 0 ... 4
    s.removeGrains({4, 0});
    EXPECT_EQ(s.grainIds(), (std::vector<long>{1, 2, 3}));
    const int m = 0;
    EXPECT_EQ(s.addGrain(Vec3(5, r, 0), r, m), 3); // index 3 ...
    EXPECT_EQ(s.grainIds().back(), 5);             // ... id 5, not 4 nor 0

    const std::string file = ::testing::TempDir() + "nscdRemoveIds.h5";
    s.writeHDF5(file);
    System t = System::readHDF5(file);
    std::remove(file.c_str());
    EXPECT_EQ(t.grainIds(), (std::vector<long>{1, 2, 3, 5}));
    t.addGrain(Vec3(6, r, 0), r, m);
    EXPECT_EQ(t.grainIds().back(), 6);
}

TEST(RemoveGrains, BadIndicesThrowAndLeaveTheSystemUnchanged)
{
    System s = stack(0);
    EXPECT_THROW(s.removeGrains({3}), InputError);
    EXPECT_THROW(s.removeGrains({1, 1}), InputError);
    EXPECT_EQ(s.size(), 3u);
    EXPECT_TRUE(s.removeGrains({}).empty());
    EXPECT_EQ(s.size(), 3u);
}
