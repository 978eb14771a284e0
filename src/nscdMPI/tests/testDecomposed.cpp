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
// Droplets, heat and cohesion: testDecomposedCoupling.cpp (the same main).
#include "DecomposedCases.H"
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
using namespace nscdtest;
// Grains thrown across the rank boundaries (x slabs): after every step each
// id is owned exactly once, and the total momentum sum m v of the owned
// grains is that of the start (internal contact impulses only) to round-off.
/// advanceDt > 0: 30 advance(advanceDt) instead of 300 step(1e-4)
void throwGrains(const DecomposedSystem::OwnerFunction& ownerOf, double advanceDt = 0)
{
    const std::vector<Grain> G = gasCase();
    DecomposedSystem D(2, MPI_COMM_WORLD, ownerOf, 3e-3);
    System& S = D.system();
    addGrains(D, G);
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
    addGrains(D, G);
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

// Grains removed by their owners (e.g. through an outlet:
// DecomposedSystem::removeOwned): their ghost copies leave every rank, the
// sums over the copies and the next steps run on the remaining grains alone.
TEST(Decomposed, RemovedGrainsLeaveEveryRank)
{
    const std::vector<Grain> G = gasCase();
    DecomposedSystem D(2, MPI_COMM_WORLD, localSlabs(0, -2e-3, 36e-3), 3e-3);
    System& S = D.system();
    addGrains(D, G);
    D.exchange();
    D.step(1e-4);
    // every third grain, removed by its owner
    std::vector<std::size_t> mine;
    for (std::size_t i = 0; i < S.size(); ++i)
        if (D.owned()[i] && D.globalIds()[i] % 3 == 0) mine.push_back(i);
    const std::size_t before = S.size();
    const std::vector<std::size_t> removed = D.removeOwned(mine);
    EXPECT_EQ(S.size(), before - removed.size());
    EXPECT_TRUE(std::is_sorted(removed.begin(), removed.end()));
    for (long id : S.grainIds()) EXPECT_NE(id % 3, 0);
    if (worldSize() > 1) EXPECT_GT(sumAll(double(removed.size() - mine.size())), 0.0); // ghosts went too
    std::vector<long> kept;
    for (long k = 0; k < long(G.size()); ++k)
        if (k % 3 != 0) kept.push_back(k);
    EXPECT_EQ(ownedIdsEverywhere(D), kept);
    // every copy of a grain counts its copies: the ghost lists stayed aligned
    std::vector<double> ones(S.size(), 1.0);
    D.sumToOwners(ones, 1);
    D.copyToGhosts(ones, 1);
    double owned = 0;
    for (std::size_t i = 0; i < S.size(); ++i) owned += D.owned()[i] ? ones[i] : 0.0;
    EXPECT_EQ(sumAll(owned), sumAll(double(S.size())));
    for (int k = 0; k < 5; ++k) EXPECT_TRUE(D.step(1e-4).converged);
    EXPECT_EQ(ownedIdsEverywhere(D), kept);
    std::unique_ptr<System> whole = D.gatherWhole(0);
    if (worldRank() == 0) EXPECT_EQ(whole->size(), kept.size());
}

// The restart of DepositCarriesItsWeightAcrossTheInterfaces without any
// rank reading the whole state: each reads its slab grown by the halo
// (System::readHDF5(file, keep)) of the n grains of `state` in a box of
// width W; it owns the same grains, holds the same ghosts, and its first
// step of dt carries the weight as the whole read's (restartLoad: wall load
// over the weight; the internal order is not read: the solves' order
// differs, at the tolerance level).
void partReadMatchesWholeRead(const std::string& state, std::size_t n, double W, double dt, double weight,
                              double restartLoad)
{
    const double halo = 2.5e-3;
    const int P = worldSize(), me = worldRank();
    const auto region = [=](const Vec3& x, double)
    { return x.x() >= me * W / P - halo && x.x() < (me + 1) * W / P + halo; };
    System part = System::readHDF5(state, region);
    EXPECT_LT(part.size(), P > 1 ? n : n + 1);
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

    partReadMatchesWholeRead(state, G.size(), W, dt, weight, restartLoad);
    MPI_Barrier(MPI_COMM_WORLD);
    if (worldRank() == 0) std::remove(state.c_str());
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
