// SPDX-License-Identifier: GPL-3.0-or-later
// Grain temperatures (thesis eq. 4.1-4.3): contact conduction, walls and
// fixed-temperature grains, sources and exchange, conservation, HDF5 state.
#include "nscd/System.H"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

using namespace nscd;

namespace
{
constexpr double pi = 3.14159265358979323846;

// heat-conducting materials (SI): rho, mu, E, nu, k, c
Material matA(double c) { return {1000, 0.3, 6e10, 0.22, 100, c}; }
Material matB(double c) { return {2000, 0.3, 3e10, 0.30, 50, c}; }

double relErr(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }
} // namespace

// Reference: two grains pressed together by opposite external forces F (no
// gravity): the normal impulse is F dt, the conductance H of eq. 4.2 is
// constant, and C_A dT_A/dt = H (T_B - T_A), C_B dT_B/dt = H (T_A - T_B)
// (C = m c). The mass-weighted mean (C_A T_A + C_B T_B)/(C_A + C_B) is
// conserved and D = T_A - T_B decays as exp(-kappa t), kappa = H (1/C_A +
// 1/C_B); the backward-Euler scheme gives exactly D_n = D_0 (1 + kappa dt)^-n.
// Tolerances: discrete closed form 1e-10 relative (solver tolerance 1e-12),
// continuous one kappa t kappa dt (the O(dt) error of backward Euler, ~1e-3),
// heat content 1e-12 relative. A second run with kappa dt = 1e8 (stiff
// contact) must relax to the mean in one step without oscillation.
TEST(Heat, TwoGrainsRelaxToMassWeightedMean)
{
    for (int dim : {2, 3})
    {
        for (double stiff : {1.0, 1e11})
        {
            System s(dim);
            // heat capacities chosen so that kappa ~ 1/s (and ~1e-8 / s x 1e11 stiff)
            const double cA = (dim == 2 ? 0.3 : 30) / stiff, cB = (dim == 2 ? 0.5 : 50) / stiff;
            const int mA = s.addMaterial(matA(cA));
            const int mB = s.addMaterial(matB(cB));
            const double rA = 0.01, rB = 0.015, F = 1.0;
            const int a = s.addGrain(Vec3(-rA, 0, 0), rA, mA);
            const int b = s.addGrain(Vec3(rB, 0, 0), rB, mB);
            s.setExternalForce(a, Vec3(F, 0, 0));
            s.setExternalForce(b, Vec3(-F, 0, 0));
            s.temperatures()[a] = 400;
            s.temperatures()[b] = 300;
            const double CA = s.mass(a) * cA, CB = s.mass(b) * cB;
            const double E0 = CA * 400 + CB * 300;
            EXPECT_NEAR(s.heatContent(), E0, 1e-15 * E0);
            // counted grains only (a subdomain's owned ones): each grain's C T
            // (consistency check of the flag argument, no physics)
            const std::vector<char> onlyA{1, 0}, onlyB{0, 1};
            EXPECT_NEAR(s.heatContent(&onlyA), CA * 400, 1e-15 * E0);
            EXPECT_NEAR(s.heatContent(&onlyB), CB * 300, 1e-15 * E0);
            const std::vector<char> wrongSize{1};
            EXPECT_THROW(s.heatContent(&wrongSize), InputError);
            const double mean = E0 / (CA + CB);
            const double dt = 1e-3;
            double D = 100, kappa0 = 0, maxDiscrete = 0, maxCont = 0, maxCons = 0, contBound = 0;
            int n = stiff > 1 ? 1 : 0;
            for (int k = 0; k < (n ? n : 1000000); ++k)
            {
                const StepReport r = s.step(dt);
                ASSERT_EQ(s.nContacts(), 1u);
                const auto c = s.contacts()[0];
                EXPECT_NEAR(c.impulse.dot(c.normal), F * dt, 1e-9 * F * dt);
                const double H = s.contactConductance(c, dt);
                const double kappa = H * (1 / CA + 1 / CB);
                if (k == 0)
                {
                    kappa0 = kappa;
                    if (!n) n = int(std::lround(2 / (kappa * dt)));
                }
                EXPECT_NEAR(kappa, kappa0, 1e-12 * kappa0);
                D /= 1 + kappa * dt; // discrete closed form with this step's H
                const double Ds = s.temperatures()[a] - s.temperatures()[b];
                maxDiscrete = std::max(maxDiscrete, std::abs(Ds - D) / 100);
                const double t = (k + 1) * dt;
                const double Dc = 100 * std::exp(-kappa0 * t);
                maxCont = std::max(maxCont, std::abs(Ds - Dc) / Dc);
                contBound = kappa0 * t * kappa0 * dt;
                maxCons = std::max(maxCons, std::abs(s.heatContent() - E0) / E0);
                EXPECT_EQ(r.wallHeat, 0.0);
                EXPECT_EQ(r.fixedGrainHeat, 0.0);
                EXPECT_EQ(r.sourceHeat, 0.0);
            }
            EXPECT_LT(maxCons, 1e-12) << "dim " << dim << " stiff " << stiff;
            if (stiff == 1)
            {
                EXPECT_LT(maxDiscrete, 1e-10) << "dim " << dim;
                EXPECT_LT(kappa0 * dt, 2e-3);
                EXPECT_LT(maxCont, contBound) << "dim " << dim;
                std::printf("[ measured ] dim %d: kappa %.4g /s, %d steps, |D - D_discrete|/D0 %.2e, "
                            "|D/D_exact - 1| %.2e (bound %.2e), heat %.2e\n",
                            dim, kappa0, n, maxDiscrete, maxCont, contBound, maxCons);
            }
            else
            {
                // kappa dt = O(1e8): one step reaches the mean. The flux-form
                // update evaluates H (T_b* - T_a*) from rounded T* ~ 400 K, so
                // its round-off is ~ eps kappa dt 400 K (here ~1e-5 K): the
                // tolerance is 1e-15 kappa dt 400 K (~5 eps).
                EXPECT_GT(kappa0 * dt, 1e6);
                const double tol = 1e-15 * kappa0 * dt * 400;
                EXPECT_NEAR(s.temperatures()[a], mean, tol);
                EXPECT_NEAR(s.temperatures()[b], mean, tol);
                EXPECT_LE(s.temperatures()[a], 400);
                EXPECT_GE(s.temperatures()[b], 300);
                std::printf(
                    "[ measured ] dim %d stiff: kappa dt %.3g, T - mean %.2e %.2e (tol %.1e), heat %.2e\n",
                    dim, kappa0 * dt, s.temperatures()[a] - mean, s.temperatures()[b] - mean, tol, maxCons);
            }
        }
    }
}

// Reference: the conductance of eq. 4.2-4.3 evaluated by hand, for a grain
// pair (harmonic mean of k, 1/E* and 1/d* sums) and a grain on a wall (d* =
// d_i, E* from the grain only, k_s = k_i); 1e-14 relative.
TEST(Heat, ConductanceFormula)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const Material A = matA(1), B = matB(1);
        const int mA = s.addMaterial(A), mB = s.addMaterial(B);
        const double rA = 0.01, rB = 0.015;
        s.addGrain(Vec3(0, rA, 0), rA, mA);          // on the floor
        s.addGrain(Vec3(0, 2 * rA + rB, 0), rB, mB); // on top of it
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        s.setGravity(Vec3(0, -9.81, 0));
        const double dt = 1e-3;
        s.step(dt);
        int seen = 0;
        for (const auto& c : s.contacts())
        {
            const double rn = c.impulse.dot(c.normal);
            if (!(rn > 0)) continue;
            double ks, Es, ds;
            if (c.j < 0)
            {
                const Material& m = c.i == 0 ? A : B;
                ks = m.conductivity;
                Es = m.youngModulus / (1 - m.poissonRatio * m.poissonRatio);
                ds = 2 * (c.i == 0 ? rA : rB);
            }
            else
            {
                ks = 2 / (1 / A.conductivity + 1 / B.conductivity);
                Es = 1
                     / ((1 - A.poissonRatio * A.poissonRatio) / A.youngModulus
                        + (1 - B.poissonRatio * B.poissonRatio) / B.youngModulus);
                ds = 1 / (1 / (2 * rA) + 1 / (2 * rB));
            }
            const double H = 4 * ks * std::pow(rn * ds / (2 * pi * Es * dt), 0.25);
            EXPECT_NEAR(s.contactConductance(c, dt), H, 1e-14 * H);
            ++seen;
        }
        EXPECT_EQ(seen, 2); // A on the floor, B on A
    }
}

namespace
{
struct ChainResult
{
    double maxErr;
    double q;
    double wallQ;
    double bathQ;
    double nonLinear;
};

// Vertical column of n grains on a floor wall at Tbot, the top grain held at
// Ttop (fixed temperature), gravity: the load, hence H_k, grows downwards.
ChainResult column(int dim, int n, double Tbot, double Ttop)
{
    System s(dim);
    const int m = s.addMaterial(matA(1e-3));
    std::vector<double> r(n);
    double y = 0;
    for (int k = 0; k < n; ++k)
    {
        r[k] = k % 2 ? 0.008 : 0.01;
        y += r[k];
        s.addGrain(Vec3(0, y, 0), r[k], m);
        y += r[k];
    }
    const int floor = s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setWallTemperature(floor, Tbot);
    s.setFixedTemperature(n - 1);
    for (int k = 0; k < n; ++k) s.temperatures()[k] = Ttop;
    s.setGravity(Vec3(0, -9.81, 0));
    // the contact forces (hence H) must be steady to 1e-9: with the default
    // tolerance (1e-6 d_min on |W dr| dt) they fluctuate by ~0.1 %
    s.settings().tolerance = 1e-12;
    const double dt = 1e-3;
    StepReport rep;
    for (int k = 0; k < 1500; ++k) rep = s.step(dt);
    // expected profile from the last step's conductances (series resistances)
    std::vector<double> R(n, 0.0); // R[k]: resistance below grain k
    for (const auto& c : s.contacts())
    {
        const double H = s.contactConductance(c, dt);
        if (!(H > 0)) continue;
        if (c.j == -(floor + 1))
            R[c.i] = 1 / H;
        else if (c.j >= 0)
            R[std::max(c.i, c.j)] = 1 / H;
    }
    double Rsum = 0;
    for (double a : R) Rsum += a;
    const double q = (Tbot - Ttop) / Rsum;
    ChainResult out{0, q, rep.wallHeat / dt, -rep.fixedGrainHeat / dt, 0};
    double T = Tbot;
    for (int k = 0; k < n; ++k)
    {
        T -= q * R[k];
        out.maxErr = std::max(out.maxErr, std::abs(s.temperatures()[k] - T));
        const double lin = Tbot + (Ttop - Tbot) * (k + 1) / double(n);
        out.nonLinear = std::max(out.nonLinear, std::abs(T - lin));
    }
    return out;
}

// Horizontal chain of n equal grains, no gravity: grain 0 (held at T0) is
// pushed by F towards grain n-1, a fixed (infinite-mass) grain held at T1.
// Every contact carries F: uniform H, linear profile. Returns the max error
// to the linear profile; seriesErr: to the series-resistance profile.
double pressedChain(int dim, int n, double T0, double T1, double& q, double& bathIn, double& seriesErr)
{
    System s(dim);
    const int m = s.addMaterial(matA(1e-3));
    const double r = 0.01;
    for (int k = 0; k < n; ++k) s.addGrain(Vec3((2 * k + 1) * r, 0, 0), r, m, k == n - 1);
    s.setExternalForce(0, Vec3(1.0, 0, 0));
    s.setFixedTemperature(0);
    s.setFixedTemperature(n - 1);
    for (int k = 0; k < n; ++k) s.temperatures()[k] = T0;
    s.temperatures()[n - 1] = T1;
    s.settings().tolerance = 1e-12; // steady contact forces (see column)
    const double dt = 1e-3;
    StepReport rep;
    for (int k = 0; k < 1500; ++k) rep = s.step(dt);
    EXPECT_EQ(s.nContacts(), std::size_t(n - 1));
    std::vector<double> R(n, 0.0); // R[k]: resistance between k-1 and k
    double Rsum = 0;
    for (const auto& c : s.contacts())
    {
        R[std::max(c.i, c.j)] = 1 / s.contactConductance(c, dt);
        Rsum += R[std::max(c.i, c.j)];
    }
    q = (T1 - T0) / Rsum;
    bathIn = rep.fixedGrainHeat / dt; // net: in from grain n-1, out to grain 0 (0 at steady state)
    double err = 0, T = T0;
    seriesErr = 0;
    for (int k = 0; k < n; ++k)
    {
        T += q * R[k];
        seriesErr = std::max(seriesErr, std::abs(s.temperatures()[k] - T));
        err = std::max(err, std::abs(s.temperatures()[k] - (T0 + (T1 - T0) * k / double(n - 1))));
    }
    return err;
}
} // namespace

// Reference: steady conduction through a chain of contacts in series: the
// heat flux q = (T_hot - T_cold)/sum_k (1/H_k) is the same through every
// contact and the temperature drops by q/H_k across contact k (H_k from the
// contacts' actual impulses, contactConductance). Tolerance 1e-6 K on a
// 100 K difference; the wall heat rate equals q to 1e-6 relative.
TEST(Heat, ChainSteadyStateSeriesResistances)
{
    for (int dim : {2, 3})
    {
        const ChainResult c = column(dim, 10, 400, 300);
        EXPECT_LT(c.maxErr, 1e-6) << "dim " << dim;
        EXPECT_GT(c.nonLinear, 0.1); // the load-dependent H makes it non-linear
        EXPECT_NEAR(c.wallQ, c.q, 1e-6 * c.q);
        EXPECT_NEAR(c.bathQ, c.q, 1e-6 * c.q);
        std::printf("[ measured ] column dim %d: max |T - T_series| %.2e K, q %.4g, wall %.2e rel, "
                    "deviation from linear %.3g K\n",
                    dim, c.maxErr, c.q, std::abs(c.wallQ / c.q - 1), c.nonLinear);
        double q = 0, bath = 0, es = 0;
        const double e = pressedChain(dim, 10, 300, 400, q, bath, es);
        EXPECT_LT(es, 1e-6) << "dim " << dim;
        EXPECT_LT(e, 1e-6) << "dim " << dim;
        EXPECT_NEAR(bath, 0.0, 1e-6 * q);
        std::printf("[ measured ] pressed chain dim %d: max |T - T_series| %.2e K, |T - linear| %.2e K, "
                    "net bath heat %.1e rel\n",
                    dim, es, e, std::abs(bath / q));
    }
}

namespace
{
// a bed of grains falling into a box, random temperatures, some sources and
// exchanges, one thermally inert material
System heatedBox(int dim, bool sources)
{
    System s(dim);
    const int m1 = s.addMaterial(matA(800));
    const int m2 = s.addMaterial(matB(500));
    const int inert = s.addMaterial({1500, 0.3});
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> U(0, 1);
    const int n = 6;
    const double h = 0.022;
    int id = 0;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b)
            for (int c = 0; c < (dim == 3 ? 3 : 1); ++c, ++id)
            {
                const int mat = id % 7 == 3 ? inert : (id % 2 ? m1 : m2);
                const int k = s.addGrain(Vec3((a + 0.5) * h, (b + 0.5) * h, dim == 3 ? (c + 0.5) * h : 0),
                                         0.008 + 0.002 * U(gen), mat);
                s.temperatures()[k] = 280 + 100 * U(gen);
                s.velocities()[k] = Vec3(U(gen) - 0.5, U(gen) - 0.5, 0) * 0.2;
                if (sources && mat != inert && k % 3 == 0) s.setHeatSource(k, 50 * (U(gen) - 0.3));
                if (sources && mat != inert && k % 5 == 0)
                    s.setHeatExchange(k, 0.5 * U(gen), 250 + 100 * U(gen));
            }
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
    s.addPlane(Vec3(n * h, 0, 0), Vec3(-1, 0, 0));
    if (dim == 3)
    {
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 0, 1));
        s.addPlane(Vec3(0, 0, 3 * h), Vec3(0, 0, -1));
    }
    s.setGravity(Vec3(0, -9.81, 0));
    return s;
}
} // namespace

// Reference: with adiabatic walls and no source, sum m c T is invariant
// (1e-12 relative), and backward Euler with an M-matrix keeps every
// temperature within the initial range (maximum principle, 1e-9 K). With
// sources and exchanges, and then a wall at fixed temperature and a
// fixed-temperature grain, the heat content changes by exactly the reported
// wallHeat + fixedGrainHeat + sourceHeat (1e-12 relative to the content).
TEST(Heat, AdiabaticBoxConservesHeat)
{
    for (int dim : {2, 3})
    {
        for (int variant : {0, 1, 2})
        {
            System s = heatedBox(dim, variant > 0);
            if (variant == 2)
            {
                s.setWallTemperature(0, 500); // heated floor
                s.setFixedTemperature(7);     // a cold bath grain
                s.temperatures()[7] = 200;
            }
            double lo = 1e300, hi = -1e300;
            for (double T : s.temperatures())
            {
                lo = std::min(lo, T);
                hi = std::max(hi, T);
            }
            const double E0 = s.heatContent();
            double wall = 0, fixedG = 0, src = 0, maxErr = 0;
            int its = 0;
            for (int k = 0; k < 400; ++k)
            {
                const StepReport r = s.advance(1e-3);
                wall += r.wallHeat;
                fixedG += r.fixedGrainHeat;
                src += r.sourceHeat;
                its = std::max(its, r.heatIterations);
                EXPECT_LT(r.heatResidual, 1e-12);
                maxErr = std::max(maxErr, std::abs(s.heatContent() - E0 - wall - fixedG - src) / E0);
            }
            EXPECT_LT(maxErr, 1e-12) << "dim " << dim << " variant " << variant;
            if (variant < 2)
            {
                EXPECT_EQ(wall, 0.0);
                EXPECT_EQ(fixedG, 0.0);
            }
            if (variant == 0)
            {
                EXPECT_EQ(src, 0.0);
                for (double T : s.temperatures())
                {
                    EXPECT_GE(T, lo - 1e-9);
                    EXPECT_LE(T, hi + 1e-9);
                }
            }
            else
                EXPECT_NE(src, 0.0);
            if (variant == 2)
            {
                EXPECT_GT(wall, 0.0);
                EXPECT_LT(fixedG, 0.0);
            }
            std::printf("[ measured ] box dim %d variant %d: %zu contacts, budget error %.2e rel, "
                        "heat in: walls %.4g fixed %.4g sources %.4g J, max CG its %d\n",
                        dim, variant, s.nContacts(), maxErr, wall, fixedG, src, its);
        }
    }
}

// Reference: an isolated grain exchanging with a bath, C dT/dt = h (Tf - T):
// backward Euler gives exactly T_{n+1} = (C/dt T_n + h Tf)/(C/dt + h)
// (1e-12 relative) and, for h dt/C = 1e6, T reaches Tf in one step without
// overshoot; plus a constant source Q: T_n = T_0 + n dt Q/C (1e-12).
// StepReport::exchangeHeat is the bath's part of sourceHeat, dt h (Tf - T_{n+1}).
TEST(Heat, ExchangeIsImplicitAndSourceIsExact)
{
    for (int dim : {2, 3})
    {
        System s(dim);
        const int m = s.addMaterial(matA(800));
        s.addGrain(Vec3(0, 0, 0), 0.01, m);
        s.addGrain(Vec3(1, 0, 0), 0.01, m);
        const double C = s.mass(0) * 800, dt = 1e-3;
        s.temperatures()[0] = 300;
        s.temperatures()[1] = 300;
        const double h = C / dt * 0.5, Tf = 350, Q = 7.5;
        s.setHeatExchange(0, h, Tf);
        s.setHeatSource(1, Q);
        EXPECT_EQ(s.heatExchange(0).first, h);
        EXPECT_EQ(s.heatSource(1), Q);
        double T = 300, err = 0;
        for (int k = 0; k < 20; ++k)
        {
            const StepReport r = s.step(dt);
            const double T1 = (C / dt * T + h * Tf) / (C / dt + h);
            EXPECT_NEAR(r.sourceHeat, dt * (h * (Tf - T1) + Q), 1e-12 * C * T1);
            // the bath's part alone (StepReport::exchangeHeat)
            EXPECT_NEAR(r.exchangeHeat, dt * h * (Tf - T1), 1e-12 * C * T1);
            T = T1;
            err = std::max(err, relErr(s.temperatures()[0], T));
            EXPECT_NEAR(s.temperatures()[1], 300 + (k + 1) * dt * Q / C, 1e-12 * 300);
        }
        EXPECT_LT(err, 1e-12);
        s.setHeatExchange(0, C / dt * 1e6, 200);
        s.step(dt);
        EXPECT_NEAR(s.temperatures()[0], 200, 2e-6 * 150);
        EXPECT_GE(s.temperatures()[0], 200);
        // switched off
        s.setHeatExchange(0, 0, 0);
        s.setHeatSource(1, 0);
        const std::vector<double> before = s.temperatures();
        s.step(dt);
        EXPECT_EQ(s.temperatures(), before);
    }
}

// Reference: restart contract for temperatures: every heat field reads back
// bit-exact and 2N steps == N steps + write + read + N steps (bitwise);
// a file without the heat datasets (older format) reads with the defaults.
TEST(Heat, HDF5RoundTripAndRestart)
{
    for (int dim : {2, 3})
    {
        auto make = [dim]()
        {
            System s = heatedBox(dim, true);
            s.setWallTemperature(1, 330.5);
            s.setFixedTemperature(4);
            s.setDefaultTemperature(290);
            s.settings().heatTolerance = 1e-13;
            return s;
        };
        const int N = 40;
        System a = make();
        for (int k = 0; k < 2 * N; ++k) a.step(1e-3);
        System b = make();
        for (int k = 0; k < N; ++k) b.step(1e-3);
        const std::string f = "nscd_heat.h5";
        b.writeHDF5(f);
        System c = System::readHDF5(f);
        EXPECT_EQ(c.temperatures(), b.temperatures());
        for (std::size_t i = 0; i < b.size(); ++i)
        {
            EXPECT_EQ(c.fixedTemperature(i), b.fixedTemperature(i));
            EXPECT_EQ(c.heatSource(i), b.heatSource(i));
            EXPECT_EQ(c.heatExchange(i), b.heatExchange(i));
        }
        for (int w = 0; w < b.nWalls(); ++w)
        {
            EXPECT_EQ(c.wallAdiabatic(w), b.wallAdiabatic(w));
            if (!b.wallAdiabatic(w)) EXPECT_EQ(c.wallTemperature(w), b.wallTemperature(w));
        }
        EXPECT_EQ(c.wallTemperature(1), 330.5);
        EXPECT_TRUE(c.fixedTemperature(4));
        EXPECT_EQ(c.defaultTemperature(), 290);
        EXPECT_EQ(c.settings().heatTolerance, 1e-13);
        EXPECT_EQ(c.heatContent(), b.heatContent());
        for (int k = 0; k < N; ++k) c.step(1e-3);
        EXPECT_EQ(a.temperatures(), c.temperatures()) << "dim " << dim;
        EXPECT_EQ(a.positions(), c.positions());
        EXPECT_EQ(a.velocities(), c.velocities());

        // older file: delete the heat datasets
        {
            const hid_t h = H5Fopen(f.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
            ASSERT_GE(h, 0);
            for (const char* name : {"temperatures", "heatSources", "heatExchange", "fixedTemperature",
                                     "wallTemperature", "heatSettings"})
                EXPECT_GE(H5Ldelete(h, name, H5P_DEFAULT), 0) << name;
            H5Fclose(h);
        }
        System old = System::readHDF5(f);
        ASSERT_EQ(old.size(), b.size());
        EXPECT_EQ(old.positions(), b.positions());
        for (std::size_t i = 0; i < old.size(); ++i)
        {
            EXPECT_EQ(old.temperatures()[i], 0.0);
            EXPECT_FALSE(old.fixedTemperature(i));
            EXPECT_EQ(old.heatSource(i), 0.0);
            EXPECT_EQ(old.heatExchange(i).first, 0.0);
        }
        for (int w = 0; w < old.nWalls(); ++w) EXPECT_TRUE(old.wallAdiabatic(w));
        EXPECT_EQ(old.defaultTemperature(), 0.0);
        old.step(1e-3); // usable
        std::remove(f.c_str());
    }
}

TEST(Heat, InputErrors)
{
    System s(2);
    EXPECT_THROW(s.addMaterial({1000, 0.3, 1e9, 0.3, 1, -800}), InputError);
    EXPECT_THROW(s.addMaterial({1000, 0.3, 1e9, 0.3, -1, 800}), InputError);
    EXPECT_THROW(s.addMaterial({1000, 0.3, -1e9, 0.3, 1, 800}), InputError);
    EXPECT_THROW(s.addMaterial({1000, 0.3, 1e9, 0.7, 1, 800}), InputError);
    EXPECT_THROW(s.addMaterial({1000, 0.3, 1e9, 0.3, 1, std::numeric_limits<double>::infinity()}),
                 InputError);
    const int m = s.addMaterial(matA(800));
    const int inert = s.addMaterial({1000, 0.3});
    s.setDefaultTemperature(293.15);
    s.addGrain(Vec3(0, 0.01, 0), 0.01, m);
    s.addGrain(Vec3(0.1, 0.01, 0), 0.01, inert);
    EXPECT_EQ(s.temperatures()[0], 293.15);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    EXPECT_THROW(s.setWallTemperature(1, 300), InputError);
    EXPECT_THROW(s.setWallTemperature(-1, 300), InputError);
    EXPECT_THROW(s.setWallTemperature(0, std::nan("")), InputError);
    EXPECT_THROW(s.setWallAdiabatic(3), InputError);
    EXPECT_THROW(s.wallTemperature(3), InputError);
    EXPECT_TRUE(s.wallAdiabatic(0));
    EXPECT_TRUE(std::isnan(s.wallTemperature(0)));
    s.setWallTemperature(0, 300);
    EXPECT_FALSE(s.wallAdiabatic(0));
    s.setWallAdiabatic(0);
    EXPECT_TRUE(s.wallAdiabatic(0));
    EXPECT_THROW(s.setHeatSource(2, 1), InputError);
    EXPECT_THROW(s.setHeatSource(0, std::nan("")), InputError);
    EXPECT_THROW(s.setHeatExchange(0, -1, 300), InputError);
    EXPECT_THROW(s.setHeatExchange(5, 1, 300), InputError);
    EXPECT_THROW(s.setFixedTemperature(5), InputError);
    EXPECT_THROW(s.setDefaultTemperature(std::nan("")), InputError);
    // heat source on a grain whose temperature is not integrated: step throws, state unchanged
    s.setHeatSource(1, 5.0);
    try
    {
        s.step(1e-3);
        ADD_FAILURE() << "no throw";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("grain 1"), std::string::npos) << e.what();
    }
    EXPECT_EQ(s.time(), 0.0);
    s.setFixedTemperature(1); // a bath: allowed (its source is ignored)
    EXPECT_NO_THROW(s.step(1e-3));
    s.temperatures()[0] = std::nan("");
    EXPECT_THROW(s.step(1e-3), InputError);
    s.temperatures()[0] = 300;
    s.temperatures().push_back(1);
    EXPECT_THROW(s.step(1e-3), InputError);
    s.temperatures().pop_back();
    s.settings().heatTolerance = 0;
    EXPECT_THROW(s.step(1e-3), InputError);
}
