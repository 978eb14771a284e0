// SPDX-License-Identifier: GPL-3.0-or-later
// Implicit fluid drag inside the contact problem (System::setFluidDrag):
// checks against analytical solutions and conservation of momentum.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>

using namespace nscd;

namespace
{
constexpr double g0 = 9.81;
}

// Reference: linear drag ODE m dv/dt = m g + c (u - v), exact solution
// v(t) = v_t + (v_0 - v_t) exp(-c t/m), v_t = u + m g/c. Backward Euler
// (the scheme of eq. 3.46-3.50) is first-order accurate and its steady state
// is v_t exactly, whatever c dt/m.
TEST(FluidDrag, LoneGrainRelaxesToTerminalVelocity)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m = s.addMaterial({2500, 0.3});
        s.addGrain(Vec3(0, 0, 0), 1e-3, m);
        s.setGravity(Vec3(0, -g0, 0));
        const double mass = s.mass(0);
        const double tau = 0.02; // relaxation time m/c [s]
        const double c = mass / tau;
        const Vec3 u(0.05, 0.1, 0);
        const Vec3 vt = u + tau * Vec3(0, -g0, 0);
        // first order in dt: halving dt halves the error at t = tau
        double err[2];
        for (int k = 0; k < 2; ++k)
        {
            System r(dim);
            const int mm = r.addMaterial({2500, 0.3});
            r.addGrain(Vec3(0, 0, 0), 1e-3, mm);
            r.setGravity(Vec3(0, -g0, 0));
            r.setFluidDrag(0, c, u);
            const double dt = k == 0 ? 1e-3 : 5e-4;
            const int n = int(std::lround(tau / dt));
            for (int j = 0; j < n; ++j) r.step(dt);
            const Vec3 exact = vt + (Vec3::Zero() - vt) * std::exp(-1.0);
            err[k] = (r.velocities()[0] - exact).norm();
        }
        EXPECT_NEAR(err[0] / err[1], 2.0, 0.1) << "dim " << dim;
        EXPECT_LT(err[0], 0.02 * vt.norm());
        // stiff: c dt/m = 1e4 reaches v_t in one step, no overshoot
        s.setFluidDrag(0, 1e4 * mass / 1e-3, u);
        s.step(1e-3);
        const Vec3 vt2 = u + 1e-7 * Vec3(0, -g0, 0);
        EXPECT_LT((s.velocities()[0] - vt2).norm(), 1e-4 * vt2.norm()) << "dim " << dim;
        // impulse received: m (v^+ - v^n) - dt m g
        const Vec3 J = s.fluidDragImpulses()[0];
        const Vec3 Jref = mass * s.velocities()[0] - 1e-3 * mass * Vec3(0, -g0, 0);
        EXPECT_LT((J - Jref).norm(), 1e-12 * Jref.norm()) << "dim " << dim;
    }
}

// Reference: static force balance of a column of n grains resting on a floor
// in a uniform upflow u (each grain feels c u up, its weight m g down): the
// contact under grain k (counted from the top, k = 1..n) carries
// k (m g - c u) per unit time; grains at rest. Stiff drag, c dt/m = 1e3 (the
// cap of the residual weight; fine grains in a liquid): the previous explicit
// coupling (drag from last step's contact impulse) was unstable there; here
// the column must stay at rest from the first step.
TEST(FluidDrag, StiffColumnAtRestCarriesItsSubmergedWeight)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m = s.addMaterial({2650, 0.4});
        const double r = 1e-4, dt = 1e-3;
        const int n = 8;
        for (int k = 0; k < n; ++k) s.addGrain(Vec3(0, r + 2 * r * k, 0), r, m);
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.setGravity(Vec3(0, -g0, 0));
        const double mass = s.mass(0);
        const double c = 1e3 * mass / dt;
        const double u = 0.6 * mass * g0 / c; // drag 60 % of the weight
        for (int k = 0; k < n; ++k) s.setFluidDrag(k, c, Vec3(0, u, 0));
        // default solver settings: the stopping test weighs the impulse
        // changes with the grains' own masses (SolverContact::residualWeight2),
        // so the drag c (u - v), which multiplies a velocity error by
        // c dt/m = 1e3, is still balanced to the solver's relative accuracy
        for (int step = 0; step < 200; ++step)
        {
            const StepReport rep = s.step(dt);
            ASSERT_TRUE(rep.converged) << "dim " << dim << " step " << step;
        }
        double vmax = 0;
        for (int k = 0; k < n; ++k) vmax = std::max(vmax, s.velocities()[k].norm());
        EXPECT_LT(c * vmax, 1e-3 * mass * g0) << "dim " << dim; // drag of the residual motion
        // floor contact: the whole column, n (m g - c u) dt per step
        double floorImpulse = 0;
        for (const auto& cv : s.contacts())
            if (cv.j < 0) floorImpulse += cv.impulse.y();
        EXPECT_NEAR(floorImpulse, n * (mass * g0 - c * u) * dt, 1e-4 * n * mass * g0 * dt) << "dim " << dim;
        // drag impulse received over the 200 steps: c u dt each
        for (int k = 0; k < n; ++k)
            EXPECT_NEAR(s.fluidDragImpulses()[k].y(), 200 * c * u * dt, 1e-3 * 200 * c * u * dt);
    }
}

// Reference: above the buoyant weight the column lifts as one rigid body: its
// top grain reaches the terminal velocity u - m g/c (each grain's own balance;
// contacts open).
TEST(FluidDrag, ColumnLiftsAtTerminalVelocityAboveTheWeight)
{
    System s(2);
    const int m = s.addMaterial({2650, 0.4});
    const double r = 1e-4, dt = 1e-3;
    for (int k = 0; k < 4; ++k) s.addGrain(Vec3(0, r + 2 * r * k, 0), r, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -g0, 0));
    const double mass = s.mass(0);
    const double c = 1e4 * mass / dt;
    const double u = 1.5 * mass * g0 / c;
    for (int k = 0; k < 4; ++k) s.setFluidDrag(k, c, Vec3(0, u, 0));
    for (int step = 0; step < 20; ++step) s.step(dt);
    const double vt = u - mass * g0 / c;
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(s.velocities()[k].y(), vt, 1e-6 * vt);
}

TEST(FluidDrag, BadInputIsRejected)
{
    System s(3);
    const int m = s.addMaterial({2500, 0.3});
    s.addGrain(Vec3(0, 0, 0), 1e-3, m);
    EXPECT_THROW(s.setFluidDrag(1, 1.0, Vec3::Zero()), InputError);
    EXPECT_THROW(s.setFluidDrag(0, -1.0, Vec3::Zero()), InputError);
    EXPECT_THROW(s.setFluidDrag(0, NAN, Vec3::Zero()), InputError);
    EXPECT_THROW(s.setFluidDrag(0, 1.0, Vec3(NAN, 0, 0)), InputError);
    EXPECT_NO_THROW(s.setFluidDrag(0, 1.0, Vec3(0, 1, 0)));
    EXPECT_EQ(s.fluidDragCoefficient(0), 1.0);
}
