// SPDX-License-Identifier: GPL-3.0-or-later
// Contact compliance (Material::compliance, relativeCompliance): the normal
// law g^+ + c F_n >= 0, F_n >= 0, complementary (an implicit, backward Euler,
// spring of compliance c in compression).
//
// References, independent of the solver:
//  - statics: in a column at rest on a floor every contact carries the
//    weight of the grains above it (momentum balance): checked on the
//    contact impulses (floor = weight). The overlap of a contact being c
//    times that weight is Hooke's law with c's own definition, so the
//    overlap checks are consistency checks of the law's implementation
//    (the positions give the overlaps; nothing is read from the solver's
//    gaps), their load from statics is the independent part;
//  - energy: backward Euler on a convex potential dissipates,
//    E^{n+1} - E^n = -m |v^{n+1} - v^n|^2/2 + (convexity gap) <= 0 with
//    E = m |v|^2/2 + m g y + delta^2/(2 c), delta the overlap (E. Hairer,
//    C. Lubich, G. Wanner, Geometric Numerical Integration, 2006, on the
//    implicit Euler method; here with the unilateral spring, still convex).
// Tolerances: the solver tolerance is 1e-11 d_min, far below the quantities
// checked; the relative bounds below are stated where they are used.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

using namespace nscd;

namespace
{
constexpr double rad = 1e-3;  // grain radius [m]
constexpr double rho = 2500;  // [kg/m^3]
constexpr double gAcc = 9.81; // [m/s^2]

/// A column of n discs (dim 2) or spheres (dim 3) touching each other and
/// the floor y = 0 (gaps exactly 0), material mat.
System column(int dim, int n, const Material& mat)
{
    System s(dim);
    const int m = s.addMaterial(mat);
    for (int k = 0; k < n; ++k) s.addGrain(Vec3(0, rad + 2 * rad * k, 0), rad, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -gAcc, 0));
    s.settings().tolerance = 1e-11;
    // the law exactly: no slop band (Settings::overlapSlop; its bound is
    // checked by SlopBandHoldsTheOverlapsWithinTheBand)
    s.settings().overlapSlop = 0;
    return s;
}

System column2D(int n, const Material& mat) { return column(2, n, mat); }

/// Overlaps from the positions: [0] with the floor, [k] between grains k-1, k.
std::vector<double> overlaps(const System& s)
{
    const auto& x = s.positions();
    std::vector<double> ov(x.size());
    ov[0] = rad - x[0].y();
    for (std::size_t k = 1; k < x.size(); ++k) ov[k] = 2 * rad - (x[k].y() - x[k - 1].y());
    return ov;
}
} // namespace

// A resting column of 20 discs with compliance c: the overlap of each
// contact equals c times the weight above it (per unit depth), to 1e-6;
// the floor carries the column's weight (1e-6: the slowest mode of the
// column still decays after 0.3 s).
TEST(Compliance, RestingColumnOverlapIsLoadTimesCompliance2D)
{
    const int n = 20;
    const double mass = rho * M_PI * rad * rad; // [kg/m]
    // bottom overlap 1e-3 r under the column's weight
    const double c = 1e-3 * rad / (n * mass * gAcc); // [m^2/N]
    Material mat{rho, 0.3};
    mat.compliance = c;
    System s = column2D(n, mat);
    const double dt = 1e-4;
    for (int k = 0; k < 3000; ++k) ASSERT_TRUE(s.step(dt).converged) << "step " << k;
    const std::vector<double> ov = overlaps(s);
    for (int k = 0; k < n; ++k)
    {
        const double expected = c * (n - k) * mass * gAcc; // weight of grains k..n-1
        EXPECT_NEAR(ov[k], expected, 1e-6 * expected) << "contact below grain " << k;
    }
    // the floor's impulse is the weight (statics, independent of c)
    for (const auto& v : s.contacts())
        if (v.j < 0) EXPECT_NEAR(v.impulse.y() / dt, n * mass * gAcc, 1e-6 * n * mass * gAcc);
}

// The same with relativeCompliance beta in 3D (spheres on a plane): the
// compliance is beta W_nn dt^2, W_nn = 2/m between grains, 1/m at the floor.
TEST(Compliance, RestingColumnOverlapIsLoadTimesRelativeCompliance3D)
{
    const int n = 6;
    const double mass = rho * 4.0 / 3.0 * M_PI * rad * rad * rad;
    const double beta = 1e-2, dt = 1e-4;
    Material mat{rho, 0.3};
    mat.relativeCompliance = beta;
    System s = column(3, n, mat);
    for (int k = 0; k < 2000; ++k) ASSERT_TRUE(s.step(dt).converged) << "step " << k;
    const std::vector<double> ov = overlaps(s);
    for (int k = 0; k < n; ++k)
    {
        const double wnn = k == 0 ? 1 / mass : 2 / mass;
        const double expected = beta * wnn * dt * dt * (n - k) * mass * gAcc;
        // the overlaps (~4e-9 m) are differences of centres ~1e-2 m: the
        // round-off of the positions over the run is ~1e-14 m
        EXPECT_NEAR(ov[k], expected, 1e-5 * expected) << "contact below grain " << k;
    }
}

// A column of 20 discs with relativeCompliance beta, at rest under step(dt),
// then advanced by advance(dt, fraction) with the fraction that splits each
// step into 10 sub-steps (gravity's velocity change over a step moves a
// grain by g dt^2 = 9.81 fraction d_min): the sub-steps keep the spring of
// the step dt, c = beta W_nn dt^2 (Material.H), so the column stays at rest
// with the overlaps of that law. A sub-step law beta W_nn (dt/10)^2 would
// find every overlap 100x its equilibrium and push them out in one
// sub-step, the speeds adding up over the contacts below (measured with
// step(dt/10), the contrast at the end: 0.15 m/s; advance(): 6e-10 m/s):
// the rest bound (speed <= g dt) is the independent check (a column
// at rest on a floor, momentum balance); the overlaps against c times the
// weight above are the law's consistency check, as above.
TEST(Compliance, SubSteppedAdvanceKeepsTheStepsRelativeCompliance)
{
    const int n = 20;
    const double mass = rho * M_PI * rad * rad; // [kg/m]
    const double beta = 1e-2, dt = 1e-3;
    Material mat{rho, 0.3};
    mat.relativeCompliance = beta;
    System s = column2D(n, mat);
    for (int k = 0; k < 600; ++k) ASSERT_TRUE(s.step(dt).converged) << "step " << k;
    auto expectLaw = [&](const std::string& when)
    {
        const std::vector<double> ov = overlaps(s);
        for (int k = 0; k < n; ++k)
        {
            const double wnn = k == 0 ? 1 / mass : 2 / mass;
            const double expected = beta * wnn * dt * dt * (n - k) * mass * gAcc;
            EXPECT_NEAR(ov[k], expected, 1e-4 * expected) << when << ", contact below grain " << k;
        }
    };
    expectLaw("after step()");
    // fraction such that g dt^2 / (fraction d_min) = 9.81: 10 sub-steps a step
    const double fraction = gAcc * dt * dt / (9.81 * 2 * rad);
    double vmax = 0;
    for (int k = 0; k < 50; ++k)
    {
        const StepReport r = s.advance(dt, fraction);
        ASSERT_TRUE(r.converged) << "advance " << k;
        ASSERT_EQ(r.substeps, 10) << "advance " << k;
        for (const Vec3& v : s.velocities()) vmax = std::max(vmax, v.norm());
    }
    EXPECT_LE(vmax, gAcc * dt) << "the column left rest when the steps were split";
    expectLaw("after advance()");
    EXPECT_EQ(s.complianceStep(), 0.0); // advance() restores the caller's (none)
    EXPECT_THROW(s.setComplianceStep(-1), InputError);
    // the contrast: the same column stepped by step(dt/10) takes the law of
    // the short step, beta W_nn (dt/10)^2, and leaves rest (the bound above
    // tells the two laws apart)
    System t = column2D(n, mat);
    for (int k = 0; k < 600; ++k) ASSERT_TRUE(t.step(dt).converged) << "step " << k;
    double vShort = 0;
    for (int k = 0; k < 10; ++k)
    {
        t.step(dt / 10);
        for (const Vec3& v : t.velocities()) vShort = std::max(vShort, v.norm());
    }
    EXPECT_GT(vShort, 10 * gAcc * dt) << "step(dt/10) should push the overlaps of the dt law out";
    std::printf("column at rest: max speed %.3g m/s with advance(dt) in 10 sub-steps, %.3g m/s with "
                "step(dt/10) (g dt = %.3g m/s)\n",
                vmax, vShort, gAcc * dt);
}

// A disc dropped 5 mm onto a compliant floor (stiffness such that omega dt
// = 0.3: it bounces) never gains energy in a step, and comes to rest at
// the static overlap c m g.
TEST(Compliance, DroppedGrainOnCompliantFloorCreatesNoEnergy)
{
    const double mass = rho * M_PI * rad * rad, dt = 1e-4;
    const double omega = 0.3 / dt;
    const double c = 1 / (omega * omega * mass); // [m^2/N]
    Material mat{rho, 0.3};
    mat.compliance = c;
    System s(2);
    const int m = s.addMaterial(mat);
    const double y0 = rad + 5e-3;
    s.addGrain(Vec3(0, y0, 0), rad, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -gAcc, 0));
    s.settings().tolerance = 1e-11;
    s.settings().overlapSlop = 0;
    auto energy = [&]()
    {
        const double y = s.positions()[0].y(), v2 = s.velocities()[0].squaredNorm();
        const double delta = std::max(0.0, rad - y);
        return 0.5 * mass * v2 + mass * gAcc * y + 0.5 * delta * delta / c;
    };
    double e = energy();
    const double e0 = e;
    double maxOverlap = 0;
    int rises = 0;
    for (int k = 0; k < 4000; ++k)
    {
        ASSERT_TRUE(s.step(dt).converged);
        const double en = energy();
        maxOverlap = std::max(maxOverlap, rad - s.positions()[0].y());
        // round-off: 1e-12 of the initial energy
        if (en > e + 1e-12 * e0) ++rises;
        EXPECT_LE(en, e + 1e-12 * e0) << "step " << k;
        e = en;
    }
    EXPECT_EQ(rises, 0);
    // the contact was compliant (overlap well beyond the hard law's slop)
    EXPECT_GT(maxOverlap, 1e-2 * rad);
    // at rest on the floor at the static overlap c m g
    EXPECT_LT(s.velocities()[0].norm(), 1e-6);
    EXPECT_NEAR(rad - s.positions()[0].y(), c * mass * gAcc, 1e-3 * c * mass * gAcc);
}

// Mixed pair: a compliant grain on a hard one takes the mean compliance.
TEST(Compliance, MixedPairTakesTheMeanCompliance)
{
    const double mass = rho * M_PI * rad * rad, dt = 1e-4;
    System s(2);
    Material hard{rho, 0.3}, soft{rho, 0.3};
    soft.compliance = 2e-6;
    const int mh = s.addMaterial(hard), ms = s.addMaterial(soft);
    s.addGrain(Vec3(0, rad, 0), rad, mh);     // hard grain on the floor
    s.addGrain(Vec3(0, 3 * rad, 0), rad, ms); // soft grain on it
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -gAcc, 0));
    s.settings().tolerance = 1e-11;
    s.settings().overlapSlop = 0;
    for (int k = 0; k < 3000; ++k) s.step(dt);
    const std::vector<double> ov = overlaps(s);
    EXPECT_LT(ov[0], 1e-4 * rad); // hard floor contact: within the slop band
    EXPECT_NEAR(ov[1], 0.5 * soft.compliance * mass * gAcc, 1e-6 * soft.compliance * mass * gAcc);
}

// With the slop band (Settings::overlapSlop, default 1e-4 r_min) a compliant
// contact holds departures from its equilibrium below the band: the column's
// overlaps are c x weight above to within the band, and the floor still
// carries the weight (statics).
TEST(Compliance, SlopBandHoldsTheOverlapsWithinTheBand)
{
    const int n = 20;
    const double mass = rho * M_PI * rad * rad, dt = 1e-4;
    const double c = 1e-3 * rad / (n * mass * gAcc);
    Material mat{rho, 0.3};
    mat.compliance = c;
    System s = column2D(n, mat);
    s.settings().overlapSlop = 1e-4;
    const double band = 1e-4 * rad;
    for (int k = 0; k < 3000; ++k) ASSERT_TRUE(s.step(dt).converged) << "step " << k;
    const std::vector<double> ov = overlaps(s);
    for (int k = 0; k < n; ++k)
        EXPECT_NEAR(ov[k], c * (n - k) * mass * gAcc, band * (1 + 1e-6)) << "contact below grain " << k;
    for (const auto& v : s.contacts())
        if (v.j < 0) EXPECT_NEAR(v.impulse.y() / dt, n * mass * gAcc, 1e-6 * n * mass * gAcc);
}

// Bad settings are InputErrors naming the field; the restart state keeps
// the compliance (bit-exact continuation).
TEST(Compliance, BadInputAndRestart)
{
    System s(2);
    Material bad{rho, 0.3};
    bad.compliance = -1;
    try
    {
        s.addMaterial(bad);
        FAIL() << "no InputError";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("compliance"), std::string::npos);
    }
    bad.compliance = 1e-6;
    bad.relativeCompliance = 1e-3;
    EXPECT_THROW(s.addMaterial(bad), InputError);
    bad.compliance = 0;
    bad.relativeCompliance = std::nan("");
    EXPECT_THROW(s.addMaterial(bad), InputError);

    Material mat{rho, 0.3};
    mat.compliance = 1e-6;
    System a = column2D(5, mat);
    a.settings().method = System::Settings::Method::APGD;
    try
    {
        a.step(1e-4);
        FAIL() << "no InputError";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("APGD"), std::string::npos);
    }
    a.settings().method = System::Settings::Method::NLGS;
    for (int k = 0; k < 50; ++k) a.step(1e-4);
    const std::string file = "compliance_restart.h5";
    a.writeHDF5(file);
    System b = System::readHDF5(file);
    EXPECT_EQ(b.material(0).compliance, mat.compliance);
    EXPECT_EQ(b.material(0).relativeCompliance, 0.0);
    for (int k = 0; k < 20; ++k)
    {
        a.step(1e-4);
        b.step(1e-4);
    }
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        EXPECT_EQ(a.positions()[i], b.positions()[i]);
        EXPECT_EQ(a.velocities()[i], b.velocities()[i]);
    }
    std::remove(file.c_str());
}

// A compliant column at rest carries its weight by overlaps (Hooke:
// c x the weight above each contact) up to 5e-2 r, 50 times the default
// overlapTolerance (1e-3 r_min):
// the state is admitted by checkInitialOverlaps with its contact impulses
// (and after an HDF5 restart), since each overlap is its contact's law
// under its load; the same positions without impulses are an InputError
// (a packing whose overlaps nothing carries).
TEST(Compliance, LoadedCompliantOverlapsPassTheInitialCheck)
{
    const int n = 20;
    const double mass = rho * M_PI * rad * rad; // [kg/m]
    Material mat{rho, 0.3};
    // bottom overlap 5e-2 r
    mat.compliance = 5e-2 * rad / (n * mass * gAcc);
    System s = column2D(n, mat);
    for (int k = 0; k < 2000; ++k) ASSERT_TRUE(s.step(1e-4).converged) << "step " << k;
    const std::vector<double> ov = overlaps(s);
    ASSERT_GT(ov[0], 4 * s.settings().overlapTolerance * rad); // the floor contact
    EXPECT_NO_THROW(s.checkInitialOverlaps());
    const std::string file = "compliance_overlaps.h5";
    s.writeHDF5(file);
    System b = System::readHDF5(file);
    std::remove(file.c_str());
    EXPECT_NO_THROW(b.checkInitialOverlaps());

    System unloaded(2);
    const int m = unloaded.addMaterial(mat);
    for (const Vec3& x : s.positions()) unloaded.addGrain(x, rad, m);
    unloaded.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    try
    {
        unloaded.checkInitialOverlaps();
        FAIL() << "no InputError";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("overlap"), std::string::npos);
    }
}

// A compliant column settled at one density and given a lighter one
// (setMaterial, as a run with porous grains does to a bed settled solid):
// its contact impulses scale with the density (the weight carried), so
// with the same absolute compliance the law's overlap c F_n halves and the
// settled overlaps are refused, the message saying why and what keeps them;
// the compliance divided by the density ratio keeps them (c F_n unchanged:
// the law's own overlap at rest, an identity of the law g + c F_n = 0).
TEST(Compliance, DensityChangeNeedsTheCompliancePerRatio)
{
    const int n = 20;
    const double mass = rho * M_PI * rad * rad; // [kg/m]
    Material mat{rho, 0.3};
    mat.compliance = 5e-2 * rad / (n * mass * gAcc); // bottom overlap 5e-2 r
    System s = column2D(n, mat);
    for (int k = 0; k < 2000; ++k) ASSERT_TRUE(s.step(1e-4).converged) << "step " << k;
    const std::string file = "compliance_density.h5";
    s.writeHDF5(file);
    // the check's message for the saved column given material m ("" if none)
    auto refusal = [&](const Material& m)
    {
        System b = System::readHDF5(file);
        b.setMaterial(0, m);
        std::string what;
        try
        {
            b.checkInitialOverlaps();
        }
        catch (const InputError& e)
        {
            what = e.what();
        }
        return what;
    };
    Material lighter = mat;
    lighter.density = 0.5 * rho;
    const std::string what = refusal(lighter);
    EXPECT_NE(what.find("scaled by 0.5"), std::string::npos) << what;
    EXPECT_NE(what.find("absolute compliance divided by 0.5"), std::string::npos) << what;
    lighter.compliance = mat.compliance / 0.5;
    EXPECT_EQ(refusal(lighter), "");
    std::remove(file.c_str());
}

// A compliant sphere at rest in the corner of one triangulated wall (floor and
// side face of the same surface) touches it twice; the initial-overlap check
// takes the grain's largest overlap with the wall, so it must admit the law's
// largest overlap of the two contacts, whichever comes last (the second run
// swaps which face carries the larger load).
TEST(Compliance, LoadedCornerOfOneWallPassesTheInitialCheck)
{
    for (const Vec3 g : {Vec3(-2, -9, 0), Vec3(-9, -2, 0)})
    {
        System s(3);
        Material mat{rho, 0.0};
        const double mass = rho * 4.0 / 3.0 * M_PI * rad * rad * rad;
        mat.compliance = 0.05 * rad / (mass * 9.0); // ~5 % r under the larger load
        const int m = s.addMaterial(mat);
        s.addGrain(Vec3(rad, rad, 5 * rad), rad, m);
        const double L = 10 * rad;
        // floor y = 0 and side x = 0, one surface, normals into the domain
        s.addTriangulatedSurface(
            {Vec3(0, 0, 0), Vec3(L, 0, 0), Vec3(L, 0, L), Vec3(0, 0, L), Vec3(0, L, 0), Vec3(0, L, L)},
            {{0, 3, 2}, {0, 2, 1}, {0, 4, 5}, {0, 5, 3}});
        s.setGravity(g);
        for (int k = 0; k < 500; ++k) ASSERT_TRUE(s.step(1e-4).converged) << "step " << k;
        const Vec3 x = s.positions()[0];
        const double big = rad - std::min(x.x(), x.y()), small = rad - std::max(x.x(), x.y());
        ASSERT_GT(small, 0);                                     // two loaded contacts,
        ASSERT_GT(big, 2 * small);                               // unequal,
        ASSERT_GT(big, 4 * s.settings().overlapTolerance * rad); // above the tolerance
        EXPECT_NO_THROW(s.checkInitialOverlaps());
    }
}

// The RMS stopping test (Settings::Convergence::RMS, LMGC90's Quad norm) on
// a frictionless column of 30 discs at rest on the floor, hard contacts:
// each contact carries the weight of the discs above it (statics), checked
// to 1e-3 per contact and 2e-4 in RMS. The test measures the last pass's
// updates, which understate the error of the column's slow mode by about
// 1/(1 - rho) = 4 N^2/pi^2 (365 here): at rmsTolerance 1e-4 the forces of
// this column were measured 0.0045 N/m off at every contact (6 % of the top
// contact's load), so the tolerance the statics need is 1e-6
// (docs/validation/contactCompliance.md).
TEST(Compliance, RmsConvergenceRestingColumnForcesMatchTheWeight)
{
    const int n = 30;
    const double mass = rho * M_PI * rad * rad, dt = 1e-4;
    System s = column2D(n, Material{rho, 0.0});
    s.settings().overlapSlop = 1e-4; // the library's default band
    s.settings().convergence = System::Settings::Convergence::RMS;
    s.settings().rmsTolerance = 1e-6;
    StepReport last;
    for (int k = 0; k < 300; ++k)
    {
        last = s.step(dt);
        ASSERT_TRUE(last.converged) << "step " << k;
    }
    EXPECT_LE(last.rmsResidual, 1e-6);
    // contact force on the upper grain of each contact = weight above it
    std::vector<double> force(n, 0.0);
    for (const auto& v : s.contacts())
    {
        const int upper = v.j < 0 ? v.i : std::max(v.i, v.j);
        force[upper] += std::abs(v.impulse.y()) / dt;
    }
    double sum2 = 0;
    for (int k = 0; k < n; ++k)
    {
        const double w = (n - k) * mass * gAcc;
        EXPECT_NEAR(force[k], w, 1e-3 * w) << "contact below grain " << k;
        sum2 += (force[k] - w) * (force[k] - w) / (w * w);
    }
    EXPECT_LE(std::sqrt(sum2 / n), 2e-4);
}

TEST(Compliance, RmsConvergenceBadSettings)
{
    System s = column2D(3, Material{rho, 0.3});
    s.settings().convergence = System::Settings::Convergence::RMS;
    s.settings().rmsTolerance = 0;
    EXPECT_THROW(s.step(1e-4), InputError);
    s.settings().rmsTolerance = 1e-4;
    s.settings().method = System::Settings::Method::APGD;
    try
    {
        s.step(1e-4);
        FAIL() << "no InputError";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("RMS"), std::string::npos);
    }
    s.settings().method = System::Settings::Method::NLGS;
    EXPECT_NO_THROW(s.step(1e-4));
}
