// SPDX-License-Identifier: GPL-3.0-or-later
// Cohesion switched by the contact age (thesis eq. 4.18, section 4.3.2: "a
// contact is considered cohesive if it persists for several time steps").
//
// Reference for every number below: the gap-based Signorini law of
// ContactLaw.H with the shifted impulse r~_n = r_n + F_c dt (eq. 2.37 with
// the cohesion impulse of eq. 4.18). For two free discs of mass m pulled
// apart along their line of centres by external forces -F/+F (no gravity,
// no friction needed: the tangential impulse is zero), one step from rest:
//   F <= F_c and the contact cohesive: r_n = -F dt, both discs stay at rest;
//   otherwise r_n = -c (c = F_c dt if cohesive, else 0) and the gap opens
//   with the relative normal velocity 2 (F - F_c/F) dt/m.
// After the contact has opened (age 0) it can only become cohesive again
// once it has been closed cohesionMinAge steps, so the discs fly apart
// freely: symplectic Euler from rest gives x_k = x_0 +/- F dt^2/m k (k+1)/2.
// Tolerances: 1e-12 relative (round-off; one contact, solved exactly).
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace nscd;

namespace
{
constexpr double r = 0.1;    // disc radius [m]
constexpr double rho = 1000; // [kg/m^3] -> m = rho pi r^2 [kg/m]
constexpr double dt = 1e-3;  // [s]
constexpr double Fc = 100;   // cohesion force [N/m]

/// Two touching free discs on the x axis (gap exactly 0), no gravity.
System twoDiscs(int minAge)
{
    System s(2);
    const int m = s.addMaterial({rho, 0.3});
    s.addGrain(Vec3(-r, 0, 0), r, m);
    s.addGrain(Vec3(r, 0, 0), r, m);
    s.settings().tolerance = 1e-12;
    s.settings().cohesionMinAge = minAge;
    s.setCohesion([](int, int) { return true; }, Fc);
    return s;
}

/// External forces: F > 0 pulls the discs apart, F < 0 presses them together.
void pull(System& s, double F)
{
    s.setExternalForce(0, Vec3(-F, 0, 0));
    s.setExternalForce(1, Vec3(F, 0, 0));
}

double gapOf(const System& s) { return s.positions()[1].x() - s.positions()[0].x() - 2 * r; }

/// The contact between grains 0 and 1 of the last step (fails if absent).
System::ContactView pairContact(const System& s)
{
    for (const auto& c : s.contacts())
        if (c.i == 0 && c.j == 1) return c;
    ADD_FAILURE() << "no contact between grains 0 and 1";
    return {};
}
} // namespace

TEST(Cohesion, ContactAgeCountsClosedSteps)
{
    System s = twoDiscs(5);
    pull(s, -10); // pressed: loaded contact
    for (int k = 1; k <= 7; ++k)
    {
        s.step(dt);
        const auto c = pairContact(s);
        EXPECT_EQ(c.age, k);
        // cohesion is available once the age at the step start (k - 1)
        // reaches cohesionMinAge, pressed or not
        EXPECT_EQ(c.cohesive, k - 1 >= 5);
        EXPECT_GT(c.impulse.dot(c.normal), 0.0); // pressed: repulsive
    }
    // unloaded but touching (gap 0 <= tolerance d_min): still closed
    pull(s, 0);
    s.step(dt);
    EXPECT_EQ(pairContact(s).age, 8);
}

TEST(Cohesion, PulledApartBelowFcHoldsOnlyAfterMinAge)
{
    const int N = 5;
    const double F = 0.5 * Fc;
    for (const int K : {N, N - 1})
    {
        System s = twoDiscs(N);
        const double m = s.mass(0);
        pull(s, -10);
        for (int k = 0; k < K; ++k) s.step(dt);
        ASSERT_EQ(pairContact(s).age, K);
        // the discs were pressed: they are at rest, gap 0
        EXPECT_LT(std::abs(gapOf(s)), 1e-15);
        pull(s, F);
        const StepReport rep = s.step(dt);
        const auto c = pairContact(s);
        if (K >= N)
        {
            // old enough: cohesive, the impulse balances the pull exactly
            EXPECT_TRUE(c.cohesive);
            EXPECT_EQ(rep.cohesiveContacts, 1);
            EXPECT_NEAR(c.impulse.dot(c.normal), -F * dt, 1e-12 * F * dt);
            EXPECT_LT(s.velocities()[0].norm() + s.velocities()[1].norm(), 1e-12 * F * dt / m);
            for (int k = 0; k < 200; ++k) s.step(dt);
            EXPECT_LT(std::abs(gapOf(s)), 1e-12 * r) << "K = " << K;
            EXPECT_EQ(pairContact(s).age, K + 201);
        }
        else
        {
            // too young: no cohesion, the gap opens at 2 F dt/m
            EXPECT_FALSE(c.cohesive);
            EXPECT_EQ(rep.cohesiveContacts, 0);
            EXPECT_NEAR(c.impulse.norm(), 0.0, 1e-15);
            const double du = s.velocities()[1].x() - s.velocities()[0].x();
            EXPECT_NEAR(du, 2 * F * dt / m, 1e-12 * 2 * F * dt / m);
            EXPECT_EQ(pairContact(s).age, 0);
            // ... and never closes again (within cohesionDistance it would be
            // caught if the age were the time spent within reach)
            for (int k = 1; k < 200; ++k) s.step(dt);
            const double ref = 2 * F * dt * dt / m * 200 * 201 / 2;
            EXPECT_NEAR(gapOf(s), ref, 1e-12 * ref) << "K = " << K;
        }
    }
}

TEST(Cohesion, AboveFcTheBondBreaks)
{
    const double F = 1.5 * Fc;
    // old contact, minAge 5: first step r_n = -F_c dt, then free flight
    {
        System s = twoDiscs(5);
        const double m = s.mass(0);
        pull(s, -10);
        for (int k = 0; k < 20; ++k) s.step(dt);
        pull(s, F);
        s.step(dt);
        const auto c = pairContact(s);
        EXPECT_TRUE(c.cohesive);
        EXPECT_NEAR(c.impulse.dot(c.normal), -Fc * dt, 1e-12 * Fc * dt);
        const double du = s.velocities()[1].x() - s.velocities()[0].x();
        EXPECT_NEAR(du, 2 * (F - Fc) * dt / m, 1e-12 * 2 * (F - Fc) * dt / m);
        EXPECT_EQ(c.age, 0); // open after the step: the bond is broken
        s.step(dt);
        EXPECT_FALSE(pairContact(s).cohesive);
        const double du2 = s.velocities()[1].x() - s.velocities()[0].x();
        EXPECT_NEAR(du2 - du, 2 * F * dt / m, 1e-12 * 2 * F * dt / m);
    }
    // minAge 0: the cohesive force keeps acting while the gap is below
    // cohesionDistance r_min: relative acceleration 2 (F - F_c)/m
    {
        System s = twoDiscs(0);
        const double m = s.mass(0);
        pull(s, F);
        for (int k = 1; k <= 10; ++k)
        {
            s.step(dt);
            ASSERT_LT(gapOf(s), s.settings().cohesionDistance * r);
            EXPECT_TRUE(pairContact(s).cohesive);
            const double du = s.velocities()[1].x() - s.velocities()[0].x();
            EXPECT_NEAR(du, 2 * (F - Fc) * dt / m * k, 1e-12 * 2 * (F - Fc) * dt / m * k);
        }
    }
}

TEST(Cohesion, WallContactAgeAndHangingDisc)
{
    // a disc under a ceiling, F_c = 2 m g: pressed up against it for N steps
    // it then hangs (cohesive wall contact); placed touching without load it
    // falls, since its first step opens the contact (age back to 0)
    const int N = 3;
    for (const bool pressed : {true, false})
    {
        System h(2);
        const int mh = h.addMaterial({1000, 0.5});
        h.addGrain(Vec3(0, -0.1, 0), 0.1, mh);
        h.addPlane(Vec3(0, 0, 0), Vec3(0, -1, 0));
        h.setGravity(Vec3(0, -9.81, 0));
        h.settings().tolerance = 1e-12;
        h.settings().cohesionMinAge = N;
        const double W = h.mass(0) * 9.81;
        h.setCohesion([](int, int j) { return j == -1; }, 2 * W);
        if (pressed)
        {
            h.setExternalForce(0, Vec3(0, 2 * W, 0));
            for (int k = 0; k < N; ++k) h.step(dt);
            h.setExternalForce(0, Vec3::Zero());
        }
        for (int k = 0; k < 100; ++k) h.step(dt);
        if (pressed)
        {
            EXPECT_NEAR(h.positions()[0].y(), -0.1, 1e-12);
            ASSERT_EQ(h.contacts().size(), 1u);
            EXPECT_EQ(h.contacts()[0].j, -1);
            EXPECT_TRUE(h.contacts()[0].cohesive);
            EXPECT_EQ(h.contacts()[0].age, N + 100);
            // the ceiling pulls the disc up with its weight (r_n = -W dt along n = -y)
            EXPECT_NEAR(h.contacts()[0].impulse.y(), W * dt, 1e-12 * W * dt);
        }
        else
        {
            // free fall: y = -0.1 - g dt^2 k (k+1)/2
            EXPECT_NEAR(h.positions()[0].y(), -0.1 - 9.81 * dt * dt * 100 * 101 / 2, 1e-12);
        }
    }
}

TEST(Cohesion, AgeIndependentOfWarmStartAndCountsSubSteps)
{
    for (const bool warm : {true, false})
    {
        System s = twoDiscs(1000);
        s.settings().warmStart = warm;
        // a third disc far away, strongly forced: sub-steps of advance()
        // (velocity change 10 m/s over the step of 1e-2 s)
        const int m = 0;
        const int fast = s.addGrain(Vec3(0, 10, 0), r, m);
        s.setExternalForce(fast, Vec3(1000 * s.mass(fast), 0, 0), Vec3::Zero());
        pull(s, -10);
        int steps = 0;
        for (int k = 0; k < 3; ++k)
        {
            const StepReport rep = s.advance(1e-2, 0.1);
            EXPECT_GE(rep.substeps, 5);
            steps += rep.substeps;
            EXPECT_EQ(pairContact(s).age, steps) << "warmStart " << warm;
        }
    }
}

TEST(Cohesion, AgeAndMinAgeSurviveHDF5Restart)
{
    const int N = 6;
    const double F = 0.5 * Fc;
    // reference: pressed N - 2 steps, written, read, then pressed 2 more
    // steps and pulled: cohesive (age N) exactly as without the restart
    System s = twoDiscs(N);
    pull(s, -10);
    for (int k = 0; k < N - 2; ++k) s.step(dt);
    const std::string f = "nscd_cohesion_age.h5";
    s.writeHDF5(f);
    System r2 = System::readHDF5(f);
    std::remove(f.c_str());
    EXPECT_EQ(r2.settings().cohesionMinAge, N);
    ASSERT_EQ(r2.contacts().size(), s.contacts().size());
    EXPECT_EQ(r2.contacts()[0].age, N - 2);
    r2.setCohesion([](int, int) { return true; }, Fc); // the predicate is not saved
    for (System* t : {&s, &r2})
    {
        for (int k = 0; k < 2; ++k) t->step(dt);
        pull(*t, F);
        for (int k = 0; k < 50; ++k) t->step(dt);
    }
    EXPECT_EQ(r2.positions(), s.positions());
    EXPECT_EQ(r2.velocities(), s.velocities());
    EXPECT_TRUE(pairContact(r2).cohesive);
    EXPECT_LT(std::abs(gapOf(r2)), 1e-12 * r);
    // seeding through setContactImpulses keeps the age
    auto views = s.contacts();
    System t = twoDiscs(N);
    t.setContactImpulses(views, dt);
    EXPECT_EQ(t.contacts()[0].age, views[0].age);
}

TEST(Cohesion, BadInputs)
{
    System s = twoDiscs(0);
    EXPECT_THROW(s.setCohesion([](int, int) { return true; }, -1.0), InputError);
    EXPECT_THROW(s.setCohesion([](int, int) { return true; }, std::nan("")), InputError);
    s.settings().cohesionMinAge = -1;
    try
    {
        s.step(dt);
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("cohesionMinAge"), std::string::npos);
    }
    s.settings().cohesionMinAge = 0;
    System::ContactView v{};
    v.i = 0;
    v.j = 1;
    v.normal = Vec3(-1, 0, 0);
    v.impulse = Vec3::Zero();
    v.age = -2;
    EXPECT_THROW(s.setContactImpulses({v}, dt), InputError);
}
