// SPDX-License-Identifier: GPL-3.0-or-later
// The Newton contact solver of compliant contacts (Settings::Method::Newton,
// src/nscd/src/ContactSolverNewton.cpp; the primal convex formulation of
// Castro, Permenter & Han, IEEE Trans. Robotics 39(2), 2023).
//
// References, independent of the solver (each test names its own):
//  - statics (momentum balance of a column at rest): every contact carries
//    the weight above it; the overlap being c times that load is Hooke's law
//    with c's definition, a consistency check of the law;
//  - the implicit (backward) Euler step of m x'' = -x/c - m g with the
//    unilateral spring, written out as its two-line recurrence (the exact
//    solution of the one-contact complementarity problem);
//  - Coulomb's block on an incline (Newton's second law): sticks for
//    tan(theta) < mu, else slides with acceleration g (sin - mu cos);
//  - the creep and the normal offset of the regularised cone, derived
//    from its projection (NewtonCone.H, Castro et al. section V): a
//    sticking contact slips at R_t |r_t|, a sliding one floats by
//    mu |v_t| dt;
//  - the compliant NLGS of the library (another method, tight tolerance).
#include "NewtonCone.H"
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

using namespace nscd;
using Method = System::Settings::Method;

namespace
{
constexpr double rad = 1e-3;  // [m]
constexpr double rho = 2500;  // [kg/m^3]
constexpr double gAcc = 9.81; // [m/s^2]

/// n frictionless discs in a column on the floor y = 0, gaps 0, compliance c.
System newtonColumn(int n, double c, double mu)
{
    System s(2);
    Material mat{rho, mu};
    mat.compliance = c;
    const int m = s.addMaterial(mat);
    for (int k = 0; k < n; ++k) s.addGrain(Vec3(0, rad + 2 * rad * k, 0), rad, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -gAcc, 0));
    s.settings().method = Method::Newton;
    s.settings().newtonTolerance = 1e-12;
    s.settings().overlapSlop = 0; // the law exactly
    return s;
}

/// A 2D pile of n discs (radius 0.9-1 mm, mu 0.4) poured between walls and
/// settled with the compliant NLGS (relativeCompliance 1e-2); deterministic.
System pile(int n)
{
    System s(2);
    Material mat{rho, 0.4};
    mat.relativeCompliance = 1e-2;
    const int m = s.addMaterial(mat);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    const double w = 12e-3, sp = 2.4e-3;
    for (int k = 0; k < n; ++k)
        s.addGrain(Vec3((k % 5 + 0.5) * sp + 2e-4 * (u(rng) - 0.5), (k / 5 + 0.5) * sp, 0),
                   rad * (0.9 + 0.1 * u(rng)), m);
    s.addSegment(Vec3(0, 0, 0), Vec3(w, 0, 0));
    s.addSegment(Vec3(0, 0, 0), Vec3(0, 0.1, 0));
    s.addSegment(Vec3(w, 0, 0), Vec3(w, 0.1, 0));
    s.setGravity(Vec3(0, -gAcc, 0));
    s.settings().tolerance = 1e-10;
    for (int k = 0; k < 600; ++k) s.step(5e-4);
    return s;
}
} // namespace

// Statics: a resting frictionless column of 20 discs, each contact carries
// the weight of the discs above it (1e-6 relative, as Compliance.*: the
// column's slow mode is still decaying after 0.3 s, 4e-8 measured);
// consistency: its overlap is c times that load (1e-6).
TEST(Newton, RestingColumnCarriesTheWeightAbove)
{
    const int n = 20;
    const double mass = rho * M_PI * rad * rad;
    const double c = 1e-3 * rad / (n * mass * gAcc); // bottom overlap 1e-3 r
    System s = newtonColumn(n, c, 0.0);
    const double dt = 1e-4;
    int maxIt = 0;
    for (int k = 0; k < 3000; ++k)
    {
        const StepReport r = s.step(dt);
        ASSERT_TRUE(r.converged) << "step " << k;
        maxIt = std::max(maxIt, r.sweeps);
    }
    EXPECT_LE(maxIt, 30); // Newton iterations per step
    for (const auto& v : s.contacts())
    {
        // contact below grain k carries grains k..n-1
        const int k = v.j < 0 ? 0 : std::max(v.i, v.j);
        const double load = (n - k) * mass * gAcc;
        EXPECT_NEAR(std::abs(v.impulse.y()) / dt, load, 1e-6 * load) << "contact below grain " << k;
    }
    const auto& x = s.positions();
    for (int k = 0; k < n; ++k)
    {
        const double ov = k == 0 ? rad - x[0].y() : 2 * rad - (x[k].y() - x[k - 1].y());
        const double expected = c * (n - k) * mass * gAcc;
        EXPECT_NEAR(ov, expected, 1e-6 * expected) << "overlap below grain " << k;
    }
}

// A sphere dropped onto a compliant floor (omega dt = 0.3) follows the
// backward-Euler recurrence of the unilateral spring, in free flight and in
// contact: v+ = (v - dt g - dt gap/(m c))/(1 + dt^2/(m c)) when the free
// flight would close the gap, gap+ = gap + dt v+ (1e-9 m/s, 1e-12 m).
TEST(Newton, DroppedSphereFollowsImplicitEulerSpring)
{
    const double mass = rho * 4.0 / 3.0 * M_PI * rad * rad * rad, dt = 1e-4;
    const double omega = 0.3 / dt, c = 1 / (omega * omega * mass);
    System s(3);
    Material mat{rho, 0.5};
    mat.compliance = c;
    const int m = s.addMaterial(mat);
    double gap = 2e-4, v = 0; // reference state
    s.addGrain(Vec3(0, rad + gap, 0), rad, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -gAcc, 0));
    s.settings().method = Method::Newton;
    s.settings().newtonTolerance = 1e-13;
    s.settings().overlapSlop = 0;
    int contactSteps = 0;
    for (int k = 0; k < 600; ++k)
    {
        s.step(dt);
        const double vFree = v - dt * gAcc;
        if (gap + dt * vFree >= 0)
            v = vFree; // no force: the spring is not compressed at the end
        else
        {
            v = (vFree - dt * gap / (mass * c)) / (1 + dt * dt / (mass * c));
            ++contactSteps;
        }
        gap += dt * v;
        ASSERT_NEAR(s.velocities()[0].y(), v, 1e-9) << "step " << k;
        ASSERT_NEAR(s.positions()[0].y() - rad, gap, 1e-12) << "step " << k;
        ASSERT_NEAR(s.velocities()[0].x(), 0.0, 1e-15);
    }
    EXPECT_GT(contactSteps, 100);
}

// Coulomb's block on an incline (rotation locked: a disc that slides),
// gravity tilted by theta on the floor y = 0, mu = 0.5, compliance c:
//  - tan(theta) < mu: it sticks; the regularised cone lets it creep at
//    R_t |r_t| = sigma (c/dt^2) m g sin(theta) dt (stiction region,
//    NewtonCone.H): the speed equals that to 1e-6, and is sigma c F_t/dt;
//  - tan(theta) > mu: it slides with a = g (sin - mu cos) to 1e-9 relative
//    over steps 1000-2000 (the sliding region keeps |r_t| = mu r_n
//    exactly), and floats by mu |v_t| dt over the spring's equilibrium:
//    overlap c F_n - mu v_t dt. Rising at mu a dt costs the start a normal
//    impulse m mu a dt and so a friction impulse: v lags a t by mu^2 a dt
//    (1e-6 relative).
TEST(Newton, BlockOnInclineSticksOrSlidesAsCoulomb)
{
    const double mass = rho * M_PI * rad * rad, dt = 1e-4, mu = 0.5;
    const double c = 1e-4 * rad / (mass * gAcc); // overlap 1e-4 r under its weight
    for (double theta : {0.4, 0.5})              // tan: 0.42 (sticks), 0.55 (slides)
    {
        System s(2);
        Material mat{rho, mu};
        mat.compliance = c;
        const int m = s.addMaterial(mat);
        const double F_n = mass * gAcc * std::cos(theta), F_t = mass * gAcc * std::sin(theta);
        s.addGrain(Vec3(0, rad - c * F_n, 0), rad, m); // at the spring's equilibrium
        s.setRotationLocked(0);
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.setGravity(Vec3(gAcc * std::sin(theta), -gAcc * std::cos(theta), 0));
        s.settings().method = Method::Newton;
        s.settings().newtonTolerance = 1e-13;
        s.settings().overlapSlop = 0;
        const double sigma = s.settings().tangentialRegularisation;
        const int steps = 2000;
        double vHalf = 0;
        for (int k = 0; k < steps; ++k)
        {
            ASSERT_TRUE(s.step(dt).converged);
            if (k == steps / 2 - 1) vHalf = s.velocities()[0].x();
        }
        const double vx = s.velocities()[0].x();
        if (std::tan(theta) < mu)
        {
            const double creep = sigma * (c / (dt * dt)) * F_t * dt;
            EXPECT_NEAR(vx, creep, 1e-6 * creep) << "theta " << theta;
            EXPECT_NEAR(creep, sigma * c * F_t / dt, 1e-12);
        }
        else
        {
            const double a = gAcc * (std::sin(theta) - mu * std::cos(theta));
            EXPECT_NEAR((vx - vHalf) / (steps / 2 * dt), a, 1e-9 * a) << "theta " << theta;
            EXPECT_NEAR(vx, a * steps * dt - mu * mu * a * dt, 1e-6 * a * steps * dt) << "theta " << theta;
            const double overlap = rad - s.positions()[0].y();
            // the previous step's speed set this step's gap
            const double expected = c * F_n - mu * (vx - a * dt) * dt;
            EXPECT_NEAR(overlap, expected, 1e-3 * std::abs(expected)) << "theta " << theta;
        }
    }
}

// The same pile state stepped once by the compliant NLGS (tolerance 1e-12
// d_min) and by Newton (newtonTolerance 1e-12): the settled pile's contacts
// stick, where the two formulations differ only by Newton's tangential
// creep R_t |r_t|, proportional to sigma. Measured: velocities differ by
// 1.3e-4 g dt with sigma 1e-3 (the default; NLGS's residual of the Newton
// solution 2e-7 d_min, below its default tolerance 1e-6), 1.3e-6 with 1e-5
// (1 and 11 Newton iterations). Bounds: 3e-4 and 1e-5 g dt for the
// velocities (translation + r x rotation), the same times the weight dt
// for each grain's total contact impulse.
TEST(Newton, AgreesWithCompliantNLGSOnASettledPile)
{
    const int n = 60;
    System a = pile(n);
    const double dt = 5e-4;
    a.settings().tolerance = 1e-12;
    a.settings().maxIterations = 1000000;
    ASSERT_TRUE(a.step(dt).converged);
    for (const double sigma : {1e-3, 1e-5})
    {
        const double bound = sigma == 1e-3 ? 3e-4 : 1e-5;
        System b = pile(n);
        b.settings().method = Method::Newton;
        b.settings().newtonTolerance = 1e-12;
        b.settings().tangentialRegularisation = sigma;
        const StepReport rb = b.step(dt);
        ASSERT_TRUE(rb.converged);
        EXPECT_LE(rb.sweeps, 30);
        double dv = 0;
        for (int i = 0; i < n; ++i)
            dv = std::max(dv, (a.velocities()[i] - b.velocities()[i]).norm()
                                  + rad * (a.angularVelocities()[i] - b.angularVelocities()[i]).norm());
        EXPECT_LE(dv, bound * gAcc * dt) << "sigma " << sigma;
        std::vector<Vec3> ia(n, Vec3::Zero()), ib(n, Vec3::Zero());
        auto total = [&](const System& s, std::vector<Vec3>& sum)
        {
            for (const auto& v : s.contacts())
            {
                sum[v.i] += v.impulse;
                if (v.j >= 0) sum[v.j] -= v.impulse;
            }
        };
        total(a, ia);
        total(b, ib);
        for (int i = 0; i < n; ++i)
        {
            const double weightDt = rho * M_PI * a.radii()[i] * a.radii()[i] * gAcc * dt;
            EXPECT_LE((ia[i] - ib[i]).norm(), bound * weightDt) << "grain " << i << " sigma " << sigma;
        }
    }
}

// Two free discs (2D) and two free spheres (3D), no gravity, touching
// (gap 0) with an approach speed of 0.1 m/s, a sliding speed of 0.01 m/s
// and spins of 5 and -3 rad/s, mu 0.5: one contact, so the NLGS local
// solve is its exact solution (eq. 2.38-2.41), and the contact sticks
// (|W_tt r_t| < mu W_nn r_n). Newton (sigma 1e-7: creep below the bound)
// gives the same velocities and spins to 1e-6 of the approach speed.
TEST(Newton, OneStickingContactMatchesTheExactLocalSolve)
{
    for (int dim : {2, 3})
    {
        auto make = [&](Method method)
        {
            System s(dim);
            Material mat{rho, 0.5};
            mat.relativeCompliance = 1e-2;
            const int m = s.addMaterial(mat);
            s.addGrain(Vec3(0, 0, 0), rad, m);
            s.addGrain(Vec3(2 * rad, 0, 0), rad, m);
            s.velocities()[0] = Vec3(0.05, 0.005, 0);
            s.velocities()[1] = Vec3(-0.05, -0.005, 0);
            s.angularVelocities()[0] = Vec3(0, 0, 5);
            s.angularVelocities()[1] = Vec3(0, 0, -3);
            s.settings().method = method;
            s.settings().tolerance = 1e-12;
            s.settings().newtonTolerance = 1e-12;
            s.settings().tangentialRegularisation = 1e-7;
            s.settings().overlapSlop = 0;
            s.step(1e-4);
            return s;
        };
        const System a = make(Method::NLGS), b = make(Method::Newton);
        for (int i = 0; i < 2; ++i)
        {
            EXPECT_LE((a.velocities()[i] - b.velocities()[i]).norm(), 1e-6 * 0.1)
                << "dim " << dim << " grain " << i;
            EXPECT_LE(rad * (a.angularVelocities()[i] - b.angularVelocities()[i]).norm(), 1e-6 * 0.1)
                << "dim " << dim << " grain " << i;
        }
        // sticking: the contact points move together (NLGS exactly)
        const Vec3 n(-1, 0, 0); // from B (grain 1) to A (grain 0)
        const Vec3 du = a.velocities()[0] - a.velocities()[1]
                        - (rad * a.angularVelocities()[0] + rad * a.angularVelocities()[1]).cross(n);
        EXPECT_LE((du - du.dot(n) * n).norm(), 1e-9) << "dim " << dim;
    }
}

// The cost of one contact's regularised cone projection (NewtonCone.H) and
// its derivatives, against central finite differences (the reference: the
// definition of a derivative): dl/dv_c = -gamma and d gamma/d v_c = -G, in
// each region (stiction, sliding, separation, frictionless), 2D (two
// components) and 3D. Step h = 1e-7 of the velocity scale; points within
// 1e-4 of a region boundary are skipped (the cost is C^1, G jumps there).
// Bound 1e-6 relative to the largest entry (measured: ~1e-9).
TEST(Newton, ConeCostGradientAndHessianMatchFiniteDifferences)
{
    std::mt19937 gen(11);
    std::uniform_real_distribution<double> u(-1, 1);
    const double Rn = 2.0, Rt = 0.05, vhat = 0.3;
    int seen[3] = {0, 0, 0};
    for (int comps : {2, 3})
        for (double mu : {0.0, 0.3, 1.0})
            for (int trial = 0; trial < 200; ++trial)
            {
                Eigen::Vector3d vc(u(gen), 0.05 * u(gen), comps == 3 ? 0.05 * u(gen) : 0.0);
                const newton::ConeProjection p = newton::project(vc, vhat, Rn, Rt, mu, true);
                // distance to the region boundaries, relative (skip the kinks)
                const double yn = -(vc(0) - vhat) / Rn, yr = std::hypot(vc(1), vc(2)) / Rt;
                if (std::abs(yn) < 1e-4
                    || (mu > 0
                        && (std::abs(yr - mu * yn) < 1e-4 * (yr + 1)
                            || std::abs(yn + mu * Rt / Rn * yr) < 1e-4 * (yr + 1))))
                    continue;
                ++seen[p.region];
                const double h = 1e-7;
                for (int a = 0; a < comps; ++a)
                {
                    Eigen::Vector3d e = Eigen::Vector3d::Zero();
                    e(a) = h;
                    const newton::ConeProjection pp = newton::project(vc + e, vhat, Rn, Rt, mu, false);
                    const newton::ConeProjection pm = newton::project(vc - e, vhat, Rn, Rt, mu, false);
                    const double scaleG = std::max(1.0, p.gamma.cwiseAbs().maxCoeff());
                    EXPECT_NEAR((pp.cost - pm.cost) / (2 * h), -p.gamma(a), 1e-6 * scaleG)
                        << "region " << p.region << " mu " << mu << " component " << a;
                    const Eigen::Vector3d dg = (pp.gamma - pm.gamma) / (2 * h);
                    const double scaleH = std::max(1.0 / Rt, p.G.cwiseAbs().maxCoeff());
                    for (int b = 0; b < comps; ++b)
                        EXPECT_NEAR(dg(b), -p.G(b, a), 1e-6 * scaleH)
                            << "region " << p.region << " mu " << mu << " entry " << b << a;
                }
            }
    // every region was sampled
    EXPECT_GT(seen[0], 50);
    EXPECT_GT(seen[1], 50);
    EXPECT_GT(seen[2], 50);
}

// Cohesion (thesis eq. 4.18) with Newton: a disc stuck under a ceiling
// with cohesion force F_c = 3 m g hangs (statics: its contact pulls with
// its weight, a normal impulse -m g dt per step, to 1e-8) and rests where the spring
// stretches by c m g (consistency, 1e-6); a disc with F_c = 0.5 m g falls.
TEST(Newton, CohesiveContactHoldsAHangingDisc)
{
    const double mass = rho * M_PI * rad * rad, dt = 1e-4;
    const double c = 1e-3 * rad / (mass * gAcc);
    for (const double factor : {3.0, 0.5})
    {
        System s(2);
        Material mat{rho, 0.3};
        mat.compliance = c;
        const int m = s.addMaterial(mat);
        s.addGrain(Vec3(0, -rad, 0), rad, m);
        s.addPlane(Vec3(0, 0, 0), Vec3(0, -1, 0)); // ceiling y = 0, grains below
        s.setGravity(Vec3(0, -gAcc, 0));
        s.setCohesion([](int, int) { return true; }, factor * mass * gAcc);
        s.settings().method = Method::Newton;
        s.settings().newtonTolerance = 1e-13;
        s.settings().overlapSlop = 0;
        for (int k = 0; k < 2000; ++k) ASSERT_TRUE(s.step(dt).converged);
        if (factor > 1)
        {
            ASSERT_EQ(s.contacts().size(), 1u);
            // on the disc: up, m g dt; along the normal (down, from the ceiling): -m g dt, a tension
            EXPECT_NEAR(s.contacts()[0].impulse.y(), mass * gAcc * dt, 1e-8 * mass * gAcc * dt);
            EXPECT_NEAR(-rad - s.positions()[0].y(), c * mass * gAcc,
                        1e-6 * c * mass * gAcc); // stretched gap
        }
        else
            EXPECT_LT(s.positions()[0].y(), -rad - 1e-3);
    }
}

// Bad input: a hard material, droplets, the RMS test, a bad tolerance or
// regularisation: InputError naming what to change.
TEST(Newton, RefusesHardContactsAndBadSettings)
{
    auto expectError = [](System& s, const std::string& word)
    {
        try
        {
            s.step(1e-4);
            FAIL() << "no InputError (" << word << ")";
        }
        catch (const InputError& e)
        {
            EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
        }
    };
    {
        System s = newtonColumn(3, 0.0, 0.3); // compliance 0: the hard law
        expectError(s, "compliance");
    }
    {
        System s = newtonColumn(3, 1e-6, 0.3);
        s.settings().convergence = System::Settings::Convergence::RMS;
        expectError(s, "Newton");
    }
    {
        System s = newtonColumn(3, 1e-6, 0.3);
        s.settings().newtonTolerance = 0;
        expectError(s, "newtonTolerance");
    }
    {
        System s = newtonColumn(3, 1e-6, 0.3);
        s.settings().tangentialRegularisation = -1;
        expectError(s, "tangentialRegularisation");
    }
    {
        // one hard material among compliant ones
        System s = newtonColumn(3, 1e-6, 0.3);
        const int hard = s.addMaterial(Material{rho, 0.3});
        s.addGrain(Vec3(0.01, rad, 0), rad, hard);
        expectError(s, "compliance");
    }
    {
        System s = newtonColumn(3, 1e-6, 0.3);
        System::Droplet d;
        d.centre = Vec3(0.01, 0.01, 0);
        d.radius = 1e-3;
        s.addDroplet(d);
        expectError(s, "droplet");
    }
}
