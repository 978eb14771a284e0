// SPDX-License-Identifier: GPL-3.0-or-later
// Internal grain order along the Morton curve (System::Settings::
// reorderInterval): the curve itself, the same physics with and without it,
// the external grain order of the interface and of the HDF5 state, and a
// bit-exact restart across reorders.
#include "Reorder.H"
#include "nscd/Permutation.H"
#include "nscd/System.H"

#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <unistd.h>

using namespace nscd;

namespace
{
constexpr double g0 = 9.81;

/// n grains over the floor of a box (2D: rows of 15 discs; 3D: layers of
/// 6 x 6 spheres, lattice spacing 2.2 mm, odd rows/layers shifted), radii
/// 0.9-1.1 mm; lowered: each grain is put on the grains below it (lowest
/// height without overlap), so the pile starts dense and close to rest;
/// otherwise a loose lattice that falls. Added in a shuffled order (seed),
/// so that the order of addition is far from the spatial one.
System makePile(int dim, int n, unsigned seed, int reorderInterval, bool lowered = false)
{
    System s(dim);
    const int m = s.addMaterial({2500, 0.4, 1e9, 0.25, 1.2, 840});
    std::vector<Vec3> x;
    std::vector<double> r;
    const int row = dim == 2 ? 15 : 6;
    for (int k = 0; k < n; ++k)
    {
        const int a = k % row, b = dim == 2 ? k / row : (k / row) % row, c = dim == 2 ? 0 : k / (row * row);
        const double h = 2.2e-3;
        const double shift = 1.1e-3 * ((dim == 2 ? b : c) % 2);
        const double ri = 1e-3 * (0.9 + 0.2 * ((k * 37) % 11) / 10.0);
        Vec3 p = dim == 2 ? Vec3(1.1e-3 + h * a + shift, 1.1e-3 + 2.05e-3 * b, 0)
                          : Vec3(1.1e-3 + h * a + shift, 1.1e-3 + 2.05e-3 * c, 1.1e-3 + h * b + shift);
        if (lowered)
        {
            double y = ri * (1 + 1e-9);
            for (int j = 0; j < k; ++j)
            {
                const double dx = p.x() - x[j].x(), dz = p.z() - x[j].z();
                const double h2 = dx * dx + dz * dz, rr = (ri + r[j]) * (1 + 1e-9);
                if (h2 < rr * rr) y = std::max(y, x[j].y() + std::sqrt(rr * rr - h2));
            }
            p.y() = y;
        }
        x.push_back(p);
        r.push_back(ri);
    }
    std::vector<int> perm(n);
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
    for (int k : perm) s.addGrain(x[k], r[k], m);
    const double W = 2.2e-3 * row + 1.1e-3;
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
    s.addPlane(Vec3(W, 0, 0), Vec3(-1, 0, 0));
    if (dim == 3)
    {
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 0, 1));
        s.addPlane(Vec3(0, 0, W), Vec3(0, 0, -1));
    }
    s.setGravity(Vec3(0, -g0, 0));
    s.settings().reorderInterval = reorderInterval;
    return s;
}

/// The "grainOrder" dataset of a state file (slot -> grain), read directly.
std::vector<int> fileOrder(const std::string& file)
{
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, "grainOrder", H5P_DEFAULT);
    const hid_t sp = H5Dget_space(d);
    hsize_t n = 0;
    H5Sget_simple_extent_dims(sp, &n, nullptr);
    std::vector<int> out(n);
    H5Dread(d, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
    H5Sclose(sp);
    H5Dclose(d);
    H5Fclose(f);
    return out;
}

/// The "positions" dataset of a state file, read directly (N x 3).
std::vector<double> filePositions(const std::string& file)
{
    const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, "positions", H5P_DEFAULT);
    const hid_t sp = H5Dget_space(d);
    hsize_t n[2] = {0, 0};
    H5Sget_simple_extent_dims(sp, n, nullptr);
    std::vector<double> out(n[0] * n[1]);
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
    H5Sclose(sp);
    H5Dclose(d);
    H5Fclose(f);
    return out;
}

std::string tmpName(const char* tag)
{
    return std::string("testReorder_") + tag + "_" + std::to_string(::getpid()) + ".h5";
}

/// Contacts as a map (smaller grain, larger grain or wall code) -> impulse on the smaller grain.
using ContactMap = std::map<std::pair<int, int>, Vec3>;

/// Same contacts (bodies) and impulses to round-off (setContactImpulses
/// splits an impulse into normal and tangential parts again).
void expectSameContacts(const ContactMap& a, const ContactMap& b)
{
    ASSERT_EQ(a.size(), b.size());
    double scale = 0;
    for (const auto& e : b) scale = std::max(scale, e.second.norm());
    for (auto p = a.begin(), q = b.begin(); p != a.end(); ++p, ++q)
    {
        ASSERT_EQ(p->first, q->first);
        EXPECT_LE((p->second - q->second).norm(), 1e-12 * scale) << p->first.first << " " << p->first.second;
    }
}

std::map<std::pair<int, int>, Vec3> contactMap(const System& s)
{
    std::map<std::pair<int, int>, Vec3> m;
    for (const auto& v : s.contacts())
    {
        const bool swap = v.j >= 0 && v.j < v.i;
        const std::pair<int, int> key = swap ? std::make_pair(v.j, v.i) : std::make_pair(v.i, v.j);
        auto it = m.emplace(key, Vec3::Zero()).first; // (Vec3() is not zeroed)
        it->second += swap ? Vec3(-v.impulse) : v.impulse;
    }
    return m;
}
} // namespace

// The Morton key interleaves the bits of the cell indices (definition:
// Morton 1966), checked against a bit-by-bit interleave, and orders a 4 x 4
// grid along the Z curve.
TEST(Reorder, MortonKeyAndCurve)
{
    std::mt19937 gen(3);
    for (int t = 0; t < 1000; ++t)
    {
        const std::uint32_t i = gen() & 0x1fffff, j = gen() & 0x1fffff, k = gen() & 0x1fffff;
        std::uint64_t k2 = 0, k3 = 0;
        for (int b = 0; b < 21; ++b)
        {
            k2 |= std::uint64_t((i >> b) & 1) << (2 * b) | std::uint64_t((j >> b) & 1) << (2 * b + 1);
            k3 |= std::uint64_t((i >> b) & 1) << (3 * b) | std::uint64_t((j >> b) & 1) << (3 * b + 1)
                  | std::uint64_t((k >> b) & 1) << (3 * b + 2);
        }
        ASSERT_EQ(mortonKey2(i, j), k2);
        ASSERT_EQ(mortonKey3(i, j, k), k3);
    }
    EXPECT_EQ(mortonKey2(0xffffffffu, 0), 0x5555555555555555ULL);
    // 4 x 4 points, index a + 4 b at cell (a, b), given in reverse order
    std::vector<Vec3> x;
    for (int p = 15; p >= 0; --p) x.emplace_back(p % 4 + 0.5, p / 4 + 0.5, 0);
    const std::vector<int> ord = mortonOrder(x, 2, 1.0);
    const int z[16] = {0, 1, 4, 5, 2, 3, 6, 7, 8, 9, 12, 13, 10, 11, 14, 15};
    for (int s = 0; s < 16; ++s) EXPECT_EQ(15 - ord[s], z[s]) << "slot " << s;
}

// The re-sort is applied only to an order that scatters neighbours: a bed
// kept in its row-by-row fill order (60 x 20 grid, rows 60 apart in memory,
// window min(4096, N/8) = 150) is kept, the same grains shuffled are
// re-sorted; a System built in row order is never reordered (its state's
// grainOrder stays the identity). Consistency check of the rule (Reorder.H).
TEST(Reorder, OnlyScatteredOrdersAreResorted)
{
    std::vector<Vec3> x;
    for (int b = 0; b < 20; ++b)
        for (int a = 0; a < 60; ++a) x.emplace_back(a + 0.5 + 0.01 * (b % 3), b + 0.5, 0);
    const std::vector<int> curve = mortonOrder(x, 2, 1.0);
    std::vector<int> slotOf(x.size());
    std::iota(slotOf.begin(), slotOf.end(), 0);
    EXPECT_FALSE(orderIsScattered(curve, slotOf));
    std::shuffle(slotOf.begin(), slotOf.end(), std::mt19937(1));
    EXPECT_TRUE(orderIsScattered(curve, slotOf));
    // a pile added row by row (15 discs a row): kept
    System s(2);
    const int m = s.addMaterial({2500, 0.4});
    for (int k = 0; k < 300; ++k)
        s.addGrain(Vec3(1.1e-3 + 2.2e-3 * (k % 15), 1.1e-3 + 2.05e-3 * (k / 15), 0), 1e-3, m);
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    s.setGravity(Vec3(0, -g0, 0));
    s.settings().reorderInterval = 1;
    for (int k = 0; k < 5; ++k) s.step(1e-4);
    const std::string f = tmpName("rows");
    s.writeHDF5(f);
    const std::vector<int> ord = fileOrder(f);
    std::vector<int> id(ord.size());
    std::iota(id.begin(), id.end(), 0);
    EXPECT_EQ(ord, id);
    std::remove(f.c_str());
}

// Bookkeeping exact: grains that touch only walls (a sparse layer on the
// floor, fixed-temperature floor, drag, external forces, a locked rotation)
// have independent contacts, so the visiting order cannot change the result:
// the run with reordering equals the run without bit for bit, grain by grain
// in the external order (per-grain data attached to the right grain).
TEST(Reorder, IndependentGrainsBitIdentical)
{
    for (int dim : {2, 3})
    {
        auto make = [dim](int interval)
        {
            System s(dim);
            const int m = s.addMaterial({2500, 0.4, 1e9, 0.25, 1.2, 840});
            std::mt19937 gen(5);
            std::uniform_real_distribution<double> U(0.8e-3, 1.2e-3);
            std::vector<int> cells(dim == 2 ? 40 : 64);
            std::iota(cells.begin(), cells.end(), 0);
            std::shuffle(cells.begin(), cells.end(), gen);
            for (int c : cells)
            {
                const double r = U(gen);
                const Vec3 p = dim == 2
                                   ? Vec3(3e-3 * (c + 0.5), r + 1e-5 * (c % 3), 0)
                                   : Vec3(3e-3 * (c % 8 + 0.5), r + 1e-5 * (c % 3), 3e-3 * (c / 8 + 0.5));
                const int k = s.addGrain(p, r, m);
                s.velocities()[k] = Vec3(0.01 * (c % 5 - 2), -0.02, 0);
                s.angularVelocities()[k] = Vec3(0, 0, 3.0 * (c % 4));
                s.setExternalForce(k, Vec3(1e-6 * c, 0, 0), Vec3(0, 0, 1e-10 * (c % 7)));
                s.setFluidDrag(k, 1e-4 * (c % 3), Vec3(0.05, 0.01 * (c % 2), 0));
                s.setHeatExchange(k, 1e-4 * (c % 4), 300 + c);
                s.temperatures()[k] = 290 + 0.5 * c;
                if (c % 6 == 0) s.setRotationLocked(k);
            }
            const int floor = s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
            s.setWallTemperature(floor, 400);
            s.setGravity(Vec3(0, -g0, 0));
            s.settings().reorderInterval = interval;
            return s;
        };
        System a = make(0), b = make(3);
        for (int k = 0; k < 40; ++k)
        {
            const StepReport ra = a.step(1e-4), rb = b.step(1e-4);
            ASSERT_EQ(ra.contacts, rb.contacts);
        }
        EXPECT_EQ(a.positions(), b.positions()) << "dim " << dim;
        EXPECT_EQ(a.velocities(), b.velocities());
        EXPECT_EQ(a.angularVelocities(), b.angularVelocities());
        EXPECT_EQ(a.temperatures(), b.temperatures());
        EXPECT_EQ(a.fluidDragImpulses(), b.fluidDragImpulses());
        EXPECT_EQ(contactMap(a), contactMap(b));
        // and the order did change
        const std::string f = tmpName("indep");
        b.writeHDF5(f);
        const std::vector<int> ord = fileOrder(f);
        std::vector<int> id(ord.size());
        std::iota(id.begin(), id.end(), 0);
        EXPECT_NE(ord, id);
        std::remove(f.c_str());
    }
}

// Same physics: a dense pile (300 discs / 216 spheres, each put on the
// grains below it, added in a shuffled order) settles on the floor, with and
// without reordering. The NLGS queue then visits the contacts in another
// order, so the runs agree to the solver tolerance, not bit for bit. The
// yardstick is the solver's own error: the same run without reordering at a
// 10 times tighter tolerance. Measured (tolerance 1e-8 d_min, 100 steps of
// 1e-4 s, max position difference over the run): reordering 1.2e-5 d_min in
// 2D and 8.8e-6 in 3D, tighter tolerance 1.3e-5 (2D) and 1.6e-5 (3D); asserted: the
// reordering changes the positions by less than 3 times what the tolerance
// does, and the floor load by less than 1e-3. (A loose pile that falls is
// chaotic: round-off differences grow to a fraction of a diameter whatever
// their cause, so it is not compared.)
TEST(Reorder, PileSamePhysicsWithinTolerance)
{
    for (int dim : {2, 3})
    {
        const int n = dim == 2 ? 300 : 216;
        System a = makePile(dim, n, 7, 0, true), b = makePile(dim, n, 7, 10, true),
               c = makePile(dim, n, 7, 0, true);
        for (System* s : {&a, &b, &c})
        {
            s->settings().tolerance = 1e-8;
            s->settings().maxIterations = 100000;
        }
        c.settings().tolerance = 1e-9;
        const double dt = 1e-4;
        double worst = 0, worstTol = 0;
        for (int k = 0; k < 100; ++k)
        {
            a.step(dt);
            b.step(dt);
            c.step(dt);
            for (std::size_t i = 0; i < a.size(); ++i)
            {
                worst = std::max(worst, (a.positions()[i] - b.positions()[i]).norm());
                worstTol = std::max(worstTol, (a.positions()[i] - c.positions()[i]).norm());
            }
        }
        const double d = a.minDiameter();
        std::printf("dim %d: max |x_reorder - x| = %.3e d_min, max |x_tol/10 - x| = %.3e d_min\n", dim,
                    worst / d, worstTol / d);
        EXPECT_LT(worst, 3 * worstTol) << "dim " << dim;
        EXPECT_NEAR(double(a.nContacts()), double(b.nContacts()), 0.01 * a.nContacts());
        auto floorLoad = [dt](const System& s)
        {
            double load = 0;
            for (const auto& v : s.contacts())
                if (v.j == -1) load += v.impulse.y() / dt;
            return load;
        };
        EXPECT_NEAR(floorLoad(b), floorLoad(a), 1e-3 * floorLoad(a)) << "dim " << dim;
    }
}

// External order: with reordering on, grain k of the interface stays the
// k-th grain added (ids, radii, materials, a force applied to grain k moves
// grain k), contacts name neighbouring grains, and the HDF5 state holds the
// grains in the order of addition while its grainOrder is not the identity.
TEST(Reorder, ExternalOrderUnchanged)
{
    System s = makePile(2, 300, 11, 5);
    const std::vector<double> r0 = s.radii();
    for (int k = 0; k < 60; ++k) s.step(2e-4);
    ASSERT_EQ(s.radii(), r0);
    for (std::size_t i = 0; i < s.size(); ++i) ASSERT_EQ(s.grainIds()[i], long(i));
    // every grain-grain contact joins grains that are neighbours in positions()
    for (const auto& v : s.contacts())
    {
        if (v.j == -1) EXPECT_LT(s.positions()[v.i].y() - s.radii()[v.i], 1e-4); // floor
        if (v.j < 0) continue;
        EXPECT_LT(v.i, v.j); // grain pairs i < j, as without reordering
        const double gap = (s.positions()[v.i] - s.positions()[v.j]).norm() - r0[v.i] - r0[v.j];
        EXPECT_LT(gap, 0.1 * s.minDiameter()) << v.i << " " << v.j;
        EXPECT_NEAR(v.normal.dot((s.positions()[v.i] - s.positions()[v.j]).normalized()), 1.0, 1e-3);
    }
    // the highest grain, pushed up with 100 times its weight, is the one
    // that rises (against the same run without the push)
    int top = 0;
    for (std::size_t i = 0; i < s.size(); ++i)
        if (s.positions()[i].y() > s.positions()[top].y()) top = int(i);
    {
        const std::string f0 = tmpName("push");
        s.writeHDF5(f0);
        System t = System::readHDF5(f0);
        std::remove(f0.c_str());
        t.setExternalForce(top, Vec3(0, 100 * s.mass(top) * g0, 0));
        for (int k = 0; k < 10; ++k)
        {
            s.step(2e-4);
            t.step(2e-4);
        }
        for (std::size_t i = 0; i < s.size(); ++i)
        {
            const double dy = t.positions()[i].y() - s.positions()[i].y();
            if (int(i) == top)
                EXPECT_GT(dy, 0.1 * r0[i]);
            else
                EXPECT_LT(std::abs(dy), 0.02 * r0[i]) << "grain " << i;
        }
    }
    const std::string f = tmpName("order");
    s.writeHDF5(f);
    const std::vector<double> xf = filePositions(f);
    ASSERT_EQ(xf.size(), 3 * s.size());
    for (std::size_t i = 0; i < s.size(); ++i)
        for (int c = 0; c < 3; ++c) ASSERT_EQ(xf[3 * i + c], s.positions()[i][c]);
    const std::vector<int> ord = fileOrder(f);
    std::vector<int> id(ord.size());
    std::iota(id.begin(), id.end(), 0);
    EXPECT_NE(ord, id);
    EXPECT_TRUE(std::is_permutation(ord.begin(), ord.end(), id.begin()));
    const System r = System::readHDF5(f);
    EXPECT_EQ(r.positions(), s.positions());
    EXPECT_EQ(contactMap(r), contactMap(s));
    EXPECT_EQ(r.settings().reorderInterval, 5);
    std::remove(f.c_str());
}

// Restart contract with reordering (interval 7: reorders at steps 1, 8, 15,
// ...): 2N steps == N steps + write + read + N steps, bit for bit, for a
// write in the middle of an interval (N = 30) and just before a reorder
// (N = 35: the restarted run must reorder at its first step).
TEST(Reorder, RestartAfterReorderIsBitExact)
{
    for (int dim : {2, 3})
        for (int N : {30, 35})
        {
            const int n = dim == 2 ? 300 : 216;
            System a = makePile(dim, n, 13, 7);
            for (int k = 0; k < 2 * N; ++k) a.step(2e-4);
            System b = makePile(dim, n, 13, 7);
            for (int k = 0; k < N; ++k) b.step(2e-4);
            const std::string f = tmpName("restart");
            b.writeHDF5(f);
            System c = System::readHDF5(f);
            for (int k = 0; k < N; ++k) c.step(2e-4);
            EXPECT_EQ(a.positions(), c.positions()) << "dim " << dim << " N " << N;
            EXPECT_EQ(a.velocities(), c.velocities());
            EXPECT_EQ(a.angularVelocities(), c.angularVelocities());
            for (std::size_t i = 0; i < a.size(); ++i)
                ASSERT_EQ(a.orientations()[i].coeffs(), c.orientations()[i].coeffs());
            EXPECT_EQ(contactMap(a), contactMap(c));
            std::remove(f.c_str());
        }
}

// removeGrains, setContactImpulses and the cohesion predicate with
// reordering on: the contact records follow the grains (consistency checks
// of the bookkeeping).
TEST(Reorder, RemoveSeedAndCohesionFollowGrains)
{
    System s = makePile(2, 300, 17, 4);
    double worstGap = -1;
    bool pairOrder = true; // grain pairs given with i < j
    s.setCohesion(
        [&](int i, int j)
        {
            const double r = j >= 0 ? s.radii()[j] : 0;
            const double gap = j >= 0 ? (s.positions()[i] - s.positions()[j]).norm() - s.radii()[i] - r
                                      : s.positions()[i].y() - s.radii()[i];
            if (j != -2 && j != -3) worstGap = std::max(worstGap, gap); // side walls: not checked
            if (j >= 0 && !(i < j)) pairOrder = false;
            return true;
        },
        1e-6);
    for (int k = 0; k < 40; ++k) s.step(2e-4);
    // (within cohesionDistance at detection; a wrong grain would be diameters away)
    EXPECT_LT(worstGap, 0.25 * s.minDiameter());
    EXPECT_TRUE(pairOrder);
    // setContactImpulses(contacts()) gives back the same contacts
    const auto before = contactMap(s);
    s.setContactImpulses(s.contacts(), 2e-4);
    expectSameContacts(contactMap(s), before);
    // remove grains 5, 17, 100: the others' contacts are kept, renumbered
    const std::set<int> gone = {5, 17, 100};
    std::map<std::pair<int, int>, Vec3> expected;
    auto renum = [&](int i)
    {
        int k = i;
        for (int g : gone)
            if (g < i) --k;
        return k;
    };
    for (const auto& e : before)
    {
        const int i = e.first.first, j = e.first.second;
        if (gone.count(i) || (j >= 0 && gone.count(j))) continue;
        expected[{renum(i), j >= 0 ? renum(j) : j}] = e.second;
    }
    const std::vector<Vec3> x0 = s.positions();
    s.removeGrains({100, 5, 17});
    expectSameContacts(contactMap(s), expected);
    for (std::size_t i = 0; i < s.size(); ++i)
        ASSERT_EQ(s.positions()[i], x0[i + (i >= 5) + (i >= 16) + (i >= 98)]);
    for (int k = 0; k < 10; ++k) s.step(2e-4);
}

// permuteInPlace against the copy b[k] = a[oldOf[k]] (definition), for
// random permutations (long cycles), fixed points and a strided view.
TEST(Reorder, PermuteInPlaceMatchesTheCopy)
{
    std::mt19937 rng(5);
    for (int N : {1, 2, 7, 1000})
    {
        std::vector<std::size_t> oldOf(N);
        std::iota(oldOf.begin(), oldOf.end(), 0);
        std::shuffle(oldOf.begin(), oldOf.end(), rng);
        if (N > 2) std::swap(oldOf[0], *std::find(oldOf.begin(), oldOf.end(), 0)); // a fixed point
        std::vector<int> a(N);
        std::vector<double> pairs(2 * N);
        for (int k = 0; k < N; ++k)
        {
            a[k] = 10 * k;
            pairs[2 * k] = k;
            pairs[2 * k + 1] = -k;
        }
        std::vector<int> want(N);
        for (int k = 0; k < N; ++k) want[k] = a[oldOf[k]];
        StridedView<double> first{pairs, 2, 0};
        permuteInPlace(oldOf, a, first);
        EXPECT_EQ(a, want) << N;
        for (int k = 0; k < N; ++k)
        {
            ASSERT_EQ(pairs[2 * k], double(oldOf[k]));
            ASSERT_EQ(pairs[2 * k + 1], -double(k)); // the other component is left alone
        }
    }
}

// renumberAlongInternalOrder (the local indices of a decomposed system
// follow the Morton order): grain k afterwards is grain result[k] before,
// with its whole state, and the run goes on as the run that was not
// renumbered, bit for bit, because the solve visits the same slots in the
// same order (consistency check of the bookkeeping; the physics is the
// same run's).
TEST(Reorder, RenumberAlongInternalOrderKeepsTheRun)
{
    for (int dim : {2, 3})
    {
        const int n = dim == 2 ? 300 : 216;
        System a = makePile(dim, n, 19, 5);
        System b = makePile(dim, n, 19, 5);
        for (System* s : {&a, &b})
        {
            for (int k = 0; k < 12; ++k) s->step(2e-4); // reordered at steps 1, 6 and 11
            for (std::size_t i = 0; i < s->size(); ++i) s->temperatures()[i] = 300 + double(i);
            s->setExternalForce(7, Vec3(0, 3 * s->mass(7) * g0, 0));
        }
        const std::vector<std::size_t> oldOf = b.renumberAlongInternalOrder();
        ASSERT_EQ(oldOf.size(), b.size()) << "dim " << dim << ": the shuffled pile is scattered";
        EXPECT_TRUE(b.renumberAlongInternalOrder().empty()); // in order now
        for (std::size_t k = 0; k < b.size(); ++k)
        {
            const std::size_t i = oldOf[k];
            ASSERT_EQ(b.grainIds()[k], a.grainIds()[i]);
            ASSERT_EQ(b.positions()[k], a.positions()[i]);
            ASSERT_EQ(b.radii()[k], a.radii()[i]);
            ASSERT_EQ(b.temperatures()[k], a.temperatures()[i]);
        }
        // (the external force on grain 7 went with it: the runs agree below)
        for (int k = 0; k < 30; ++k)
        {
            a.step(2e-4);
            b.step(2e-4);
        }
        for (std::size_t k = 0; k < b.size(); ++k)
        {
            const std::size_t i = oldOf[k];
            ASSERT_EQ(b.positions()[k], a.positions()[i]) << "dim " << dim << " grain " << i;
            ASSERT_EQ(b.velocities()[k], a.velocities()[i]);
            ASSERT_EQ(b.angularVelocities()[k], a.angularVelocities()[i]);
        }
        // the contacts: the same pairs of grains with the same impulses
        ContactMap ca = contactMap(a), cb;
        for (const auto& e : contactMap(b))
        {
            int i = int(oldOf[e.first.first]),
                j = e.first.second >= 0 ? int(oldOf[e.first.second]) : e.first.second;
            const bool swap = j >= 0 && j < i;
            cb[swap ? std::make_pair(j, i) : std::make_pair(i, j)] = swap ? Vec3(-e.second) : e.second;
        }
        EXPECT_EQ(ca, cb);
    }
}

// Bad input: a negative interval is an InputError at the next step.
TEST(Reorder, NegativeIntervalThrows)
{
    System s = makePile(2, 30, 1, -1);
    EXPECT_THROW(s.step(1e-4), InputError);
}
