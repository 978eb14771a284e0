// SPDX-License-Identifier: GPL-3.0-or-later
// Contact solver methods (System::Settings::Method: NLGS, OverRelaxedNLGS,
// APGD) on problems with an independent reference, and the stopping test.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <unistd.h>

using namespace nscd;

namespace
{
constexpr double pi = 3.14159265358979323846;
constexpr double g0 = 9.81;
using Method = System::Settings::Method;
const Method methods[] = {Method::NLGS, Method::OverRelaxedNLGS, Method::APGD, Method::NNCG};
std::string name(Method m)
{
    return m == Method::NLGS   ? "NLGS"
           : m == Method::APGD ? "APGD"
           : m == Method::NNCG ? "NNCG"
                               : "OverRelaxedNLGS";
}
} // namespace

// Reference: statics (Newton's third law over a step). A grain resting on a
// plane receives the normal impulse m g dt, a column of n discs on a floor
// the floor impulse n m g dt (equilibrium of the column), 2D and 3D.
TEST(ContactSolver, RestingGrainAndColumnCarryTheirWeight)
{
    for (Method meth : methods)
        for (int dim : {2, 3})
            for (int n : {1, 8})
            {
                System s(dim);
                const int m = s.addMaterial({2500, 0.4});
                const double r = 0.005, dt = 1e-3;
                for (int k = 0; k < n; ++k) s.addGrain(Vec3(0, r * (2 * k + 1), 0), r, m);
                s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
                s.setGravity(Vec3(0, -g0, 0));
                s.settings().tolerance = 1e-9;
                s.settings().method = meth;
                s.settings().maxIterations = 100000;
                for (int k = 0; k < 200; ++k)
                {
                    const StepReport rep = s.step(dt);
                    EXPECT_TRUE(rep.converged) << name(meth);
                    EXPECT_EQ(rep.method, int(meth));
                    EXPECT_LT(rep.maxOverlap, 1e-3 * r);
                }
                double floor = 0;
                for (const auto& c : s.contacts())
                    if (c.j < 0) floor = c.impulse.y();
                const double w = n * s.mass(0) * g0 * dt;
                EXPECT_NEAR(floor, w, 1e-5 * w) << name(meth) << " dim " << dim << " n " << n;
                EXPECT_LT(s.velocities()[n - 1].norm(), 1e-6) << name(meth);
            }
}

// Reference: block (rotation-locked disc/sphere) on an incline: at rest if
// tan a < mu, else sliding with a = g (sin a - mu cos a) (Coulomb). 1 % on a;
// velocities within the solver tolerance (tolerance d_min/dt).
TEST(ContactSolver, InclineStickAndSlide)
{
    for (Method meth : methods)
        for (int dim : {2, 3})
            for (double deg : {20.0, 30.0})
            {
                const double mu = deg < 25 ? 0.5 : 0.3, th = deg * pi / 180, T = 0.5, dt = 1e-3;
                System s(dim);
                const int m = s.addMaterial({2500, mu});
                const double r = 0.01;
                s.addGrain(Vec3(0, r, 0), r, m);
                s.setRotationLocked(0);
                s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
                s.setGravity(Vec3(g0 * std::sin(th), -g0 * std::cos(th), 0));
                s.settings().method = meth;
                for (int k = 0; k < int(std::lround(T / dt)); ++k)
                {
                    const StepReport rep = s.step(dt);
                    EXPECT_TRUE(rep.converged) << name(meth);
                    EXPECT_LT(rep.maxOverlap, 1e-3 * r);
                }
                const double v = s.velocities()[0].x();
                // velocity error allowed by the stopping test: tolerance d_min / dt
                const double vTol = s.settings().tolerance * 2 * r / dt;
                if (deg < 25)
                    EXPECT_LT(std::abs(v), vTol) << name(meth) << " dim " << dim;
                else
                {
                    const double a = g0 * (std::sin(th) - mu * std::cos(th));
                    EXPECT_NEAR(v, a * T, 0.01 * a * T) << name(meth) << " dim " << dim;
                    EXPECT_LT(std::abs(s.velocities()[0].y()), vTol) << "no lift-off while sliding";
                }
            }
}

// The stopping test is comparable across tolerances and methods: from the
// same state (a 2D pile of 300 discs falling into a box, saved), one step
// with a tighter tolerance never ends with a larger residual than a looser
// one, and every converged step has residual <= tolerance. Consistency check
// of the solver's own residual (no external reference).
TEST(ContactSolver, ResidualMonotoneInTolerance)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    for (int k = 0; k < 300; ++k)
        s.addGrain(Vec3(1.1e-3 + 2.2e-3 * (k % 15) + 2e-4 * ((k / 15) % 2), 1.1e-3 + 2.05e-3 * (k / 15), 0),
                   1e-3 * (0.9 + 0.2 * ((k * 37) % 11) / 10.0), m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
    s.addPlane(Vec3(0.034, 0, 0), Vec3(-1, 0, 0));
    s.setGravity(Vec3(0, -g0, 0));
    for (int k = 0; k < 150; ++k) s.step(2e-4);
    const std::string file = "testContactSolver_" + std::to_string(::getpid()) + ".h5";
    s.writeHDF5(file);
    for (Method meth : methods)
    {
        double prev = 1e300;
        for (double tol : {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8})
        {
            System t = System::readHDF5(file);
            t.settings().method = meth;
            t.settings().tolerance = tol;
            t.settings().maxIterations = 100000;
            t.settings().residualHistory = true;
            const StepReport rep = t.step(2e-4);
            EXPECT_TRUE(rep.converged) << name(meth) << " tol " << tol;
            EXPECT_LE(rep.residual, tol) << name(meth);
            EXPECT_LE(rep.residual, prev) << name(meth) << " tol " << tol;
            prev = rep.residual;
            ASSERT_GE(rep.residualHistory.size(), 2u);
            EXPECT_EQ(rep.residualHistory.back(), rep.residual);
            std::printf("%s tol %.0e: residual %.3e, %d sweeps, history %zu\n", name(meth).c_str(), tol,
                        rep.residual, rep.sweeps, rep.residualHistory.size());
        }
    }
    std::remove(file.c_str());
}

// Bad input: an unknown method is an InputError, not a silent default.
TEST(ContactSolver, UnknownMethodThrows)
{
    System s(2);
    s.settings().method = static_cast<Method>(7);
    EXPECT_THROW(s.step(1e-3), InputError);
}
