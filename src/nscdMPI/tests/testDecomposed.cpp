// SPDX-License-Identifier: GPL-3.0-or-later
// nscdMPI: a grain system decomposed over the ranks of MPI_COMM_WORLD (run
// by ctest on 1, 2 and 4 ranks). Every rank also runs the undecomposed
// System for comparison (the cases are small).
//   - conservation: grains thrown across the rank boundaries keep every id
//     exactly once and the total momentum (no walls, no gravity: contact
//     impulses are internal forces, Newton's third law);
//   - statics: a deposit settled across horizontal rank boundaries carries
//     its weight to the floor (the floor's impulse over dt equals the total
//     weight), and settles like the undecomposed run (bed height).
#include "nscdMPI/DecomposedSystem.H"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <random>
#include <string>
#include <unordered_map>

using namespace nscd;
using nscd::mpi::DecomposedSystem;

namespace
{
int worldRank()
{
    int r;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
}
int worldSize()
{
    int p;
    MPI_Comm_size(MPI_COMM_WORLD, &p);
    return p;
}

double sumAll(double x)
{
    double s = 0;
    MPI_Allreduce(&x, &s, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    return s;
}
double maxAll(double x)
{
    double s = 0;
    MPI_Allreduce(&x, &s, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    return s;
}

/// Owner of x: P slabs of [lo, hi) along axis k (clamped).
DecomposedSystem::OwnerFunction slabs(int k, double lo, double hi)
{
    const int P = worldSize();
    return [=](const Vec3& x, long)
    { return std::clamp(int(std::floor((x[k] - lo) / (hi - lo) * P)), 0, P - 1); };
}

/// The same slabs seen locally: this rank's slab, notHere elsewhere (as a
/// mesh region: a rank knows its own cells only); nothing beyond [lo, hi).
DecomposedSystem::OwnerFunction localSlabs(int k, double lo, double hi)
{
    const int P = worldSize(), me = worldRank();
    return [=](const Vec3& x, long)
    {
        const double s = std::floor((x[k] - lo) / (hi - lo) * P);
        return s == me ? me : DecomposedSystem::notHere;
    };
}

/// The global ids of the grains owned anywhere, sorted (on every rank).
std::vector<long> ownedIdsEverywhere(const DecomposedSystem& D)
{
    std::vector<long> mine;
    for (std::size_t i = 0; i < D.owned().size(); ++i)
        if (D.owned()[i]) mine.push_back(D.globalIds()[i]);
    const int P = worldSize();
    int n = int(mine.size());
    std::vector<int> counts(P), offs(P, 0);
    MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
    std::partial_sum(counts.begin(), counts.end() - 1, offs.begin() + 1);
    std::vector<long> all(offs.back() + counts.back());
    MPI_Allgatherv(mine.data(), n, MPI_LONG, all.data(), counts.data(), offs.data(), MPI_LONG,
                   MPI_COMM_WORLD);
    std::sort(all.begin(), all.end());
    return all;
}

/// Grains of a case: centre, radius, velocity.
struct Grain
{
    Vec3 x;
    double r;
    Vec3 v;
};

/// 20 x 20 discs of radius 0.45-0.5 mm on a lattice of 1.2 mm, converging
/// on the centre at 20 1/s, drifting at 0.4 m/s along x, plus random
/// velocities of up to 0.1 m/s.
std::vector<Grain> gasCase()
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Grain> g;
    const double a = 1.2e-3;
    const Vec3 c(10 * a, 10 * a, 0);
    for (int j = 0; j < 20; ++j)
        for (int i = 0; i < 20; ++i)
        {
            const Vec3 x((i + 0.5) * a, (j + 0.5) * a, 0);
            const double r = 0.5e-3 * (0.95 + 0.05 * u(rng));
            g.push_back({x, r, Vec3(-20 * (x - c) + 0.1 * Vec3(u(rng), u(rng), 0) + Vec3(0.4, 0, 0))});
        }
    return g;
}

/// cols x rows discs of radius 0.45-0.55 mm (random, seed) on a loose
/// lattice of spacing a, odd rows shifted, 0.1 mm above the floor and off
/// the left wall: a pour into a box of width cols a + 0.2 mm.
std::vector<Grain> looseLattice(int cols, int rows, double a, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.45e-3, 0.55e-3);
    std::vector<Grain> G;
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < cols; ++i)
            G.push_back({Vec3((i + 0.5 + (j % 2 ? 0.1 : -0.1)) * a + 0.1e-3, (j + 0.5) * a + 0.1e-3, 0),
                         u(rng), Vec3::Zero()});
    return G;
}

/// A box of width W (floor y = 0, walls x = 0 and x = W), gravity 9.81 m/s^2
/// down; returns the grains' material (2500 kg/m^3, mu 0.4).
int box(System& S, double W)
{
    S.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    S.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
    S.addPlane(Vec3(W, 0, 0), Vec3(-1, 0, 0));
    S.setGravity(Vec3(0, -9.81, 0));
    return S.addMaterial({2500, 0.4});
}

/// Momentum sum m v of the grains owned on every rank (2D) [kg m/s per m];
/// scale: their sum m |v|.
Vec3 ownedMomentum(const DecomposedSystem& D, double& scale)
{
    const System& S = D.system();
    Vec3 p = Vec3::Zero();
    double s = 0;
    for (std::size_t i = 0; i < S.size(); ++i)
        if (D.owned()[i])
        {
            p += S.mass(i) * S.velocities()[i];
            s += S.mass(i) * S.velocities()[i].norm();
        }
    scale = sumAll(s);
    return Vec3(sumAll(p.x()), sumAll(p.y()), 0.0);
}

/// The walls' vertical impulse in the last step's contacts [N s/m] (of the
/// owned grains' contacts if owned is given).
double wallLoad(const System& S, const std::vector<char>* owned)
{
    double fy = 0;
    for (const System::ContactView& c : S.contacts())
        if (c.j < 0 && (!owned || (*owned)[c.i])) fy += c.impulse.y();
    return fy;
}
} // namespace

// Grains thrown across the rank boundaries (x slabs): after every step each
// id is owned exactly once, and the total momentum sum m v of the owned
// grains is that of the start (internal contact impulses only) to round-off.
/// advanceDt > 0: 30 advance(advanceDt) instead of 300 step(1e-4)
void throwGrains(const DecomposedSystem::OwnerFunction& ownerOf, double advanceDt = 0)
{
    const std::vector<Grain> G = gasCase();
    DecomposedSystem D(2, MPI_COMM_WORLD, ownerOf, 3e-3);
    System& S = D.system();
    const int m = S.addMaterial({2500, 0.3});
    for (std::size_t k = 0; k < G.size(); ++k)
    {
        const std::size_t i = D.addGrain(long(k), G[k].x, G[k].r, m);
        if (i != std::size_t(-1)) S.velocities()[i] = G[k].v;
    }
    D.exchange();
    // total momentum, sum m |v| (its scale) and kinetic energy of the owned grains
    auto momentum = [&](double& scale, double& energy)
    {
        Vec3 p = Vec3::Zero();
        double s = 0, e = 0;
        for (std::size_t i = 0; i < S.size(); ++i)
            if (D.owned()[i])
            {
                const Vec3& v = S.velocities()[i];
                p += S.mass(i) * v;
                s += S.mass(i) * v.norm();
                e += 0.5
                     * (S.mass(i) * v.squaredNorm() + S.inertia(i) * S.angularVelocities()[i].squaredNorm());
            }
        scale = sumAll(s);
        energy = sumAll(e);
        return Vec3(sumAll(p.x()), sumAll(p.y()), 0.0);
    };
    double scale0 = 0, energy0 = 0;
    const Vec3 p0 = momentum(scale0, energy0);
    std::vector<long> ids(G.size());
    std::iota(ids.begin(), ids.end(), 0L);
    long migrated = 0;
    int contactsMax = 0;
    int substeps = 0;
    for (int n = 0; n < (advanceDt > 0 ? 30 : 300); ++n)
    {
        const StepReport rep = advanceDt > 0 ? D.advance(advanceDt) : D.step(1e-4);
        ASSERT_TRUE(rep.converged) << "step " << n;
        ASSERT_LT(rep.maxOverlap, 1e-3 * 0.5e-3) << "step " << n;
        substeps = std::max(substeps, rep.substeps);
        migrated += D.counters().migratedOut;
        contactsMax = std::max(contactsMax, rep.contacts);
        ASSERT_EQ(ownedIdsEverywhere(D), ids) << "step " << n;
    }
    double scale = 0, energy = 0;
    const Vec3 p = momentum(scale, energy);
    EXPECT_LT((p - p0).norm(), 1e-12 * scale0) << "momentum " << p.transpose() << " from " << p0.transpose();
    EXPECT_LT(energy, 0.98 * energy0); // the (inelastic) collisions dissipated
    EXPECT_GT(sumAll(double(contactsMax)), 100);
    if (worldSize() > 1) EXPECT_GT(sumAll(double(migrated)), 20); // grains changed ranks
    if (advanceDt > 0) EXPECT_GT(substeps, 1);
}

TEST(Decomposed, ThrownGrainsKeepEveryIdAndTheMomentum) { throwGrains(slabs(0, 0, 36e-3)); }

// The same with an owner function that knows only its own rank's slab: the
// owners of the grains leaving a slab are found by asking every rank.
TEST(Decomposed, ThrownGrainsKeepEveryIdWithALocalOwnerFunction) { throwGrains(localSlabs(0, -2e-3, 36e-3)); }

// Steps of 2 ms: a grain at 0.5 m/s would reach beyond the halo's spare
// (3 mm - 2 r_max), so advance() sub-steps, and the ids and momentum are kept.
TEST(Decomposed, AdvanceSubStepsToKeepTheContactReachInTheHalo)
{
    throwGrains(localSlabs(0, -2e-3, 36e-3), 2e-3);
}

// Grains thrown across the rank boundaries in a fluid: each grain has an
// implicit drag (System::setFluidDrag, c dt/m = 1) towards a uniform flow.
// Without walls and gravity the contacts are internal, so over each step the
// grains' total momentum changes by the sum of their drag impulses
// (System::fluidDragImpulses; Newton's third law), also for the interface
// grains, whose contacts are solved on several ranks. Their caller's values
// travel with them (setGrainDataWidth: every copy holds its grain's id),
// also when a rank renumbers its local grains along the Morton order, and
// copyToGhosts sets the ghosts to their owners' values.
TEST(Decomposed, DragImpulsesAndTravellingValuesFollowTheGrains)
{
    const std::vector<Grain> G = gasCase();
    DecomposedSystem D(2, MPI_COMM_WORLD, localSlabs(0, -2e-3, 36e-3), 3e-3);
    System& S = D.system();
    const int m = S.addMaterial({2500, 0.3});
    for (std::size_t k = 0; k < G.size(); ++k)
    {
        const std::size_t i = D.addGrain(long(k), G[k].x, G[k].r, m);
        if (i != std::size_t(-1)) S.velocities()[i] = G[k].v;
    }
    D.setGrainDataWidth(2);
    for (std::size_t i = 0; i < S.size(); ++i) D.grainData()[2 * i] = double(D.globalIds()[i]);
    D.exchange();
    const double dt = 1e-4;
    const Vec3 u(0.2, 0.1, 0);
    auto momentum = [&](double& scale) { return ownedMomentum(D, scale); };
    double worst = 0, scale = 0;
    long interface = 0, renumbered = 0;
    for (int n = 0; n < 100; ++n)
    {
        for (std::size_t i = 0; i < S.size(); ++i) S.setFluidDrag(i, 0.05 * S.mass(i) / dt, u);
        const Vec3 p0 = momentum(scale);
        const StepReport rep = D.step(dt);
        ASSERT_TRUE(rep.converged) << "step " << n;
        interface += sumAll(D.counters().averagings) > worldSize();
        renumbered += sumAll(double(D.counters().renumbered)) > 0;
        Vec3 J = Vec3::Zero();
        for (std::size_t i = 0; i < S.size(); ++i)
        {
            if (D.owned()[i]) J += S.fluidDragImpulses()[i];
            ASSERT_EQ(D.grainData()[2 * i], double(D.globalIds()[i]))
                << "step " << n; // travelled, ghosts too
        }
        J = Vec3(sumAll(J.x()), sumAll(J.y()), 0.0);
        worst = std::max(worst, (momentum(scale) - p0 - J).norm() / scale);
    }
    if (worldRank() == 0)
        std::printf("[ drag ] %d ranks: |d(sum m v) - sum J|/sum m|v| at most %.2e per step\n", worldSize(),
                    worst);
    EXPECT_LT(worst, 1e-12);
    if (worldSize() > 1) EXPECT_GT(interface, 10); // steps with interface averagings
    // the gas's grains reach a rank in a scattered order: its local indices
    // are renumbered along the Morton order, and the travelling values, the
    // drag impulses and the momentum balance above went through it
    if (worldSize() > 1) EXPECT_GT(renumbered, 0);

    std::vector<double> values(S.size());
    for (std::size_t i = 0; i < S.size(); ++i)
        values[i] = D.owned()[i] ? 2.0 * double(D.globalIds()[i]) : -1.0;
    D.copyToGhosts(values, 1);
    for (std::size_t i = 0; i < S.size(); ++i) EXPECT_EQ(values[i], 2.0 * double(D.globalIds()[i]));
    EXPECT_THROW(D.setGrainDataWidth(-1), InputError);
}

// Summing to the owners: every copy of a grain (owned or ghost) holds 1, so
// after the sum an owner holds the number of ranks that hold the grain, and
// the sum over the owned grains is the number of local grains of all ranks
// (nothing lost, nothing counted twice). A grain thrown out of every region
// stays with its owner and is reported unclaimed.
TEST(Decomposed, GhostValuesSumToTheirOwnersAndLostGrainsAreReported)
{
    const std::vector<Grain> G = gasCase();
    DecomposedSystem D(2, MPI_COMM_WORLD, localSlabs(0, -2e-3, 36e-3), 3e-3);
    System& S = D.system();
    const int m = S.addMaterial({2500, 0.3});
    for (std::size_t k = 0; k < G.size(); ++k) D.addGrain(long(k), G[k].x, G[k].r, m);
    D.exchange();
    std::vector<double> ones(2 * S.size(), 1.0);
    D.sumToOwners(ones, 2);
    double owned = 0, held = 0;
    for (std::size_t i = 0; i < S.size(); ++i)
        if (D.owned()[i])
        {
            owned += ones[2 * i];
            EXPECT_EQ(ones[2 * i], ones[2 * i + 1]);
        }
    EXPECT_EQ(sumAll(owned), sumAll(double(S.size())));
    EXPECT_EQ(D.system().grainIds(), D.globalIds()); // the local System's ids are the global ones
    if (worldSize() > 1) EXPECT_GT(sumAll(double(S.size())), double(G.size())); // ghosts exist
    if (worldRank() == 0) ones.push_back(1.0); // wrong on one rank: every rank throws
    EXPECT_THROW(D.sumToOwners(ones, 2), InputError);

    // grain 0 (on the lowest slab) thrown below every region
    for (std::size_t i = 0; i < S.size(); ++i)
        if (D.globalIds()[i] == 0) S.velocities()[i] = Vec3(-2e4, 0, 0);
    D.step(1e-4);
    double lost = 0;
    for (int i : D.unclaimed())
    {
        EXPECT_EQ(D.globalIds()[i], 0);
        EXPECT_TRUE(D.owned()[i]);
        lost += 1;
    }
    EXPECT_EQ(sumAll(lost), 1.0);
    EXPECT_EQ(sumAll(double(D.counters().unclaimed)), 1.0);
    EXPECT_EQ(ownedIdsEverywhere(D).size(), G.size());
}

// A deposit settled across horizontal rank boundaries (y slabs: the weight of
// the upper ranks' grains crosses every interface). 300 discs of 0.9-1.1 mm
// dropped from a loose lattice into a box, 0.15 s. Statics: the floor carries
// the whole weight (its contact impulses over dt = sum m g, to the solver's
// tolerance); and the bed settles to the undecomposed run's height.
TEST(Decomposed, DepositCarriesItsWeightAcrossTheInterfaces)
{
    const int cols = 10, rows = 20;
    const double a = 1.15e-3, W = cols * a + 0.2e-3, H = rows * a + 1e-3;
    const std::vector<Grain> G = looseLattice(cols, rows, a, 3);
    DecomposedSystem D(2, MPI_COMM_WORLD, slabs(1, 0, 0.6 * H), 2.5e-3);
    const int m = box(D.system(), W);
    for (std::size_t k = 0; k < G.size(); ++k) D.addGrain(long(k), G[k].x, G[k].r, m);
    D.exchange();
    System serial(2);
    box(serial, W);
    for (const Grain& g : G) serial.addGrain(g.x, g.r, m);

    // statics, averaged over the last 100 steps: the walls' vertical impulse
    // (floor, and the side walls' friction) over the time = the weight
    const double dt = 5e-4;
    const int steps = 300, averaged = 100;
    int averagingsMax = 0, capped = 0;
    double loadDecomposed = 0, loadSerial = 0;
    for (int n = 0; n < steps; ++n)
    {
        const StepReport rep = D.step(dt);
        averagingsMax = std::max(averagingsMax, rep.sweeps);
        serial.step(dt);
        if (n < steps - averaged) continue;
        capped += !rep.converged; // (the pour may cap a step, not the bed at rest)
        loadDecomposed += sumAll(wallLoad(D.system(), &D.owned())) / (averaged * dt);
        loadSerial += wallLoad(serial, nullptr) / (averaged * dt);
    }
    double weight = 0;
    for (std::size_t i = 0; i < serial.size(); ++i) weight += serial.mass(i) * 9.81;
    EXPECT_NEAR(loadSerial / weight, 1.0, 1e-3);
    EXPECT_NEAR(loadDecomposed / weight, 1.0, 1e-3);
    EXPECT_EQ(capped, 0);
    // at rest, at the undecomposed run's height
    double vmax = 0, top = 0, topSerial = 0, ySum = 0;
    for (std::size_t i = 0; i < D.system().size(); ++i)
        if (D.owned()[i])
        {
            vmax = std::max(vmax, D.system().velocities()[i].norm());
            top = std::max(top, D.system().positions()[i].y() + D.system().radii()[i]);
            ySum += D.system().positions()[i].y();
        }
    vmax = maxAll(vmax);
    top = maxAll(top);
    const double yMean = sumAll(ySum) / double(G.size());
    double ySerial = 0;
    for (std::size_t i = 0; i < serial.size(); ++i)
    {
        topSerial = std::max(topSerial, serial.positions()[i].y() + serial.radii()[i]);
        ySerial += serial.positions()[i].y();
    }
    ySerial /= double(G.size());
    if (worldRank() == 0)
        std::printf("[ deposit ] %d ranks: wall load/weight %.6f (serial %.6f), top %.4f mm (serial %.4f), "
                    "mean y %.5f mm (serial %.5f), vmax %.2e m/s, sweeps/step max %d\n",
                    worldSize(), loadDecomposed / weight, loadSerial / weight, 1e3 * top, 1e3 * topSerial,
                    1e3 * yMean, 1e3 * ySerial, vmax, averagingsMax);
    EXPECT_LT(vmax, 5e-3);
    EXPECT_NEAR(top, topSerial, 0.02 * topSerial);
    EXPECT_NEAR(yMean, ySerial, 0.01 * ySerial);

    // the bed gathered whole on rank 0 (every grain once, in id order, with
    // its contacts), written, and restarted on x slabs (another
    // decomposition): the first step carries the weight to the walls at
    // once (the warm start was kept) and the bed stays at rest
    const std::string state =
        "decomposedRestart-np" + std::to_string(worldSize()) + ".h5"; // ctest runs np 1, 2, 4 at once
    std::unique_ptr<System> whole = D.gatherWhole(0);
    EXPECT_EQ(bool(whole), worldRank() == 0);
    if (whole)
    {
        ASSERT_EQ(whole->size(), G.size());
        for (std::size_t i = 0; i < G.size(); ++i) EXPECT_EQ(whole->grainIds()[i], long(i));
        EXPECT_GT(whole->nContacts(), G.size());
        EXPECT_NEAR(wallLoad(*whole, nullptr) / dt / weight, 1.0, 2e-3);
        whole->writeHDF5(state);
    }
    MPI_Barrier(MPI_COMM_WORLD);
    DecomposedSystem R(System::readHDF5(state), MPI_COMM_WORLD, localSlabs(0, 0, W), 2.5e-3);
    const StepReport rep = R.step(dt);
    EXPECT_TRUE(rep.converged);
    const double restartLoad = sumAll(wallLoad(R.system(), &R.owned())) / dt / weight;
    EXPECT_NEAR(restartLoad, 1.0, 2e-3);
    EXPECT_EQ(ownedIdsEverywhere(R).size(), G.size());
    if (worldRank() == 0)
        std::printf("[ restart ] %d ranks: first step %d sweeps, wall load/weight %.6f\n", worldSize(),
                    rep.sweeps, restartLoad);

    // the same restart without any rank reading the whole state: each reads
    // its slab grown by the halo (System::readHDF5(file, keep)); it owns the
    // same grains, holds the same ghosts, and its first step carries the
    // weight as the whole read's (the internal order is not read: the
    // solves' order differs, at the tolerance level)
    const double halo = 2.5e-3;
    const int P = worldSize(), me = worldRank();
    const auto region = [=](const Vec3& x, double)
    { return x.x() >= me * W / P - halo && x.x() < (me + 1) * W / P + halo; };
    System part = System::readHDF5(state, region);
    EXPECT_LT(part.size(), P > 1 ? G.size() : G.size() + 1);
    DecomposedSystem Rp(std::move(part), long(System::grainIdsHDF5(state).size()), MPI_COMM_WORLD,
                        localSlabs(0, 0, W), halo);
    auto idsOf = [](const DecomposedSystem& S, bool owned)
    {
        std::vector<long> ids;
        for (std::size_t i = 0; i < S.system().size(); ++i)
            if (bool(S.owned()[i]) == owned) ids.push_back(S.globalIds()[i]);
        std::sort(ids.begin(), ids.end());
        return ids;
    };
    DecomposedSystem Rw(System::readHDF5(state), MPI_COMM_WORLD, localSlabs(0, 0, W), halo);
    EXPECT_EQ(idsOf(Rp, true), idsOf(Rw, true));
    EXPECT_EQ(idsOf(Rp, false), idsOf(Rw, false));
    EXPECT_EQ(sumAll(double(Rp.system().nContacts())), sumAll(double(Rw.system().nContacts())));
    const StepReport repPart = Rp.step(dt);
    Rw.step(dt);
    EXPECT_TRUE(repPart.converged);
    const double partLoad = sumAll(wallLoad(Rp.system(), &Rp.owned())) / dt / weight;
    EXPECT_NEAR(partLoad, restartLoad, 1e-4);
    std::unordered_map<long, Vec3> xw;
    for (std::size_t i = 0; i < Rw.system().size(); ++i)
        if (Rw.owned()[i]) xw[Rw.globalIds()[i]] = Rw.system().positions()[i];
    double dx = 0;
    for (std::size_t i = 0; i < Rp.system().size(); ++i)
        if (Rp.owned()[i]) dx = std::max(dx, (Rp.system().positions()[i] - xw.at(Rp.globalIds()[i])).norm());
    dx = maxAll(dx);
    EXPECT_LT(dx, 1e-5 * 1e-3); // 1e-5 d: the contact tolerance's scale
    if (worldRank() == 0)
        std::printf("[ part read ] %d ranks: first step %d sweeps, wall load/weight %.6f, "
                    "max |x - x(whole read)| %.2e m\n",
                    worldSize(), repPart.sweeps, partLoad, dx);
    MPI_Barrier(MPI_COMM_WORLD);
    if (worldRank() == 0) std::remove(state.c_str());
}

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

/// The failures of a rank other than 0, with its rank (rank 0 prints the report).
class RankFailurePrinter : public ::testing::EmptyTestEventListener
{
    void OnTestPartResult(const ::testing::TestPartResult& r) override
    {
        if (r.failed())
            std::printf("[ rank %d ] failure in %s:%d\n%s\n", worldRank(),
                        r.file_name() ? r.file_name() : "?", r.line_number(), r.summary());
    }
};

int main(int argc, char** argv)
{
    MPI_Init(&argc, &argv);
    ::testing::InitGoogleTest(&argc, argv);
    if (worldRank() != 0) // one report: rank 0's, and the others' failures
    {
        ::testing::TestEventListeners& L = ::testing::UnitTest::GetInstance()->listeners();
        delete L.Release(L.default_result_printer());
        L.Append(new RankFailurePrinter);
    }
    const int failed = RUN_ALL_TESTS();
    int anyFailed = 0;
    MPI_Allreduce(&failed, &anyFailed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return anyFailed;
}
