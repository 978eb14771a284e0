// SPDX-License-Identifier: GPL-3.0-or-later
// Per-grain columns (nscd/GrainColumns.H) in a decomposed run (run by ctest
// on 1, 2 and 4 ranks with testDecomposed.cpp's main): a column declared
// with ColumnMigrate travels with its grains between the ranks, with
// ColumnGhost it is copied to the ghosts too, and gatherWhole gathers it.
#include "nscdMPI/DecomposedSystem.H"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

using namespace nscd;
using nscd::mpi::DecomposedSystem;

namespace
{
int rankOf(MPI_Comm c)
{
    int r;
    MPI_Comm_rank(c, &r);
    return r;
}
int sizeOf(MPI_Comm c)
{
    int p;
    MPI_Comm_size(c, &p);
    return p;
}

double total(double x)
{
    double s = 0;
    MPI_Allreduce(&x, &s, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    return s;
}

/// Values of grain id g in step n.
double charge(long g, int n) { return 1e-3 * double(g) + double(n); }
Vec3 spin(long g) { return Vec3(double(g), 0.5, -double(g)); }
} // namespace

// A gas of 400 discs crossing x slabs: every owned grain holds its values
// after each step (migrated ones too), ghosts hold the owner's value of a
// ColumnGhost column and the default or a former value of the others, and
// the gathered whole system holds every grain's values.
TEST(DecomposedColumns, ColumnsTravelWithTheirGrains)
{
    const int P = sizeOf(MPI_COMM_WORLD);
    const double lo = -2e-3, hi = 36e-3;
    auto owner = [=](const Vec3& x, long)
    { return std::clamp(int(std::floor((x.x() - lo) / (hi - lo) * P)), 0, P - 1); };
    DecomposedSystem D(2, MPI_COMM_WORLD, owner, 3e-3);
    System& S = D.system();
    const int m = S.addMaterial({2500, 0.3});
    S.addColumn<double>("charge", ColumnMigrate | ColumnGhost, -1.0);
    S.addColumn<Vec3>("spin", ColumnMigrate, Vec3::Zero());
    S.addColumn<long>("birth", ColumnMigrate | ColumnGhost | ColumnRestart, -1L);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    const double a = 1.2e-3;
    const Vec3 c(10 * a, 10 * a, 0);
    for (int k = 0; k < 400; ++k)
    {
        const Vec3 x((k % 20 + 0.5) * a, (k / 20 + 0.5) * a, 0);
        const double r = 0.5e-3 * (0.95 + 0.05 * u(rng));
        const Vec3 v = -20 * (x - c) + 0.1 * Vec3(u(rng), u(rng), 0) + Vec3(0.4, 0, 0);
        const std::size_t i = D.addGrain(long(k), x, r, m);
        if (i == std::size_t(-1)) continue;
        S.velocities()[i] = v;
        S.column<Vec3>("spin")[i] = spin(k);
        S.column<long>("birth")[i] = 7L * k;
    }
    D.exchange();
    long migrated = 0, ghostsChecked = 0;
    for (int n = 0; n < 100; ++n)
    {
        auto& q = S.column<double>("charge");
        for (std::size_t i = 0; i < S.size(); ++i)
            if (D.owned()[i]) q[i] = charge(D.globalIds()[i], n);
        ASSERT_TRUE(D.step(1e-4).converged) << "step " << n;
        migrated += D.counters().migratedOut;
        const auto& q2 = S.column<double>("charge");
        const auto& s = S.column<Vec3>("spin");
        const auto& b = S.column<long>("birth");
        ASSERT_EQ(q2.size(), S.size());
        for (std::size_t i = 0; i < S.size(); ++i)
        {
            const long g = D.globalIds()[i];
            ASSERT_EQ(q2[i], charge(g, n))
                << "step " << n << ", grain " << g << (D.owned()[i] ? "" : " (ghost)");
            ASSERT_EQ(b[i], 7L * g) << "step " << n << ", grain " << g;
            if (D.owned()[i])
                ASSERT_EQ(s[i], spin(g)) << "step " << n << ", grain " << g;
            else
            {
                // not copied to ghosts: the default, or the value of a grain that was owned here
                ASSERT_TRUE(s[i] == Vec3::Zero() || s[i] == spin(g)) << "step " << n << ", ghost " << g;
                ++ghostsChecked;
            }
        }
    }
    if (P > 1)
    {
        EXPECT_GT(total(double(migrated)), 20); // grains changed ranks
        EXPECT_GT(total(double(ghostsChecked)), 100);
    }
    const std::unique_ptr<System> whole = D.gatherWhole(0);
    if (rankOf(MPI_COMM_WORLD) == 0)
    {
        ASSERT_EQ(whole->size(), 400u);
        for (std::size_t i = 0; i < whole->size(); ++i)
        {
            const long g = whole->grainIds()[i];
            EXPECT_EQ(whole->column<double>("charge")[i], charge(g, 99));
            EXPECT_EQ(whole->column<Vec3>("spin")[i], spin(g));
            EXPECT_EQ(whole->column<long>("birth")[i], 7L * g);
        }
    }
}
