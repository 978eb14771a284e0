// SPDX-License-Identifier: GPL-3.0-or-later
// The relax stage of System::step (split impulse: E. Catto, GDC 2006; the
// relax of Box2D v3's soft step; src/nscd/README.md "Relax stage"): an
// overlap deeper than the slop band (Settings::overlapSlop) is pushed back
// by the positions only, then the rows are solved again without the push.
// After a converged first solve only the push-out rows are queued for that
// second solve (every other row is converged at the same velocities).
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <algorithm>

using namespace nscd;

namespace
{
const double g0 = 9.81;
}

// A column of 10 discs at rest on a floor (default tolerance 1e-6 d_min and
// slop 1e-4 r_min): no overlap leaves the band, so no step runs the relax
// stage's second solve, and the overlaps stay below the slop.
TEST(RelaxStage, ColumnAtRestRunsNoSecondSolve)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    const double r = 1e-3;
    for (int k = 0; k < 10; ++k) s.addGrain(Vec3(0, r * (2 * k + 1), 0), r, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -g0, 0));
    const double slop = s.settings().overlapSlop * r;
    for (int k = 0; k < 100; ++k) s.step(1e-4); // the contacts load
    for (int k = 0; k < 200; ++k)
    {
        const StepReport rep = s.step(1e-4);
        EXPECT_TRUE(rep.converged);
        EXPECT_EQ(rep.relaxSolves, 0) << "step " << k;
        EXPECT_EQ(rep.relaxLocalSolves, 0) << "step " << k;
        EXPECT_LT(rep.maxOverlap, slop) << "step " << k;
    }
}

// 50 discs side by side on a floor, apart from each other, one of them
// 5 slop deep in it: the relax stage runs once, its second solve re-solves
// that disc's floor row alone (not the 50 rows), the disc ends at the band
// edge (5 slop -> 1 slop within the tolerance) without the push-out
// velocity, and the other discs are not moved.
TEST(RelaxStage, SecondSolveQueuesOnlyThePushOutRows)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    const double r = 1e-3, dt = 1e-4;
    const double slop = s.settings().overlapSlop * r;
    for (int k = 0; k < 50; ++k) s.addGrain(Vec3(3 * r * k, r - (k == 7 ? 5 * slop : 0.0), 0), r, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -g0, 0));
    const StepReport rep = s.step(dt);
    ASSERT_EQ(rep.contacts, 50);
    EXPECT_TRUE(rep.converged);
    EXPECT_EQ(rep.relaxSolves, 1);
    EXPECT_GE(rep.relaxLocalSolves, 1);
    EXPECT_LE(rep.relaxLocalSolves, 2);
    const double xi = s.settings().tolerance * 2 * r;
    EXPECT_NEAR(s.positions()[7].y(), r - slop, xi);  // pushed back to the band edge
    EXPECT_NEAR(s.velocities()[7].y(), 0.0, xi / dt); // without the push-out velocity
    for (int k = 0; k < 50; ++k)
        if (k != 7) EXPECT_NEAR(s.positions()[k].y(), r, 1e-15) << "disc " << k;
}
