// SPDX-License-Identifier: GPL-3.0-or-later
// Settings::FrictionLaw::Anitescu, the convex relaxation of Coulomb's cone
// (src/ContactLaws.H, AnitescuCone; M. Anitescu, Math. Program. 105:113-143,
// 2006): the local projection against a brute-force minimisation, and the
// grain-scale mechanics against Coulomb's law and the cone's dual.
#include "ContactLaws.H"
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

using namespace nscd;

namespace
{
constexpr double pi = 3.14159265358979323846;
constexpr double g0 = 9.81;

/// The weighted distance of (x, s) to (x0, s0) in the metric diag(1/iwnn, 1/iwtt).
double cost(double x, double s, double x0, double s0, double iwnn, double iwtt)
{
    return (x - x0) * (x - x0) / iwnn + (s - s0) * (s - s0) / iwtt;
}
} // namespace

// Reference: the minimiser of the weighted distance over the cone s <= mu x,
// x >= 0 found by brute force (the cone's side s = mu x sampled finely, the
// interior only when the point is in it, the apex), independent of the
// closed form. Metric ratios 1/3 (a 2D disc with rotation: W_tt = 3 W_nn)
// to 10, points in the cone, in its polar cone and between.
TEST(FrictionLawAnitescu, ProjectionIsTheWeightedNearestPointOfTheCone)
{
    for (double mu : {0.1, 0.5, 1.2})
        for (double ratio : {1.0 / 3.0, 1.0, 10.0})
            for (double x0 : {-2.0, -0.3, 0.0, 0.4, 1.0, 3.0})
                for (double s0 : {0.0, 0.2, 1.0, 5.0})
                {
                    const double iwnn = 1.0, iwtt = ratio; // iwtt/iwnn = W_nn/W_tt
                    double x = x0, s = s0;
                    law::AnitescuCone::project(x, s, mu, iwnn, iwtt);
                    // brute force over the cone's side and apex
                    double best = std::numeric_limits<double>::max(), bx = 0, bs = 0;
                    if (s0 <= mu * x0)
                    {
                        best = 0;
                        bx = x0;
                        bs = s0;
                    }
                    const int n = 200000;
                    const double xMax = 10.0;
                    for (int k = 0; k <= n && best > 0; ++k)
                    {
                        const double xc = xMax * k / n;
                        const double c = cost(xc, mu * xc, x0, s0, iwnn, iwtt);
                        if (c < best)
                        {
                            best = c;
                            bx = xc;
                            bs = mu * xc;
                        }
                    }
                    const double tol = 2e-4;
                    EXPECT_NEAR(x, bx, tol)
                        << "mu " << mu << " ratio " << ratio << " at (" << x0 << ", " << s0 << ")";
                    EXPECT_NEAR(s, bs, tol)
                        << "mu " << mu << " ratio " << ratio << " at (" << x0 << ", " << s0 << ")";
                    EXPECT_LE(s, mu * x + 1e-12);
                    EXPECT_GE(x, 0.0);
                }
}

namespace
{
/// slide(): down-slope and normal velocity at T, largest gap to the plane of
/// a grainOnPlane at rest, stepped by dt = 1e-3 s for T.
struct SlideResult
{
    double v, vn, maxGap;
};

constexpr double r = 0.01; // grain radius [m]

/// A rotation-locked grain of radius r resting on the plane y = 0 with
/// velocity (v0, 0, 0), friction mu, law `law`, gravity tilted by theta [deg].
System grainOnPlane(int dim, double mu, System::Settings::FrictionLaw law, double thetaDeg, double v0)
{
    System s(dim);
    const int m = s.addMaterial({2500, mu});
    s.addGrain(Vec3(0, r, 0), r, m);
    s.setRotationLocked(0);
    s.velocities()[0] = Vec3(v0, 0, 0);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.settings().frictionLaw = law;
    const double th = thetaDeg * pi / 180;
    s.setGravity(Vec3(g0 * std::sin(th), -g0 * std::cos(th), 0));
    return s;
}

SlideResult slide(int dim, double thetaDeg, double mu, System::Settings::FrictionLaw law, double T)
{
    System s = grainOnPlane(dim, mu, law, thetaDeg, 0.0);
    const double dt = 1e-3;
    const int n = int(std::lround(T / dt));
    double maxGap = 0;
    for (int k = 0; k < n; ++k)
    {
        const StepReport rep = s.step(dt);
        EXPECT_TRUE(rep.converged);
        maxGap = std::max(maxGap, s.positions()[0].y() - r);
    }
    return {s.velocities()[0].x(), s.velocities()[0].y(), maxGap};
}
} // namespace

// Reference: Coulomb's law on an incline, rotation locked: at rest if
// tan theta < mu (a sticking contact is the same in both laws, exactly), and
// a = g (sin theta - mu cos theta) when sliding. The convex law lifts a
// sliding grain at mu |u_t| and it hops (below), but every impulse of its
// sliding contact is on the cone, |r_t| = mu r_n, so the momentum balance
// over [0, T] is Coulomb's with the normal impulse the weight's plus the
// grain's normal momentum at T: v_t(T) = a T - mu v_n(T), to the solver's
// velocity tolerance (tolerance d_min / dt: a local solve within it keeps
// the previous impulse).
TEST(FrictionLawAnitescu, InclineSticksAndSlidesWithCoulombsImpulse)
{
    using Law = System::Settings::FrictionLaw;
    for (int dim : {2, 3})
    {
        const SlideResult st = slide(dim, 20, 0.5, Law::Anitescu, 0.5);
        EXPECT_LT(std::abs(st.v), 1e-8) << "dim " << dim;
        EXPECT_LT(st.maxGap, 1e-9);
        const double th = 30 * pi / 180, mu = 0.3, T = 1.0;
        const double a = g0 * (std::sin(th) - mu * std::cos(th));
        const SlideResult sl = slide(dim, 30, mu, Law::Anitescu, T);
        const double tolV = System::Settings{}.tolerance * 2 * r / 1e-3;
        EXPECT_NEAR(sl.v, a * T - mu * sl.vn, tolV) << "dim " << dim;
        EXPECT_GT(sl.maxGap, 0.0); // it hops
        const SlideResult co = slide(dim, 30, mu, Law::Coulomb, T);
        EXPECT_NEAR(co.v, a * T, 0.01 * a * T) << "dim " << dim;
        EXPECT_LT(co.maxGap, 1e-9);
    }
}

// Reference: the cone's dual (Anitescu 2006): a sliding contact ends the
// step at u_n = mu |u_t|, so a grain launched at v0 along a level floor
// leaves it at mu |v| after its first step and rises, ballistically, to
// (mu v)^2 / (2 g) (the hop this law adds to a sliding grain; it vanishes
// with mu |u_t| and is why the law suits flows whose sliding speeds are
// small next to sqrt(g d)). Consistency check of the law's known artefact.
TEST(FrictionLawAnitescu, SlidingGrainLiftsAtTheConesDual)
{
    using Law = System::Settings::FrictionLaw;
    const double mu = 0.3, v0 = 0.5;
    System s = grainOnPlane(2, mu, Law::Anitescu, 0.0, v0);
    const double dt = 1e-4;
    s.step(dt);
    const Vec3 v = s.velocities()[0];
    EXPECT_NEAR(v.y(), mu * v.x(), 1e-9);
    double top = 0;
    for (int k = 0; k < 2000; ++k)
    {
        s.step(dt);
        top = std::max(top, s.positions()[0].y() - r);
    }
    const double hop = (mu * v.x()) * (mu * v.x()) / (2 * g0);
    EXPECT_NEAR(top, hop, 0.02 * hop);
}

// The setting is refused with APGD, which solves the Coulomb law.
TEST(FrictionLawAnitescu, RefusedWithAPGD)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.5});
    s.addGrain(Vec3(0, 0.01, 0), 0.01, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.settings().frictionLaw = System::Settings::FrictionLaw::Anitescu;
    s.settings().method = System::Settings::Method::APGD;
    EXPECT_THROW(s.step(1e-3), InputError);
}
