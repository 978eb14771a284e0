// advance() faults (issue 27): the sub-step cap and the heartbeat.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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
}

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
    EXPECT_EQ(s.positions()[0], Vec3(0, 0, 0));   // state unchanged
    EXPECT_EQ(s.time(), 0.0);

    s.settings().maxSubSteps = 100;
    const StepReport r = s.advance(0.1, 0.1);
    EXPECT_EQ(r.substeps, 100);
    // free fall: y = -g t^2/2 up to the sub-stepping's O(dt) integration error
    EXPECT_NEAR(s.positions()[0].y(), -0.05, 0.05*0.02);
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
    s.settings().heartbeatSeconds = 0;   // every sub-step
    s.settings().heartbeat = [&beats](long done, double all) { beats.emplace_back(done, all); };
    s.advance(0.1, 0.1);
    ASSERT_EQ(beats.size(), 99u);        // after each sub-step but the last
    EXPECT_EQ(beats.front().first, 1);
    EXPECT_EQ(beats.back().first, 99);
    for (const auto& b : beats) EXPECT_GE(b.second, double(b.first));
    EXPECT_NEAR(beats.front().second, 100, 1);
}
