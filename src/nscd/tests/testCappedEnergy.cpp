// SPDX-License-Identifier: GPL-3.0-or-later
// A contact solve stopped at its cap (Settings::maxIterations) must not
// inject energy: for the dissipative law (inelastic Signorini, Coulomb
// friction, static walls) the kinetic energy after the step may not exceed
// that of the free velocities v + dt F/m (System::Impl::limitCappedEnergy,
// src/Integrate.cpp): without the limit, a warm-started Gauss-Seidel
// stopped at the cap in a deep frictionless column raises it 40-fold in one
// step (docs/validation/dropletDigging.md: why no deep bed of these grains
// comes to rest at tolerance 1e-3).
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace nscd;

namespace
{
const double g0 = 9.81;

double kineticEnergy(const System& s, const std::vector<Vec3>& v)
{
    double e = 0;
    for (std::size_t i = 0; i < s.size(); ++i)
        e += 0.5 * s.mass(i) * v[i].squaredNorm()
             + 0.5 * s.inertia(i) * s.angularVelocities()[i].squaredNorm();
    return e;
}

/// n discs of ~1 mm poured from a loose lattice `wide` discs wide between
/// frictionless side walls (tolerance 1e-3, at most maxIt sweeps per step).
System pouredColumn(int wide, int n, int maxIt, double mu)
{
    const double d = 1e-3, sp = 1.1 * d, W = wide * sp;
    System s(2);
    const int m = s.addMaterial({2500, mu});
    s.settings().tolerance = 1e-3;
    s.settings().maxIterations = maxIt;
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0, 1);
    for (int k = 0; k < n; ++k)
        s.addGrain(Vec3((k % wide + 0.5) * sp + 0.04 * d * (2 * u(rng) - 1), (k / wide + 0.5) * sp, 0),
                   0.5 * d * (0.9 + 0.1 * u(rng)), m);
    s.addSegment(Vec3(0, 0, 0), Vec3(W, 0, 0));
    s.setWallFriction(s.addSegment(Vec3(0, 0, 0), Vec3(0, 1, 0)), 0.0);
    s.setWallFriction(s.addSegment(Vec3(W, 0, 0), Vec3(W, 1, 0)), 0.0);
    s.setGravity(Vec3(0, -g0, 0));
    return s;
}
} // namespace

// Single-file and 10-wide columns landing with 5 sweeps per step at most:
// most solves stop at the cap. Every step: KE_after <= KE_free (1 + 1e-12),
// the kinetic energy in the free velocities v - g dt e_y (no other force,
// so the angular velocities are free ones). Measured before the limiter:
// KE_after/KE_free up to 1.59 (single file, step 187) and 1.39 (10 wide),
// and grains launched out of the column (9.7 and 3.0 m/s after 1,000 steps).
TEST(CappedEnergy, CappedSolveNeverRaisesTheKineticEnergy)
{
    const double dt = 5e-4;
    for (int wide : {1, 10})
    {
        System s = pouredColumn(wide, wide == 1 ? 200 : 1000, 5, 0.3);
        int capped = 0, limited = 0;
        for (int k = 0; k < 400; ++k)
        {
            std::vector<Vec3> vf = s.velocities();
            for (Vec3& v : vf) v.y() -= g0 * dt;
            const double eFree = kineticEnergy(s, vf);
            const StepReport r = s.step(dt);
            const double eAfter = kineticEnergy(s, s.velocities());
            ASSERT_LE(eAfter, eFree * (1 + 1e-12)) << wide << " wide, step " << k;
            capped += !r.converged;
            limited += r.energyLimited;
            if (r.energyLimited == 0)
                EXPECT_EQ(r.impulseScale, 1.0);
            else
            {
                EXPECT_GE(r.impulseScale, 0.0);
                EXPECT_LT(r.impulseScale, 1.0);
                EXPECT_GT(r.energyRaise, 0.0);
            }
        }
        EXPECT_GT(capped, 200) << wide << " wide";
        EXPECT_GT(limited, 0) << wide << " wide";
        // no grain faster than the free fall from the top of the lattice
        double vmax = 0;
        for (const Vec3& v : s.velocities()) vmax = std::max(vmax, v.norm());
        EXPECT_LT(vmax, std::sqrt(2 * g0 * 0.25)) << wide << " wide";
    }
}

// A converged solve is left alone (the limiter acts on capped solves only,
// so converged steps are unchanged to the bit): a 20-disc column landing and
// coming to rest at tolerance 1e-6 reports nothing in its converged steps.
TEST(CappedEnergy, ConvergedStepsAreNotLimited)
{
    System s = pouredColumn(1, 20, 1000, 0.3);
    s.settings().tolerance = 1e-6;
    int converged = 0;
    for (int k = 0; k < 300; ++k)
    {
        const StepReport r = s.step(5e-4);
        if (!r.converged) continue;
        ++converged;
        EXPECT_EQ(r.energyLimited, 0);
        EXPECT_EQ(r.impulseScale, 1.0);
        EXPECT_EQ(r.energyRaise, 0.0);
    }
    EXPECT_GT(converged, 250);
}
