// SPDX-License-Identifier: GPL-3.0-or-later
// API errors, checks, sub-stepping, momentum conservation.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

using namespace nscd;

TEST(Errors, BadInputs)
{
    EXPECT_THROW(System(4), InputError);
    System s(2);
    EXPECT_THROW(s.addMaterial({0.0, 0.3}), InputError);
    EXPECT_THROW(s.addMaterial({-1.0, 0.3}), InputError);
    EXPECT_THROW(s.addMaterial({1000, -0.1}), InputError);
    const int m = s.addMaterial({1000, 0.3});
    EXPECT_EQ(m, 0);
    EXPECT_THROW(s.addGrain(Vec3(0, 0, 0), -0.1, m), InputError);
    EXPECT_THROW(s.addGrain(Vec3(0, 0, 0), 0.0, m), InputError);
    EXPECT_THROW(s.addGrain(Vec3(0, 0, 0), 0.1, 7), InputError);
    try
    {
        s.addGrain(Vec3(0, 0, 0), 0.1, 3);
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("unknown material 3"), std::string::npos);
    }
    EXPECT_THROW(s.addTriangulatedSurface({Vec3(0, 0, 0)}, {{0, 0, 0}}), InputError); // 2D
    EXPECT_THROW(s.step(0.0), InputError);
    EXPECT_THROW(s.setWallVelocity(3, Vec3::Zero()), InputError);
    System s3(3);
    s3.addMaterial({1000, 0.3});
    EXPECT_THROW(s3.addSegment(Vec3(0, 0, 0), Vec3(1, 0, 0)), InputError);
    EXPECT_THROW(s3.addTriangulatedSurface({Vec3(0, 0, 0), Vec3(1, 0, 0)}, {{0, 1, 2}}), InputError);
}

TEST(Errors, InitialOverlapNamesThePair)
{
    System s(2);
    const int m = s.addMaterial({1000, 0.3});
    s.addGrain(Vec3(0, 0, 0), 0.1, m);
    s.addGrain(Vec3(0.5, 0, 0), 0.1, m);
    s.addGrain(Vec3(0.69, 0, 0), 0.1, m);        // overlaps grain 1 by 0.01
    s.addPlane(Vec3(0, -0.1, 0), Vec3(0, 1, 0)); // grain 0 just touches: fine
    try
    {
        s.checkInitialOverlaps();
        FAIL() << "overlap not detected";
    }
    catch (const InputError& e)
    {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("grains 1 and 2"), std::string::npos) << msg;
        EXPECT_NE(msg.find("0.01"), std::string::npos) << msg;
        EXPECT_EQ(msg.find("wall"), std::string::npos) << msg;
    }
    s.positions()[2].x() = 0.7;
    EXPECT_NO_THROW(s.checkInitialOverlaps());
    s.positions()[0].y() = -0.05; // into the plane by 0.05
    try
    {
        s.checkInitialOverlaps();
        FAIL();
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("grain 0 and wall 0"), std::string::npos);
    }
}

// Consistency check of the documented rule of advance() (System.H): a
// velocity alone no longer sub-steps (the gap law keeps a grain from
// tunnelling whatever its displacement, see ContactsOfFastGrains); the
// velocity change of the step's forces does, |dv| dt_sub <= fraction d_min
// (the displacement rule of thesis section 5.1.3 applied to the part of
// the motion the first-order step integrates approximately), and an absurd
// speed does, |v| dt_sub <= 100 d_min.
TEST(SubStepping, PicksDtFromDminAndVelocityChange)
{
    System s(2);
    const int m = s.addMaterial({1000, 0.3});
    s.addGrain(Vec3(0, 0, 0), 0.01, m);
    const int b = s.addGrain(Vec3(1, 0, 0), 0.05, m);
    s.velocities()[b] = Vec3(3.0, 4.0, 0); // |v| = 5: 2.5 d_min per step
    const double frac = 0.1, dmin = 0.02;
    const double dt = 1e-2;
    using Cause = StepReport::SubStepCause;
    EXPECT_EQ(s.subStep(dt, frac), dt);
    EXPECT_EQ(s.subStepChoice(dt, frac).cause, Cause::None);
    const StepReport one = s.advance(dt, frac);
    EXPECT_EQ(one.substeps, 1);
    EXPECT_EQ(one.substepCause, Cause::None);
    // a force changing its velocity by 5 m/s over dt: 25 sub-steps
    const double mass = s.mass(b);
    s.setExternalForce(b, Vec3(0, 500 * mass, 0), Vec3::Zero());
    const double h = s.subStep(dt, frac);
    EXPECT_LE(5.0 * h, frac * dmin * (1 + 1e-12));
    EXPECT_GT(5.0 * h * 2, frac * dmin); // not needlessly small
    const double t0 = s.time();
    const StepReport r = s.advance(dt, frac);
    EXPECT_EQ(r.substeps, int(std::ceil(5.0 * dt / (frac * dmin))));
    EXPECT_NEAR(s.time() - t0, dt, 1e-15);
    // the report names the rule, the grain (by id) and its velocity change
    EXPECT_EQ(r.substepCause, Cause::VelocityChange);
    EXPECT_EQ(r.substepBody, s.grainIds()[std::size_t(b)]);
    EXPECT_NEAR(r.substepSpeed, 5.0, 1e-9);
    // no force, an absurd speed of 1e4 m/s: 1e4 dt / (100 d_min) = 50 sub-steps
    s.setExternalForce(b, Vec3::Zero(), Vec3::Zero());
    s.velocities()[b] = Vec3(1e4, 0, 0);
    const SubStepChoice c = s.subStepChoice(dt, frac);
    EXPECT_EQ(c.count, 50);
    EXPECT_EQ(c.cause, Cause::Travel);
    EXPECT_NEAR(c.speed, 1e4, 1e-6);
    const StepReport fast = s.advance(dt, frac);
    EXPECT_EQ(fast.substeps, 50);
    EXPECT_EQ(fast.substepCause, Cause::Travel);
    EXPECT_EQ(fast.substepBody, s.grainIds()[std::size_t(b)]);
}

// Consistency check of the tangential rule of advance() (System.H): two
// touching discs (a contact of the last step) sliding past each other at
// v_t move by at most fraction d_min per sub-step, and the report names the
// rule and the sliding speed.
TEST(SubStepping, TangentialSlideOfTouchingGrainsIsReported)
{
    System s(2);
    const int m = s.addMaterial({1000, 0.0});
    const double r = 0.01, frac = 0.1, dt = 1e-2;
    s.addGrain(Vec3(0, 0, 0), r, m, true);
    const int b = s.addGrain(Vec3(0, 2 * r, 0), r, m);
    s.setGravity(Vec3(0, -9.81, 0));
    s.step(1e-4); // the resting pair becomes a contact of the last step
    ASSERT_EQ(s.contacts().size(), 1u);
    s.velocities()[b] = Vec3(0.5, 0, 0); // sliding over the fixed disc: 0.25 d_min per step of 1e-2 s
    const SubStepChoice c = s.subStepChoice(dt, frac);
    using Cause = StepReport::SubStepCause;
    EXPECT_EQ(c.cause, Cause::TangentialSlide);
    EXPECT_NEAR(c.speed, 0.5, 1e-9);
    EXPECT_EQ(c.count, std::ceil(0.5 * dt / (frac * 2 * r)));
    EXPECT_EQ(s.advance(dt, frac).substepCause, Cause::TangentialSlide);
}

// Reference: Newton's third law in every local update (eq. 2.26-2.27):
// total linear momentum conserved to machine precision (1e-12 relative).
TEST(Momentum, ConservedInFreeCollisions)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m1 = s.addMaterial({1000, 0.4});
        const int m2 = s.addMaterial({2500, 0.2});
        std::mt19937 gen(11);
        std::uniform_real_distribution<double> U(0, 1);
        const int n = dim == 2 ? 10 : 5;
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b)
                for (int c = 0; c < (dim == 3 ? n : 1); ++c)
                {
                    const int k = s.addGrain(Vec3(0.1 * a, 0.1 * b, 0.1 * c), 0.02 + 0.025 * U(gen),
                                             (a + b) % 2 ? m1 : m2);
                    s.velocities()[k] = Vec3(U(gen) - 0.5, U(gen) - 0.5, dim == 3 ? U(gen) - 0.5 : 0.0);
                    if (dim == 3)
                        s.angularVelocities()[k] = Vec3(U(gen), U(gen), U(gen)) * 10;
                    else
                        s.angularVelocities()[k] = Vec3(0, 0, 10 * U(gen));
                }
        auto momentum = [&]()
        {
            Vec3 p = Vec3::Zero();
            for (std::size_t i = 0; i < s.size(); ++i) p += s.mass(i) * s.velocities()[i];
            return p;
        };
        double scale = 0;
        for (std::size_t i = 0; i < s.size(); ++i) scale += s.mass(i) * s.velocities()[i].norm();
        const Vec3 p0 = momentum();
        int contacts = 0;
        for (int k = 0; k < 300; ++k) contacts += s.step(2e-3).contacts;
        EXPECT_GT(contacts, 100);
        EXPECT_LT((momentum() - p0).norm(), 1e-12 * scale) << "dim " << dim;
    }
}

TEST(Contacts, ViewAndCohesion)
{
    // two discs resting on a plane; the view exposes normals, impulses, walls as -(w+1)
    System s(2);
    const int m = s.addMaterial({1000, 0.5, 1e9, 0.3, 1.0, 800});
    s.addGrain(Vec3(0, 0.1, 0), 0.1, m);
    s.addGrain(Vec3(0.2, 0.1, 0), 0.1, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -9.81, 0));
    const double dt = 1e-3;
    for (int k = 0; k < 10; ++k) s.step(dt);
    const auto cs = s.contacts();
    int walls = 0;
    for (const auto& c : cs)
    {
        if (c.j == -1)
        {
            ++walls;
            EXPECT_NEAR(c.normal.y(), 1.0, 1e-14);
            // weight per unit depth times dt (1e-9 rel)
            EXPECT_NEAR(c.impulse.y(), s.mass(c.i) * 9.81 * dt, 1e-9 * s.mass(c.i) * 9.81 * dt);
            EXPECT_GT(s.contactConductance(c, dt), 0.0);
        }
    }
    EXPECT_EQ(walls, 2);
    // cohesion holds a disc hanging under a ceiling: F_c > m g
    System h(2);
    const int mh = h.addMaterial({1000, 0.5});
    h.addGrain(Vec3(0, -0.1, 0), 0.1, mh);
    h.addPlane(Vec3(0, 0, 0), Vec3(0, -1, 0));
    h.setGravity(Vec3(0, -9.81, 0));
    h.setCohesion([](int, int j) { return j == -1; }, 2.0 * h.mass(0) * 9.81);
    for (int k = 0; k < 100; ++k) h.step(dt);
    EXPECT_NEAR(h.positions()[0].y(), -0.1, 1e-9);
    // too weak cohesion: it falls
    h.setCohesion([](int, int) { return true; }, 0.5 * h.mass(0) * 9.81);
    for (int k = 0; k < 100; ++k) h.step(dt);
    EXPECT_LT(h.positions()[0].y(), -0.11);
}

// setMaterial (used by grainCloud when constant/grainProperties differs from a
// saved state): the grains of that material get the new mass and moment of
// inertia, and the wall carries the new weight.  Reference: statics, the
// normal impulse of a disc resting on a plane is m g dt with m = rho pi r^2
// per unit depth (2D) or rho 4/3 pi r^3 (3D); I = m r^2/2 (disc), 2 m r^2/5
// (sphere).
TEST(Materials, SetMaterialRecomputesMassAndWeight)
{
    const double pi = 3.14159265358979323846, r = 0.1, g = 9.81, dt = 1e-3;
    for (const int dim : {2, 3})
    {
        System s(dim);
        const int m0 = s.addMaterial({3200, 0.3});
        const int m1 = s.addMaterial({1000, 0.3});
        s.addGrain(Vec3(0, r, 0), r, m0);
        s.addGrain(Vec3(3 * r, r, 0), r, m1);
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.setGravity(Vec3(0, -g, 0));
        const double shape = dim == 2 ? pi * r * r : 4.0 / 3.0 * pi * r * r * r;
        const double iFactor = dim == 2 ? 0.5 : 0.4;
        EXPECT_NEAR(s.mass(0), 3200 * shape, 1e-12 * 3200 * shape);
        Material changed{1600, 0.3, 1e11, 0.35, 234, 290};
        s.setMaterial(m0, changed);
        EXPECT_EQ(s.material(m0).youngModulus, 1e11);
        EXPECT_EQ(s.material(m0).heatCapacity, 290);
        EXPECT_NEAR(s.mass(0), 1600 * shape, 1e-12 * 1600 * shape);
        EXPECT_NEAR(s.inertia(0), iFactor * 1600 * shape * r * r, 1e-12 * 1600 * shape * r * r);
        EXPECT_NEAR(s.mass(1), 1000 * shape, 1e-12 * 1000 * shape); // other material untouched
        for (int k = 0; k < 5; ++k) s.step(dt);
        int seen = 0;
        for (const auto& c : s.contacts())
        {
            if (c.j != -1) continue;
            ++seen;
            const double rho = c.i == 0 ? 1600 : 1000;
            EXPECT_NEAR(c.impulse.y(), rho * shape * g * dt, 1e-9 * rho * shape * g * dt) << "dim " << dim;
        }
        EXPECT_EQ(seen, 2);
        // errors: unknown id, invalid material (the old one stays)
        EXPECT_THROW(s.setMaterial(2, changed), InputError);
        EXPECT_THROW(s.setMaterial(-1, changed), InputError);
        try
        {
            s.setMaterial(m0, {0.0, 0.3});
            FAIL();
        }
        catch (const InputError& e)
        {
            EXPECT_NE(std::string(e.what()).find("setMaterial: density"), std::string::npos) << e.what();
        }
        EXPECT_EQ(s.material(m0).density, 1600);
        EXPECT_NEAR(s.mass(0), 1600 * shape, 1e-12 * 1600 * shape);
    }
}

// Consistency check of the kept contact records: a contact with a wall is
// kept as body N + k; a grain added after a step must not turn it into a
// contact with the new grain (the record is shifted with N, as removal
// compacts it), so the view still names the wall and the floor's impulse is
// still there as the warm start (the next step converges at once).
TEST(Contacts, AddingAGrainKeepsWallContacts)
{
    System s(2);
    const int m = s.addMaterial({2500, 0.3});
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.addGrain(Vec3(0, 0.01, 0), 0.01, m);
    s.setGravity(Vec3(0, -9.81, 0));
    for (int k = 0; k < 3; ++k) s.step(1e-3);
    ASSERT_EQ(s.contacts().size(), 1u);
    EXPECT_EQ(s.contacts()[0].j, -1);
    s.addGrain(Vec3(1, 1, 0), 0.01, m); // far away
    s.addGrain(Vec3(2, 1, 0), 0.01, m); // two grains added before the records are used
    ASSERT_EQ(s.contacts().size(), 1u);
    EXPECT_EQ(s.contacts()[0].j, -1);
    // a state written before the next step keeps the wall contact too
    s.writeHDF5("nscd_added_grains.h5");
    const System back = System::readHDF5("nscd_added_grains.h5");
    std::remove("nscd_added_grains.h5");
    ASSERT_EQ(back.contacts().size(), 1u);
    EXPECT_EQ(back.contacts()[0].j, -1);
    const StepReport r = s.step(1e-3);
    EXPECT_LE(r.sweeps, 1);
    EXPECT_NEAR(s.contacts()[0].impulse.y(), s.mass(0) * 9.81 * 1e-3, 1e-9 * s.mass(0) * 9.81 * 1e-3);
}
