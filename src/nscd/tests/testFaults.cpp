// SPDX-License-Identifier: GPL-3.0-or-later
// advance() faults: the sub-step cap and the heartbeat.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace nscd;

namespace
{
/// One disc of diameter 0.01 m falling freely under g = 10 m/s^2.
System fallingDisc()
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    s.addGrain(Vec3(0, 0, 0), 0.005, m);
    s.setGravity(Vec3(0, -10, 0));
    return s;
}
} // namespace

// Sub-steps: ceil(|v + g dt| dt / (f d)) (thesis 5.1.3); dt = 0.1 s, f = 0.1,
// d = 0.01 m: 1 m/s x 0.1 s / 0.001 m = 100 sub-steps, independent of the code.
TEST(AdvanceFaults, SubStepCapThrowsBeforeMovingAnyGrain)
{
    System s = fallingDisc();
    s.settings().maxSubSteps = 99;
    try
    {
        s.advance(0.1, 0.1);
        FAIL() << "expected StepError";
    }
    catch (const StepError& e)
    {
        const std::string w = e.what();
        EXPECT_NE(w.find("maxSubSteps = 99"), std::string::npos) << w;
        EXPECT_NE(w.find("grain 0"), std::string::npos) << w;
        EXPECT_NE(w.find("about 100 sub-steps"), std::string::npos) << w;
    }
    EXPECT_EQ(s.positions()[0], Vec3(0, 0, 0)); // state unchanged
    EXPECT_EQ(s.time(), 0.0);

    s.settings().maxSubSteps = 100;
    const StepReport r = s.advance(0.1, 0.1);
    EXPECT_EQ(r.substeps, 100);
    // free fall: y = -g t^2/2 up to the sub-stepping's O(dt) integration error
    EXPECT_NEAR(s.positions()[0].y(), -0.05, 0.05 * 0.02);
}

TEST(AdvanceFaults, NonFiniteForceThrows)
{
    System s = fallingDisc();
    s.setExternalForce(0, Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0), Vec3::Zero());
    EXPECT_THROW(s.advance(1e-3, 0.1), StepError);
    EXPECT_EQ(s.positions()[0], Vec3(0, 0, 0));
}

TEST(AdvanceFaults, BadMaxSubStepsIsAnInputError)
{
    System s = fallingDisc();
    s.settings().maxSubSteps = 0;
    EXPECT_THROW(s.advance(1e-3, 0.1), InputError);
}

TEST(AdvanceFaults, HeartbeatReportsProgress)
{
    System s = fallingDisc();
    std::vector<std::pair<long, double>> beats;
    s.settings().heartbeatSeconds = 0; // every sub-step
    s.settings().heartbeat = [&beats](long done, double all) { beats.emplace_back(done, all); };
    s.advance(0.1, 0.1);
    ASSERT_EQ(beats.size(), 99u); // after each sub-step but the last
    EXPECT_EQ(beats.front().first, 1);
    EXPECT_EQ(beats.back().first, 99);
    for (const auto& b : beats) EXPECT_GE(b.second, double(b.first));
    EXPECT_NEAR(beats.front().second, 100, 1);
}

// 4,314 discs of 55 um poured from a loose lattice into a column ten grains
// wide whose side walls are frictionless (docs/validation/dropletDigging.md,
// "Measured, building the Table 4.2 bed"). Around step 212 (t = 0.042 s)
// the whole column comes to rest on the floor at once and the solves stop
// at the sweep cap for several sub-steps; the overlaps they leave (up to
// 1 % of d) were pushed back at (gap + slop)/dt as real velocity, which
// summed over the ~370 layers launched the column upwards: a grain at
// 7.8 m/s left through a side wall (with friction on the walls the column
// came to rest). Conservation check, not a re-derivation: no grain may be
// faster than the free fall from the top of the lattice (energy bound), and
// none may leave. Fixed by the relax stage (System::Impl::relaxPushOut).
// The first 260 steps hold the event (about 1 min of CPU).
TEST(AdvanceFaults, FrictionlessSideWallsKeepAPouredColumnInside)
{
    const double d = 55e-6, w = 10e-3 / 18, H = 0.0364, dt = 2e-4;
    System s(2);
    const int m = s.addMaterial({3200, 0.3});
    s.settings().tolerance = 1e-3;
    s.settings().maxIterations = 1000;
    std::mt19937_64 rng(8);
    std::uniform_real_distribution<double> u(0, 1);
    const double sp = 1.1 * d;
    int n = 0;
    for (int j = 0; n < 4314; ++j)
        for (int i = 0; i < int(w / sp) && n < 4314; ++i, ++n)
        {
            const double dd = 0.9 * d + 0.1 * d * u(rng);
            s.addGrain(Vec3((i + 0.5) * sp + 0.04 * d * (2 * u(rng) - 1),
                            (j + 0.5) * sp + 0.04 * d * (2 * u(rng) - 1), 0),
                       dd / 2, m);
        }
    s.addSegment(Vec3(0, 0, 0), Vec3(w, 0, 0));
    s.setWallFriction(s.addSegment(Vec3(0, 0, 0), Vec3(0, H, 0)), 0.0);
    s.setWallFriction(s.addSegment(Vec3(w, 0, 0), Vec3(w, H, 0)), 0.0);
    s.setGravity(Vec3(0, -9.81, 0));
    for (int k = 0; k < 260; ++k)
    {
        s.advance(dt, 0.1);
        double vmax = 0;
        for (const Vec3& v : s.velocities()) vmax = std::max(vmax, v.norm());
        // free fall from the top of the lattice: sqrt(2 g H) = 0.85 m/s
        ASSERT_LT(vmax, 1.0) << "step " << k + 1;
    }
    for (const Vec3& x : s.positions()) EXPECT_TRUE(x.x() > 0 && x.x() < w);
}
