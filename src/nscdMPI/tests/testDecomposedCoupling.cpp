// SPDX-License-Identifier: GPL-3.0-or-later
// nscdMPI: droplets, heat conduction and cohesion across the interfaces of
// a decomposed grain system, and the input it refuses (run by ctest on 1, 2
// and 4 ranks with testDecomposed.cpp's main); every rank also runs the
// undecomposed System for comparison.
#include "DecomposedCases.H"
#include "nscdMPI/DecomposedSystem.H"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

using namespace nscd;
using nscd::mpi::DecomposedSystem;
using namespace nscdtest;

// A droplet with mass driven through the gas of grains across the rank
// boundaries (x slabs), no walls, no gravity: the droplet's copies on the
// ranks that solve its contacts exchange momentum with the grains there,
// and the total momentum, grains' sum m v plus the droplet's M V, is kept to
// round-off (internal contact impulses only; Newton's third law), while
// every rank holds the same droplet.
TEST(Decomposed, DropletThroughTheGrainsKeepsTheMomentum)
{
    const std::vector<Grain> G = gasCase();
    DecomposedSystem D(2, MPI_COMM_WORLD, slabs(0, 0, 24e-3), 3e-3);
    System& S = D.system();
    const int m = S.addMaterial({2500, 0.3});
    for (std::size_t k = 0; k < G.size(); ++k)
    {
        const std::size_t i = D.addGrain(long(k), G[k].x, G[k].r, m);
        if (i != std::size_t(-1)) S.velocities()[i] = G[k].v;
    }
    System::Droplet drop;
    drop.centre = Vec3(12e-3, 12e-3, 0);
    drop.radius = 2.5e-3;
    drop.mass = 1000 * M_PI * drop.radius * drop.radius;
    drop.velocity = Vec3(0.3, -0.2, 0);
    drop.surfaceTension = 0.02; // grains pushed in beyond 2 sigma = 0.04 N/m
    S.addDroplet(drop);
    D.exchange();
    auto momentum = [&](double& scale) -> Vec3 // (a Vec3, not an Eigen expression of temporaries)
    {
        const Vec3 p = ownedMomentum(D, scale);
        const System::Droplet& d = S.droplet(0);
        scale += d.mass * d.velocity.norm();
        return p + d.mass * d.velocity;
    };
    double scale0 = 0, worst = 0, spread = 0, exchanged = 0;
    int shared = 0;
    const Vec3 p0 = momentum(scale0);
    for (int n = 0; n < 150; ++n)
    {
        S.droplet(0).impulse.setZero();
        const StepReport rep = D.step(1e-4);
        ASSERT_TRUE(rep.converged) << "step " << n;
        double scale = 0;
        worst = std::max(worst, (momentum(scale) - p0).norm() / scale0);

        exchanged += S.droplet(0).impulse.norm();
        const System::Droplet& d = S.droplet(0);
        double here = 0; // this rank solved a droplet contact
        for (double rn : d.grainImpulse) here = std::max(here, rn > 0 ? 1.0 : 0.0);
        shared = std::max(shared, int(sumAll(here)));
        std::fill(S.droplet(0).grainImpulse.begin(), S.droplet(0).grainImpulse.end(), 0.0);
        spread = std::max({spread, maxAll(d.centre.x()) + maxAll(-d.centre.x()),
                           maxAll(d.velocity.x()) + maxAll(-d.velocity.x())});
    }
    if (worldRank() == 0)
        std::printf("[ droplet gas ] %d ranks: |d(sum m v + M V)|/sum m|v| at most %.2e, droplet impulses "
                    "%.3g of its momentum, at most %d ranks solving its contacts\n",
                    worldSize(), worst, exchanged / (drop.mass * drop.velocity.norm()), shared);
    EXPECT_LT(worst, 1e-12);
    EXPECT_GT(exchanged, 0.05 * drop.mass * drop.velocity.norm()); // the droplet did meet grains
    if (worldSize() > 1) EXPECT_GT(shared, 1);                     // on several ranks in one step
    EXPECT_EQ(spread, 0.0);
    EXPECT_EQ(ownedIdsEverywhere(D).size(), G.size());
}

// A droplet resting on a deposit across vertical rank boundaries (x slabs:
// its contacts are solved on several ranks, each holding a copy of it of
// mass m/n). 128 discs of 0.9-1.1 mm dropped from a loose lattice into a box,
// a 2D water droplet of R = 3 mm dropped on them (its weight as its force:
// System gravity does not act on droplets; a surface tension of 0.5 N/m, so
// that the entry barrier 2 sigma = 1 N/m per grain is 3.6 times its weight
// and it stays on the grains' tops), 0.2 s. Statics, independent of the
// serial run (Newton's third law): over the last 100 steps the droplet's
// contact impulse over dt carries its weight, and the walls carry the
// grains' and the droplet's. Every rank holds the same droplet (centre and
// velocity, bit for bit), and it rests at the undecomposed run's height.
TEST(Decomposed, DropletRestsOnTheBedAcrossTheInterfacesAsSerial)
{
    const int cols = 16, rows = 8;
    const double a = 1.15e-3, W = cols * a + 0.2e-3, R = 3e-3, g = 9.81;
    const std::vector<Grain> G = looseLattice(cols, rows, a, 5);
    System::Droplet drop;
    drop.centre = Vec3(0.5 * W, rows * a + R + 1e-3, 0);
    drop.radius = R;
    drop.mass = 1000 * M_PI * R * R; // [kg/m]
    drop.force = Vec3(0, -drop.mass * g, 0);
    drop.surfaceTension = 0.5;
    auto setUp = [&](System& S)
    {
        S.addDroplet(drop);
        return box(S, W);
    };
    DecomposedSystem D(2, MPI_COMM_WORLD, slabs(0, 0, W), 2.5e-3);
    const int m = setUp(D.system());
    for (std::size_t k = 0; k < G.size(); ++k) D.addGrain(long(k), G[k].x, G[k].r, m);
    D.exchange();
    System serial(2);
    setUp(serial);
    for (const Grain& g0 : G) serial.addGrain(g0.x, g0.r, m);

    const double dt = 5e-4;
    const int steps = 400, averaged = 100;
    double loadDecomposed = 0, loadSerial = 0, dropDecomposed = 0, dropSerial = 0, spread = 0;
    double grainImpulse = 0, grainImpulseSerial = 0, ghostImpulse = 0; // sum of r_n [N s/m]
    double farImpulse = -1; // largest gap [m] of a grain with an impulse on the droplet
    int shared = 0;
    for (int n = 0; n < steps; ++n)
    {
        for (System* S : {&D.system(), &serial})
        {
            S->droplet(0).impulse.setZero();
            std::fill(S->droplet(0).grainImpulse.begin(), S->droplet(0).grainImpulse.end(), 0.0);
        }
        D.step(dt);
        serial.step(dt);
        const System::Droplet& d = D.system().droplet(0);
        spread = std::max({spread, maxAll(d.centre.y()) + maxAll(-d.centre.y()),
                           maxAll(d.velocity.norm()) + maxAll(-d.velocity.norm())});
        // after the step's exchange (migrations, ghosts): each entry still
        // belongs to its grain (a grain pressed on the droplet), ghosts zero
        double here = 0; // ranks solving a droplet contact
        ASSERT_EQ(d.grainImpulse.size(), D.system().size());
        for (std::size_t i = 0; i < D.system().size(); ++i)
        {
            if (!(d.grainImpulse[i] > 0)) continue;
            here = 1;
            const double gap = (D.system().positions()[i] - d.centre).norm() - R - D.system().radii()[i];
            farImpulse = std::max(farImpulse, gap);
            if (!D.owned()[i]) ghostImpulse = std::max(ghostImpulse, d.grainImpulse[i]);
        }
        shared = std::max(shared, int(sumAll(here)));
        if (n < steps - averaged) continue;
        loadDecomposed += sumAll(wallLoad(D.system(), &D.owned())) / (averaged * dt);
        loadSerial += wallLoad(serial, nullptr) / (averaged * dt);
        dropDecomposed += d.impulse.y() / (averaged * dt);
        dropSerial += serial.droplet(0).impulse.y() / (averaged * dt);
        double mine = 0;
        for (std::size_t i = 0; i < D.system().size(); ++i)
            if (D.owned()[i]) mine += d.grainImpulse[i];
        grainImpulse += sumAll(mine);
        for (double rn : serial.droplet(0).grainImpulse) grainImpulseSerial += rn;
    }
    double weight = 0;
    for (std::size_t i = 0; i < serial.size(); ++i) weight += serial.mass(i) * g;
    const double dropWeight = drop.mass * g;
    const double yd = D.system().droplet(0).centre.y(), ydSerial = serial.droplet(0).centre.y();
    if (worldRank() == 0)
        std::printf("[ droplet ] %d ranks (at most %d solving its contacts): droplet impulse/weight %.6f "
                    "(serial %.6f), wall load/total weight %.6f (serial %.6f), centre %.4f mm (serial %.4f), "
                    "sum of grain impulses %.4g (serial %.4g) N s/m\n",
                    worldSize(), shared, dropDecomposed / dropWeight, dropSerial / dropWeight,
                    loadDecomposed / (weight + dropWeight), loadSerial / (weight + dropWeight), 1e3 * yd,
                    1e3 * ydSerial, grainImpulse, grainImpulseSerial);
    EXPECT_NEAR(dropSerial / dropWeight, 1.0, 1e-3);
    EXPECT_NEAR(dropDecomposed / dropWeight, 1.0, 1e-3);
    EXPECT_NEAR(loadSerial / (weight + dropWeight), 1.0, 1e-3);
    EXPECT_NEAR(loadDecomposed / (weight + dropWeight), 1.0, 1e-3);
    EXPECT_EQ(spread, 0.0);                       // the same droplet on every rank
    EXPECT_EQ(ghostImpulse, 0.0);                 // a contact's impulse is its owner's
    EXPECT_LT(maxAll(farImpulse), 0.1 * 0.45e-3); // only grains at the droplet's surface
    EXPECT_NEAR(grainImpulse, grainImpulseSerial, 0.05 * grainImpulseSerial);
    EXPECT_NEAR(yd, ydSerial, 0.02 * ydSerial); // (as the deposit's top above)
    // held on the grains' tops by the barrier: no grain immersed
    double immersed = 0;
    for (std::size_t i = 0; i < D.system().size(); ++i)
        immersed =
            std::max(immersed, R + D.system().radii()[i]
                                   - (D.system().positions()[i] - D.system().droplet(0).centre).norm());
    EXPECT_LT(maxAll(immersed), 1e-3 * 0.45e-3);
    EXPECT_EQ(ownedIdsEverywhere(D).size(), G.size());
    if (worldSize() > 1) EXPECT_GT(shared, 1); // the droplet's contacts on several ranks
}

// Heat conduction across the interfaces: 6 vertical columns of 12 discs of
// 1 mm resting on a floor held at 300 K, the discs at 300-500 K, a heat
// source on each column's top disc, an exchange with a 350 K bath on its
// third, a fixed-temperature disc (450 K) in column 2; horizontal slabs, so
// every column's conduction crosses every interface. A column's contact
// forces are statically determinate (the weight above), so the decomposed
// and the undecomposed solves give the same conductances to the contact
// tolerance, and the temperatures must agree to 1e-8 of the 200 K span after
// 20 steps. Independent of the serial run, the heat budget closes to
// round-off: the change of the heat content of the owned grains equals the
// summed wall, fixed-grain and source heat (conservation). The heat capacity
// is small (1e-3 J/(kg K)) so that H dt/(m c) ~ 0.1 and heat crosses several
// discs in 20 steps.
TEST(Decomposed, HeatConductionAcrossTheInterfacesMatchesSerial)
{
    const int cols = 6, rows = 12;
    const double r = 0.5e-3, pitch = 1.5e-3, H = rows * 2 * r, dt = 1e-4;
    auto setUp = [&](System& S)
    {
        S.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
        S.setWallTemperature(0, 300);
        S.setGravity(Vec3(0, -9.81, 0));
        S.settings().tolerance = 1e-13;
        S.settings().heatTolerance = 1e-14;
        Material m{2500, 0.3};
        m.youngModulus = 1e9;
        m.poissonRatio = 0.3;
        m.conductivity = 1.0;
        m.heatCapacity = 1e-3;
        return S.addMaterial(m);
    };
    auto centre = [&](long k) { return Vec3((k / rows + 0.5) * pitch, (2 * (k % rows) + 1) * r, 0); };
    auto T0 = [&](long k) { return 300 + 200 * double((k * 7) % 13) / 12; };
    // heat input of grain k: (fixed temperature, source Q [W/m], exchange h [W/(m K)])
    auto heatInput = [&](System& S, std::size_t i, long k)
    {
        S.temperatures()[i] = T0(k);
        if (k % rows == rows - 1) S.setHeatSource(i, 1e-3 * (1 + k / rows));
        if (k % rows == 2) S.setHeatExchange(i, 1e-3, 350);
        if (k == 2 * rows + 5)
        {
            S.setFixedTemperature(i, true);
            S.temperatures()[i] = 450;
        }
    };
    DecomposedSystem D(2, MPI_COMM_WORLD, slabs(1, 0, H), 2.5e-3);
    const int m = setUp(D.system());
    for (long k = 0; k < cols * rows; ++k) D.addGrain(k, centre(k), r, m);
    D.exchange();
    for (std::size_t i = 0; i < D.system().size(); ++i) heatInput(D.system(), i, D.globalIds()[i]);
    System serial(2);
    setUp(serial);
    for (long k = 0; k < cols * rows; ++k) serial.addGrain(centre(k), r, m);
    for (long k = 0; k < cols * rows; ++k) heatInput(serial, std::size_t(k), k);

    auto ownedHeat = [&]()
    {
        double q = 0;
        const System& S = D.system();
        for (std::size_t i = 0; i < S.size(); ++i)
            if (D.owned()[i] && !S.fixedTemperature(i))
                q += S.mass(i) * S.material(S.materials()[i]).heatCapacity * S.temperatures()[i];
        return sumAll(q);
    };
    const double q0 = ownedHeat();
    double budget = 0, budgetScale = 0;
    int iterations = 0;
    for (int n = 0; n < 20; ++n)
    {
        const StepReport rep = D.step(dt);
        const StepReport repSerial = serial.step(dt);
        EXPECT_TRUE(rep.converged);
        budget += rep.wallHeat + rep.fixedGrainHeat + rep.sourceHeat;
        budgetScale += std::abs(rep.wallHeat) + std::abs(rep.fixedGrainHeat) + std::abs(rep.sourceHeat);
        EXPECT_NEAR(rep.wallHeat, repSerial.wallHeat, 1e-8 * std::abs(repSerial.wallHeat));
        iterations = std::max(iterations, rep.heatIterations);
    }
    double dT = 0, spread = 0;
    for (std::size_t i = 0; i < D.system().size(); ++i)
    {
        const double Ts = serial.temperatures()[std::size_t(D.globalIds()[i])];
        dT = std::max(dT, std::abs(D.system().temperatures()[i] - Ts)); // ghosts included
    }
    for (std::size_t k = 0; k < serial.size(); ++k)
        spread = std::max(spread, std::abs(serial.temperatures()[k] - T0(long(k))));
    dT = maxAll(dT);
    const double closure = std::abs(ownedHeat() - q0 - budget);
    if (worldRank() == 0)
        std::printf(
            "[ heat ] %d ranks: max |T - T(serial)| %.2e K (largest change %.2f K), budget defect %.2e of "
            "%.2e J/m, CG iterations/step max %d\n",
            worldSize(), dT, spread, closure, budgetScale, iterations);
    EXPECT_GT(spread, 1.0); // the heat moved
    EXPECT_LT(dT, 1e-8 * 200);
    EXPECT_LT(closure, 1e-12 * budgetScale + 1e-14 * q0);
}

// A chain of discs hanging under a ceiling by cohesion (thesis eq. 4.18),
// cut by horizontal slabs so its contacts cross the interfaces. Statics: a
// contact k places below the ceiling carries the weight of the grains under
// it, (n - k) m g, in tension; it holds while that is <= F_c. With F_c =
// 1.5 n m g the chain hangs (the ceiling's contact pulls n m g); with F_c =
// (n/2) m g the ceiling lets go: the chain falls as a rigid body at
// g (1 - F_c/(n m g)) while the ceiling's gap is within cohesionDistance r,
// then at g (its inner contacts carry at most (n - 1) m g/2 < F_c), which a
// scalar recurrence of the same time stepping gives (a consistency check of
// the cohesion-distance rule; the hanging chain's statics is the independent
// reference). Either way the grains' positions are the undecomposed run's.
TEST(Decomposed, CohesiveChainHangsAcrossTheInterfacesAsSerial)
{
    const int n = 12;
    const double r = 0.5e-3, H = 2 * n * r, dt = 1e-4, g = 9.81;
    for (const double load : {1.5, 0.5})
    {
        double Fc = 0;
        auto setUp = [&](System& S)
        {
            S.addPlane(Vec3(0, H, 0), Vec3(0, -1, 0)); // the ceiling
            S.setGravity(Vec3(0, -g, 0));
            S.settings().tolerance = 1e-12;
            const int m = S.addMaterial({2500, 0.3});
            return m;
        };
        auto centre = [&](long k) { return Vec3(2 * r, H - (2 * k + 1) * r, 0); };
        DecomposedSystem D(2, MPI_COMM_WORLD, slabs(1, 0, H), 2.5e-3);
        const int m = setUp(D.system());
        for (long k = 0; k < n; ++k) D.addGrain(k, centre(k), r, m);
        D.exchange();
        System serial(2);
        setUp(serial);
        for (long k = 0; k < n; ++k) serial.addGrain(centre(k), r, m);
        const double W = n * serial.mass(0) * g; // [N/m]
        Fc = load * W;
        D.system().setCohesion([](int, int) { return true; }, Fc);
        serial.setCohesion([](int, int) { return true; }, Fc);

        const int steps = 30;
        double ceilingImpulse = 0; // this rank's owned contacts with the ceiling, last step
        for (int s = 0; s < steps; ++s)
        {
            const StepReport rep = D.step(dt);
            serial.step(dt);
            EXPECT_TRUE(rep.converged);
            ceilingImpulse = 0;
            for (const System::ContactView& c : D.system().contacts())
                if (c.j < 0 && D.owned()[std::size_t(c.i)]) ceilingImpulse += c.impulse.y();
        }
        ceilingImpulse = sumAll(ceilingImpulse);
        double dx = 0, drop = 0;
        for (std::size_t i = 0; i < D.system().size(); ++i)
        {
            const long k = D.globalIds()[i];
            dx = std::max(dx, (D.system().positions()[i] - serial.positions()[std::size_t(k)]).norm());
            if (D.owned()[i] && k == n - 1) drop = centre(k).y() - D.system().positions()[i].y();
        }
        dx = maxAll(dx);
        drop = sumAll(drop);
        const double tEnd = steps * dt;
        if (worldRank() == 0)
            std::printf(
                "[ cohesion ] %d ranks, F_c = %.1f n m g: max |x - x(serial)| %.2e m, lowest grain fell "
                "%.3e m (free fall %.3e), ceiling pull %.6f n m g dt\n",
                worldSize(), load, dx, drop, 0.5 * g * tEnd * tEnd, ceilingImpulse / (W * dt));
        EXPECT_LT(dx, 1e-9 * r);
        if (load > 1)
        {
            EXPECT_LT(drop, 1e-6 * r);                          // the chain hangs
            EXPECT_NEAR(ceilingImpulse, W * dt, 1e-6 * W * dt); // and the ceiling carries it
        }
        else
        {
            // rigid fall, pulled back while the gap is within the cohesion distance
            double v = 0, y = 0;
            const double reach = serial.settings().cohesionDistance * r;
            for (int s = 0; s < steps; ++s)
            {
                v += (y <= reach ? g * (1 - Fc / W) : g) * dt;
                y += v * dt;
            }
            if (worldRank() == 0) std::printf("[ cohesion ] expected fall %.6e m\n", y);
            EXPECT_GT(y, 0.5 * 0.5 * g * tEnd * tEnd);
            EXPECT_NEAR(drop, y, 1e-6 * y);
        }
    }
}

TEST(Decomposed, BadInputIsRefused)
{
    EXPECT_THROW(DecomposedSystem(2, MPI_COMM_WORLD, slabs(0, 0, 1), 0.0), InputError);
    {
        // input refused on one rank only: every rank throws (none hangs)
        DecomposedSystem D(2, MPI_COMM_WORLD, slabs(0, 0, 10e-3), 3e-3);
        const int m = D.system().addMaterial({2500, 0.3});
        for (int k = 0; k < 8; ++k) D.addGrain(k, Vec3((k + 0.5) * 1.25e-3, 1e-3, 0), 0.5e-3, m);
        D.exchange();
        if (worldRank() == 0) D.system().settings().tolerance = -1;
        try
        {
            D.step(1e-4);
            FAIL() << "no error for a negative tolerance on rank 0";
        }
        catch (const InputError& e)
        {
            const std::string what = e.what();
            if (worldRank() == 0)
                EXPECT_NE(what.find("tolerance > 0"), std::string::npos) << what;
            else
                EXPECT_NE(what.find("another subdomain refused"), std::string::npos) << what;
        }
    }
    // settings the interface-averaged solve does not follow (it is plain
    // Gauss-Seidel), set on every rank: refused, not silently replaced
    for (const auto& set :
         std::vector<std::pair<const char*, void (*)(System::Settings&)>>{
             {"method APGD", [](System::Settings& s) { s.method = System::Settings::Method::APGD; }},
             {"method NNCG", [](System::Settings& s) { s.method = System::Settings::Method::NNCG; }},
             {"method OverRelaxedNLGS",
              [](System::Settings& s) { s.method = System::Settings::Method::OverRelaxedNLGS; }},
             {"relaxation 1.5", [](System::Settings& s) { s.relaxation = 1.5; }}})
    {
        DecomposedSystem D(2, MPI_COMM_WORLD, slabs(0, 0, 10e-3), 3e-3);
        const int m = D.system().addMaterial({2500, 0.3});
        for (int k = 0; k < 8; ++k) D.addGrain(k, Vec3((k + 0.5) * 1.25e-3, 1e-3, 0), 0.5e-3, m);
        D.exchange();
        set.second(D.system().settings());
        try
        {
            D.step(1e-4);
            ADD_FAILURE() << "no error for " << set.first;
        }
        catch (const InputError& e)
        {
            const std::string what = e.what();
            EXPECT_NE(what.find("use NLGS with relaxation 1"), std::string::npos)
                << set.first << ": " << what;
            if (std::string(set.first).rfind("method", 0) == 0)
                EXPECT_NE(what.find(std::string("got ") + set.first), std::string::npos) << what;
        }
    }
    DecomposedSystem D(
        2, MPI_COMM_WORLD, [](const Vec3&, long) { return -2; }, 1e-3);
    const int m = D.system().addMaterial({2500, 0.3});
    try
    {
        D.addGrain(0, Vec3(1, 2, 0), 1e-3, m);
        FAIL() << "no error for an owner function outside the ranks";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("owner function gives rank -2"), std::string::npos) << e.what();
    }
}
