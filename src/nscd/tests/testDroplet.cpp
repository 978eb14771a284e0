// SPDX-License-Identifier: GPL-3.0-or-later
// Capillary entry barrier of a droplet (System::Droplet, Droplet.H).
//
// References for the numbers below:
//  - the entry force of a non-wetting surface (contact angle 180 degrees)
//    on a grain at filling angle phi, cos(phi) = 1 - h/r: 2D 2 sigma
//    sin(phi) per unit depth, 3D 2 pi sigma r sin^2(phi) (surface tension
//    along the contact line, tangent to the grain; Droplet.H), with the
//    threshold F_max = 2 sigma (2D), 2 pi sigma r (3D) up to h = r;
//  - statics: a droplet held by grains receives exactly its weight from
//    them, and the floor under the grains carries grains + droplet;
//  - one step of the gap-based Signorini law with the bounded impulse
//    0 <= r_n <= F_c dt (ContactLaw.H conventions), solved exactly for one
//    contact: impulse min(needed, F_c dt);
//  - momentum conservation of droplet + grain (Newton's third law).
// Tolerances: 1e-12 relative (round-off, one contact solved exactly) unless
// stated; the floor test converges the Gauss-Seidel to tolerance 1e-12.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>

using namespace nscd;

namespace
{
constexpr double r = 1e-3;     // grain radius [m]
constexpr double rho = 1000;   // grain density [kg/m^3]
constexpr double R = 5e-3;     // droplet radius [m]
constexpr double sigma = 0.05; // surface tension [N/m] -> 2D F_max = 0.1 N/m
constexpr double dt = 1e-3;    // [s]
constexpr double g = 9.81;     // [m/s^2]

System::Droplet droplet(const Vec3& centre, double mass, const Vec3& force,
                        const Vec3& velocity = Vec3::Zero())
{
    System::Droplet d;
    d.centre = centre;
    d.radius = R;
    d.mass = mass;
    d.force = force;
    d.velocity = velocity;
    d.surfaceTension = sigma;
    return d;
}

System twoD()
{
    System s(2);
    s.settings().tolerance = 1e-12;
    s.settings().maxIterations = 100000;
    return s;
}
} // namespace

TEST(Droplet, EntryForceProfile)
{
    // 2D: threshold 2 sigma up to h = r, then 2 sigma sin(phi), 0 when inside
    EXPECT_DOUBLE_EQ(System::capillaryEntryForce(2, sigma, r, -1e-3), 2 * sigma);
    EXPECT_DOUBLE_EQ(System::capillaryEntryForce(2, sigma, r, 0.5 * r), 2 * sigma);
    EXPECT_DOUBLE_EQ(System::capillaryEntryForce(2, sigma, r, r), 2 * sigma);
    // h = 1.5 r: cos(phi) = -1/2, sin(phi) = sqrt(3)/2
    EXPECT_NEAR(System::capillaryEntryForce(2, sigma, r, 1.5 * r), 2 * sigma * std::sqrt(0.75), 1e-15);
    EXPECT_EQ(System::capillaryEntryForce(2, sigma, r, 2 * r), 0.0);
    // 3D: 2 pi sigma r, then 2 pi sigma r sin^2(phi)
    EXPECT_NEAR(System::capillaryEntryForce(3, sigma, r, 0.3 * r), 2 * M_PI * sigma * r, 1e-18);
    EXPECT_NEAR(System::capillaryEntryForce(3, sigma, r, 1.5 * r), 2 * M_PI * sigma * r * 0.75, 1e-18);
}

TEST(Droplet, LightDropletRestsOnAGrain)
{
    // weight M g = 0.049 N/m < 2 sigma = 0.1 N/m: held at the surface
    System s = twoD();
    const int m = s.addMaterial({rho, 0.3});
    s.addGrain(Vec3(0, 0, 0), r, m, true);
    const double M = 5e-3;
    const Vec3 x0(0, R + r, 0);
    const int id = s.addDroplet(droplet(x0, M, Vec3(0, -M * g, 0)));
    for (int k = 0; k < 20; ++k)
    {
        s.droplet(id).impulse.setZero();
        s.step(dt);
        // the grain gives the droplet exactly its weight: statics
        EXPECT_NEAR(s.droplet(id).impulse.y(), M * g * dt, 1e-12 * M * g * dt);
        EXPECT_NEAR(s.droplet(id).velocity.norm(), 0.0, 1e-14);
        // ... through its own normal impulse (grainImpulse, resized by the
        // step to the grain count, accumulated since the last reset)
        ASSERT_EQ(s.droplet(id).grainImpulse.size(), 1u);
        EXPECT_NEAR(s.droplet(id).grainImpulse[0], (k + 1) * M * g * dt, 1e-12 * (k + 1) * M * g * dt);
    }
    EXPECT_NEAR((s.droplet(id).centre - x0).norm(), 0.0, 1e-15);
    // droplet contacts are not grain contacts (views, heat, warm start)
    EXPECT_EQ(s.nContacts(), 0u);
}

TEST(Droplet, HeavyDropletPushesThroughAGrain)
{
    // weight 0.196 N/m > 2 sigma: the grain is pushed in with exactly
    // F_c(h) dt per step, until it is inside; then the droplet is free
    System s = twoD();
    const int m = s.addMaterial({rho, 0.3});
    s.addGrain(Vec3(0, 0, 0), r, m, true);
    const double M = 0.02;
    const Vec3 F(0, -M * g, 0);
    const int id = s.addDroplet(droplet(Vec3(0, R + r, 0), M, F));
    double v = 0;
    int inside = -1;
    for (int k = 0; k < 200 && inside < 0; ++k)
    {
        const System::Droplet d = s.droplet(id);
        const double h = R + r - d.centre.y(); // immersion at the step start
        const double Fc = h > -2 * r ? System::capillaryEntryForce(2, sigma, r, h) : 0.0;
        s.droplet(id).impulse.setZero();
        s.step(dt);
        // the free velocity v - g dt always needs more than F_c dt to be stopped
        // (the grain is fixed): r_n = F_c dt exactly
        v += dt * (-g + Fc / M);
        EXPECT_NEAR(s.droplet(id).velocity.y(), v, 1e-12);
        EXPECT_NEAR(s.droplet(id).impulse.y(), Fc * dt, 1e-15);
        if (h >= 2 * r) inside = k;
    }
    ASSERT_GE(inside, 0) << "the grain never got inside";
    // once inside the droplet moves as if the grain were not there
    const double v1 = s.droplet(id).velocity.y();
    s.step(dt);
    EXPECT_NEAR(s.droplet(id).velocity.y(), v1 - g * dt, 1e-12);
}

TEST(Droplet, MomentumOfDropletAndGrain)
{
    // no gravity; droplet of mass M moving at v0 onto a free grain at rest
    const double M = 5e-3, mg = rho * M_PI * r * r;
    for (const double v0 : {0.01, 1.0})
    {
        System s = twoD();
        const int m = s.addMaterial({rho, 0.3});
        s.addGrain(Vec3(R + r, 0, 0), r, m);
        const int id = s.addDroplet(droplet(Vec3::Zero(), M, Vec3::Zero(), Vec3(v0, 0, 0)));
        s.step(dt);
        const double vg = s.velocities()[0].x(), vd = s.droplet(id).velocity.x();
        // Newton's third law: total momentum kept
        EXPECT_NEAR(M * vd + mg * vg, M * v0, 1e-14);
        // impulse needed for a common velocity (perfectly inelastic): m M v0/(M + m)
        const double need = mg * M * v0 / (M + mg), cap = 2 * sigma * dt;
        const double p = std::min(need, cap);
        EXPECT_NEAR(mg * vg, p, 1e-12 * need);
        if (need < cap)
            EXPECT_NEAR(vg, vd, 1e-12 * v0); // slow: held out
        else
            EXPECT_GT(vd, vg); // fast: pushed in
        EXPECT_NEAR(s.droplet(id).impulse.x(), -p, 1e-12 * need);
    }
}

TEST(Droplet, FloorCarriesGrainAndDroplet)
{
    // droplet resting on a grain resting on a floor (gravity): the floor's
    // impulse per step is (m_grain + M) g dt, so the droplet contact is part
    // of the same Gauss-Seidel network (and not lagged by a step)
    System s = twoD();
    s.setGravity(Vec3(0, -g, 0));
    const int m = s.addMaterial({rho, 0.3});
    s.addGrain(Vec3(0, r, 0), r, m);
    s.addPlane(Vec3::Zero(), Vec3(0, 1, 0));
    const double M = 5e-3, mg = rho * M_PI * r * r;
    const int id = s.addDroplet(droplet(Vec3(0, 2 * r + R, 0), M, Vec3(0, -M * g, 0)));
    for (int k = 0; k < 5; ++k)
    {
        s.droplet(id).impulse.setZero();
        s.step(dt);
        ASSERT_EQ(s.nContacts(), 1u);
        const auto c = s.contacts()[0];
        EXPECT_NEAR(c.impulse.y(), (mg + M) * g * dt, 1e-9 * (mg + M) * g * dt);
        EXPECT_NEAR(s.droplet(id).impulse.y(), M * g * dt, 1e-9 * M * g * dt);
        // per grain: the one grain carries the droplet (reset by hand)
        EXPECT_NEAR(s.droplet(id).grainImpulse[0], M * g * dt, 1e-9 * M * g * dt);
        s.droplet(id).grainImpulse.assign(1, 0.0);
        // at rest to the solver tolerance xi/dt = 1e-12 d_min/dt = 2e-12 m/s
        EXPECT_NEAR(s.droplet(id).velocity.norm(), 0.0, 1e-11);
        EXPECT_NEAR(s.velocities()[0].norm(), 0.0, 1e-11);
    }
}

TEST(Droplet, AbsorbedGrainIsFree)
{
    // a grain deep inside a held (kinematic) droplet falls freely
    System s = twoD();
    s.setGravity(Vec3(0, -g, 0));
    const int m = s.addMaterial({rho, 0.3});
    s.addGrain(Vec3::Zero(), r, m);
    s.addDroplet(droplet(Vec3::Zero(), 0.0, Vec3::Zero()));
    s.step(dt);
    EXPECT_NEAR(s.velocities()[0].y(), -g * dt, 1e-15);
}

TEST(Droplet, ThreeDimensionalThreshold)
{
    // sphere droplet on a fixed sphere: entry force 2 pi sigma r = 3.1e-4 N
    const double Fmax = 2 * M_PI * sigma * r;
    for (const double W : {0.5 * Fmax, 2 * Fmax})
    {
        System s(3);
        s.settings().tolerance = 1e-12;
        const int m = s.addMaterial({rho, 0.3});
        s.addGrain(Vec3::Zero(), r, m, true);
        const double M = 1e-3;
        const int id = s.addDroplet(droplet(Vec3(0, 0, R + r), M, Vec3(0, 0, -W)));
        s.step(dt);
        const double expect = W < Fmax ? 0.0 : -(W - Fmax) * dt / M;
        EXPECT_NEAR(s.droplet(id).velocity.z(), expect, 1e-15);
    }
}

TEST(Droplet, InvalidInput)
{
    System s = twoD();
    System::Droplet d = droplet(Vec3::Zero(), 1.0, Vec3::Zero());
    d.radius = 0;
    EXPECT_THROW(s.addDroplet(d), InputError);
    d.radius = R;
    d.mass = -1;
    EXPECT_THROW(s.addDroplet(d), InputError);
    d.mass = 1;
    const int id = s.addDroplet(d);
    s.droplet(id).surfaceTension = -1;
    EXPECT_THROW(s.step(dt), InputError);
    EXPECT_THROW(s.droplet(7), InputError);
}
