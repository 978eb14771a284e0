// SPDX-License-Identifier: GPL-3.0-or-later
// Verlet list of candidate grain pairs (System::Settings::verletSkin): the
// contacts detected through the list are those of the grid scan (skin 0),
// in the same order, so the whole state stays bit-identical, for a moving
// polydisperse pile and a bed at rest, 2D and 3D, across reorders, added,
// removed and displaced grains, a fast grain, moving walls and a restart.
#include "nscd/System.H"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <unistd.h>

using namespace nscd;

namespace
{
constexpr double r0 = 1e-3; // mean radius [m]
constexpr double dt = 5e-4; // [s]

/// n polydisperse grains (radii 0.7-1.3 r0, seeded) on a jittered lattice
/// of spacing 2.8 r0 (2D: rows of 12; 3D: layers of 6 x 6) over the floor
/// of a box, added in a shuffled order; with random velocities up to
/// 0.2 m/s (moving). Walls: a plane floor; 2D: segment side walls, 3D: a
/// triangulated floor plate just under the plane floor and plane sides.
/// Gravity, reorderInterval 10, the given verletSkin.
System makePile(int dim, int n, double skin, unsigned seed, bool moving)
{
    System s(dim);
    const int m = s.addMaterial({2500, 0.4, 1e9, 0.25, 1.2, 840});
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const int row = dim == 2 ? 12 : 6;
    const double h = 2.8 * r0, W = h * row + 0.6 * r0;
    std::vector<Vec3> x, v;
    std::vector<double> r;
    for (int k = 0; k < n; ++k)
    {
        const int a = k % row, b = dim == 2 ? k / row : (k / row) % row, c = dim == 2 ? 0 : k / (row * row);
        const int level = dim == 2 ? b : c;
        Vec3 p(0.3 * r0 + h * (a + 0.5) + 0.1 * r0 * u(rng), 1.5 * r0 + h * level + 0.1 * r0 * u(rng), 0);
        if (dim == 3) p.z() = 0.3 * r0 + h * (b + 0.5) + 0.1 * r0 * u(rng);
        x.push_back(p);
        r.push_back(r0 * (1 + 0.3 * u(rng)));
        v.push_back(moving ? Vec3(0.2 * u(rng), 0.2 * u(rng), dim == 3 ? 0.2 * u(rng) : 0.0) : Vec3::Zero());
    }
    std::vector<int> perm(n);
    std::iota(perm.begin(), perm.end(), 0);
    std::shuffle(perm.begin(), perm.end(), rng);
    for (int k : perm)
    {
        const int i = s.addGrain(x[k], r[k], m);
        s.velocities()[i] = v[k];
    }
    s.addPlane(Vec3(0, 0, 0), Vec3(0, 1, 0));
    if (dim == 2)
    {
        s.addSegment(Vec3(0, 0, 0), Vec3(0, 60 * h, 0));
        s.addSegment(Vec3(W, 0, 0), Vec3(W, 60 * h, 0));
    }
    else
    {
        s.addTriangulatedSurface({Vec3(-W, -1e-4 * r0, -W), Vec3(2 * W, -1e-4 * r0, -W),
                                  Vec3(2 * W, -1e-4 * r0, 2 * W), Vec3(-W, -1e-4 * r0, 2 * W)},
                                 {{0, 1, 2}, {0, 2, 3}});
        s.addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0));
        s.addPlane(Vec3(W, 0, 0), Vec3(-1, 0, 0));
        s.addPlane(Vec3(0, 0, 0), Vec3(0, 0, 1));
        s.addPlane(Vec3(0, 0, W), Vec3(0, 0, -1));
    }
    s.setGravity(Vec3(0, -9.81, 0));
    s.settings().reorderInterval = 10;
    s.settings().verletSkin = skin;
    return s;
}

/// The same contacts (bodies, in the same order; normals, gaps, impulses)
/// and grains (positions, velocities) to the bit.
void expectIdentical(const System& a, const System& b, const std::string& where)
{
    const auto ca = a.contacts(), cb = b.contacts();
    ASSERT_EQ(ca.size(), cb.size()) << where;
    for (std::size_t k = 0; k < ca.size(); ++k)
    {
        ASSERT_EQ(ca[k].i, cb[k].i) << where << " contact " << k;
        ASSERT_EQ(ca[k].j, cb[k].j) << where << " contact " << k;
        ASSERT_TRUE(ca[k].normal == cb[k].normal && ca[k].gap == cb[k].gap && ca[k].impulse == cb[k].impulse)
            << where << " contact " << k;
    }
    ASSERT_EQ(a.size(), b.size()) << where;
    for (std::size_t i = 0; i < a.size(); ++i)
        ASSERT_TRUE(a.positions()[i] == b.positions()[i] && a.velocities()[i] == b.velocities()[i])
            << where << " grain " << i;
}

/// Step a (skin 0) and b (skin > 0) together; every step identical. @return b's list builds.
int stepBoth(System& a, System& b, int steps, const std::string& where)
{
    int builds = 0;
    for (int k = 0; k < steps; ++k)
    {
        const StepReport ra = a.step(dt), rb = b.step(dt);
        EXPECT_EQ(ra.verletBuilds, 0);
        builds += rb.verletBuilds;
        expectIdentical(a, b, where + " step " + std::to_string(k));
        if (::testing::Test::HasFatalFailure()) return builds;
    }
    return builds;
}
} // namespace

// Reference: Verlet 1967 / LAMMPS neighbour skin (Verlet.H): the listed
// pairs re-tested with the grid scan's test give the grid scan's contacts.
// A loose polydisperse pile thrown at random velocities falls and collides
// in a box (moving, reordered every 10 steps): the same contacts in the same
// order and the same state to the bit as without the list. With a small
// skin (0.02 r_min: the grains cross half of it in a fraction of a step) no
// list is built (Verlet.H, "When a list is built": it would be crossed in
// fewer than 3 detections in 2D, 1 in 3D); with a large one (3 r_min:
// ~1 mm, crossed in a few steps at 0.2-0.5 m/s) the list is built and
// rebuilt as the pile moves.
TEST(VerletList, MovingPileSameContacts)
{
    for (int dim : {2, 3})
        for (double skin : {0.02, 3.0})
        {
            const int n = dim == 2 ? 180 : 216;
            System a = makePile(dim, n, 0, 7, true), b = makePile(dim, n, skin, 7, true);
            const std::string where = "dim " + std::to_string(dim) + " skin " + std::to_string(skin);
            const int builds = stepBoth(a, b, 120, where);
            if (skin < 1)
                EXPECT_EQ(builds, 0) << where;
            else
                EXPECT_GT(builds, 5) << where;
            EXPECT_GT(a.nContacts(), std::size_t(n)) << where; // the pile has come together
        }
}

// Reference: as above. A bed settled at rest (state written and read into
// both Systems; skin 1 r_min): the same contacts and state to the bit over 60
// steps with one or two list builds; then a fast grain (8 m/s, 2 diameters
// per step: paired in the fast-grain pass; no list while it flies) dropped
// onto it, a grain moved by hand, grains removed and added, and a restart
// from the HDF5 state of the listed System (verletSkin is not saved: set
// again) stay identical too, with the list built again after each change.
TEST(VerletList, BedAtRestAndChanges)
{
    for (int dim : {2, 3})
    {
        const int n = dim == 2 ? 180 : 216;
        const std::string where = "dim " + std::to_string(dim);
        const std::string file = "testVerletList_" + std::to_string(::getpid()) + ".h5";
        {
            System s = makePile(dim, n, 0, 11, false);
            for (int k = 0; k < 600; ++k) s.step(dt);
            s.writeHDF5(file);
        }
        System a = System::readHDF5(file), b = System::readHDF5(file);
        a.settings().verletSkin = 0; // (not in the state: the default otherwise)
        b.settings().verletSkin = 1.0;
        // built at the first step, then kept (3D: once more, the settled bed still creeps)
        EXPECT_LE(stepBoth(a, b, 60, where + " at rest"), 2) << where;
        ASSERT_FALSE(::testing::Test::HasFatalFailure());

        // a fast grain dropped onto the bed (fast-grain pass of the detection)
        double top = 0;
        for (const Vec3& p : a.positions()) top = std::max(top, p.y());
        for (System* s : {&a, &b})
        {
            const int f = s->addGrain(Vec3(8 * r0, top + 6 * r0, dim == 3 ? 8 * r0 : 0.0), r0, 0);
            s->velocities()[f] = Vec3(0.5, -8.0, 0);
        }
        // while it flies (4 mm a step against half the skin, 0.35 mm) no list
        // is built; once it has landed and the bed is calm again, one is
        EXPECT_EQ(stepBoth(a, b, 1, where + " fast grain"), 0);
        EXPECT_GE(stepBoth(a, b, 10, where + " fast grain landed"), 1);
        ASSERT_FALSE(::testing::Test::HasFatalFailure());

        // a grain moved by hand (0.5 r0: beyond half the skin), grains removed, one added
        for (System* s : {&a, &b}) s->positions()[5] += Vec3(0.5 * r0, 0, 0);
        EXPECT_GE(stepBoth(a, b, 5, where + " moved"), 1);
        for (System* s : {&a, &b}) s->removeGrains({3, 40, 41});
        EXPECT_GE(stepBoth(a, b, 5, where + " removed"), 1);
        for (System* s : {&a, &b})
            s->addGrain(Vec3(20 * r0, top + 3 * r0, dim == 3 ? 5 * r0 : 0.0), 1.1 * r0, 0);
        EXPECT_GE(stepBoth(a, b, 10, where + " added"), 1);
        ASSERT_FALSE(::testing::Test::HasFatalFailure());

        // restart of the listed System: bit-exact against it and against a
        b.writeHDF5(file);
        System c = System::readHDF5(file);
        c.settings().verletSkin = 1.0;
        for (int k = 0; k < 10; ++k)
        {
            a.step(dt);
            b.step(dt);
            c.step(dt);
            expectIdentical(b, c, where + " restart step " + std::to_string(k));
            expectIdentical(a, c, where + " restart vs skin 0, step " + std::to_string(k));
            ASSERT_FALSE(::testing::Test::HasFatalFailure());
        }
        std::remove(file.c_str());
    }
}

// Reference: as above. A moving wall (a piston plane pushing into a settled
// 2D pile, 0.05 m/s: 25 um a step, against half the skin, 0.18 mm): the
// wall's displacement enters the list's cover; then a fixed grain added.
TEST(VerletList, MovingWallAndFixedGrain)
{
    System a = makePile(2, 120, 0, 3, false), b = makePile(2, 120, 0.5, 3, false);
    for (System* s : {&a, &b})
    {
        for (int k = 0; k < 200; ++k) s->step(dt);
        s->settings().verletSkin = s == &a ? 0.0 : 0.5;
        s->addPlane(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.05, 0, 0));
    }
    EXPECT_GT(stepBoth(a, b, 80, "piston"), 1);
    for (System* s : {&a, &b}) s->addGrain(s->positions()[10] + Vec3(0, 2.5 * r0, 0), r0, 0, true);
    EXPECT_GE(stepBoth(a, b, 10, "fixed grain"), 1);
}

TEST(VerletList, NegativeSkinThrows)
{
    System s = makePile(2, 10, -0.1, 1, false);
    EXPECT_THROW(s.step(dt), InputError);
    s.settings().verletSkin = std::numeric_limits<double>::infinity();
    EXPECT_THROW(s.step(dt), InputError);
}
