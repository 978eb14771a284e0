// SPDX-License-Identifier: GPL-3.0-or-later
// Broad phase: uniform grid vs brute force; timing vs CGAL box_intersection_d.
#include "nscd/System.H"

#include <CGAL/Bbox_2.h>
#include <CGAL/Bbox_3.h>
#include <CGAL/box_intersection_d.h>

#include <gtest/gtest.h>

#include <chrono>
#include <iostream>
#include <random>
#include <set>

using namespace nscd;

namespace
{
System randomSet(int dim, int n, double L, unsigned seed)
{
    System s(dim);
    const int m = s.addMaterial({1000, 0.3});
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> X(0, L), R(0.005, 0.03); // polydisperse, ratio 6
    for (int k = 0; k < n; ++k) s.addGrain(Vec3(X(gen), X(gen), dim == 3 ? X(gen) : 0.0), R(gen), m);
    return s;
}
} // namespace

// Reference: brute-force O(N^2) pair search with the same alert distance
// (grains at rest: alert = alertMargin * r_min); sets must be identical.
TEST(BroadPhase, GridFindsEveryBruteForcePair)
{
    for (int dim : {2, 3})
    {
        const int n = dim == 2 ? 1500 : 2000;
        System s = randomSet(dim, n, dim == 2 ? 1.0 : 0.4, 42 + dim);
        s.settings().alertMargin = 0.3;
        s.settings().maxIterations = 1; // only detection matters here
        // overlaps of the random set only held (no push-out velocity: no grain
        // leaves its reach, so the detection is not repeated with larger ones)
        s.settings().overlapSlop = 1e6;
        const auto x = s.positions();
        const auto& r = s.radii();
        double rmin = 1e9;
        for (double a : r) rmin = std::min(rmin, a);
        const double alert = s.settings().alertMargin * rmin;
        std::set<std::pair<int, int>> brute;
        for (int i = 0; i < n; ++i)
            for (int j = i + 1; j < n; ++j)
                if ((x[i] - x[j]).norm() - r[i] - r[j] < alert) brute.insert({i, j});
        EXPECT_EQ(s.step(1e-9).redetections, 0);
        std::set<std::pair<int, int>> grid;
        for (const auto& c : s.contacts()) grid.insert({std::min(c.i, c.j), std::max(c.i, c.j)});
        EXPECT_GT(brute.size(), std::size_t(100));
        EXPECT_EQ(grid, brute) << "dim " << dim;
    }
}

// Reference: brute-force O(N^2) pair search with each pair's alert distance
// af dt (s_i + s_j) + alertMargin r_min, s = |v| + r|w| (no force: the free
// velocity is the velocity), on a bed at rest with fast grains (paired in
// the separate pass of the broad phase): 5 fast grains, then 200 (more than
// the pass takes: the slowest of them go back to the grid), and two fast
// grains outside the box of the others (a fast-fast pair). Every
// brute-force pair must be found; pairs beyond it only if the step was
// re-detected with larger reaches (a fast grain hit something).
TEST(BroadPhase, FastGrainsFindEveryBruteForcePair)
{
    for (int dim : {2, 3})
        for (int nFast : {5, 200})
        {
            const int n = dim == 2 ? 1500 : 2000;
            System s = randomSet(dim, n, dim == 2 ? 1.0 : 0.4, 7 + dim);
            s.settings().maxIterations = 1;
            s.settings().overlapSlop = 1e6;
            const double dt = 1e-3;
            std::mt19937 gen(5);
            std::normal_distribution<double> G(0, 1);
            for (int k = 0; k < nFast; ++k)
            {
                const int i = int(gen() % n);
                // 2 to 20 mean diameters per step, random direction
                Vec3 v(G(gen), G(gen), dim == 3 ? G(gen) : 0.0);
                v *= (0.035 + 0.3 * (k % 10) / 9.0) / (dt * v.norm());
                s.velocities()[i] = v;
            }
            // two fast grains side by side outside the bed's box (fast-fast pair
            // of grains outside the grid)
            const double L = dim == 2 ? 1.0 : 0.4;
            s.velocities()[s.addGrain(Vec3(-0.2 * L, 0.5 * L, 0), 0.01, 0)] = Vec3(0, 0.07 / dt, 0);
            s.velocities()[s.addGrain(Vec3(-0.2 * L + 0.05, 0.5 * L, 0), 0.01, 0)] = Vec3(0, -0.07 / dt, 0);
            const int n2 = int(s.size());
            const auto x = s.positions();
            const auto v = s.velocities();
            const auto& r = s.radii();
            double rmin = 1e9;
            for (double a : r) rmin = std::min(rmin, a);
            const double af = s.settings().alertDistanceFactor, margin = s.settings().alertMargin * rmin;
            std::set<std::pair<int, int>> brute;
            for (int i = 0; i < n2; ++i)
                for (int j = i + 1; j < n2; ++j)
                    if ((x[i] - x[j]).norm() - r[i] - r[j] < af * dt * (v[i].norm() + v[j].norm()) + margin)
                        brute.insert({i, j});
            const StepReport rep = s.step(dt);
            std::set<std::pair<int, int>> grid;
            for (const auto& c : s.contacts())
                if (c.j >= 0) grid.insert({std::min(c.i, c.j), std::max(c.i, c.j)});
            EXPECT_GT(brute.size(), std::size_t(100));
            for (const auto& p : brute)
                EXPECT_TRUE(grid.count(p)) << "dim " << dim << " pair " << p.first << " " << p.second;
            if (rep.redetections == 0) EXPECT_EQ(grid, brute) << "dim " << dim;
        }
}

// Measurement (not a pass/fail criterion beyond sanity): grid detection time
// (StepReport::detectSeconds, includes building the contact list) vs CGAL
// box_intersection_d on the same inflated boxes (pairs only).
TEST(BroadPhase, BenchmarkGridVsCgalBoxIntersection)
{
    for (int dim : {2, 3})
    {
        const int n = 20000;
        const double phi = dim == 2 ? 0.5 : 0.3;
        const double rm = 0.0175; // mean radius
        const double L = dim == 2 ? std::sqrt(n * 3.14159 * rm * rm * 1.1 / phi)
                                  : std::cbrt(n * 4.19 * rm * rm * rm * 1.2 / phi);
        System s = randomSet(dim, n, L, 7);
        s.settings().alertMargin = 0.05;
        s.settings().maxIterations = 1;
        s.settings().overlapSlop = 1e6; // no push-out, no re-detection
        double grid = 1e9;
        for (int k = 0; k < 3; ++k)
        {
            // positions unchanged with dt tiny; only timing
            const StepReport rep = s.step(1e-12);
            grid = std::min(grid, rep.detectSeconds);
        }
        const auto& x = s.positions();
        const auto& r = s.radii();
        const double alert = 0.05 * 0.005;
        double cgal = 1e9;
        std::size_t pairs = 0;
        for (int k = 0; k < 3; ++k)
        {
            const auto t0 = std::chrono::steady_clock::now();
            pairs = 0;
            if (dim == 2)
            {
                using Box =
                    CGAL::Box_intersection_d::Box_with_handle_d<double, 2, int,
                                                                CGAL::Box_intersection_d::ID_EXPLICIT>;
                std::vector<Box> boxes;
                boxes.reserve(n);
                for (int i = 0; i < n; ++i)
                {
                    const double h = r[i] + 0.5 * alert;
                    boxes.emplace_back(CGAL::Bbox_2(x[i].x() - h, x[i].y() - h, x[i].x() + h, x[i].y() + h),
                                       i);
                }
                CGAL::box_self_intersection_d(boxes.begin(), boxes.end(),
                                              [&](const Box& a, const Box& b)
                                              {
                                                  const int i = a.handle(), j = b.handle();
                                                  if ((x[i] - x[j]).norm() - r[i] - r[j] < alert) ++pairs;
                                              });
            }
            else
            {
                using Box =
                    CGAL::Box_intersection_d::Box_with_handle_d<double, 3, int,
                                                                CGAL::Box_intersection_d::ID_EXPLICIT>;
                std::vector<Box> boxes;
                boxes.reserve(n);
                for (int i = 0; i < n; ++i)
                {
                    const double h = r[i] + 0.5 * alert;
                    boxes.emplace_back(CGAL::Bbox_3(x[i].x() - h, x[i].y() - h, x[i].z() - h, x[i].x() + h,
                                                    x[i].y() + h, x[i].z() + h),
                                       i);
                }
                CGAL::box_self_intersection_d(boxes.begin(), boxes.end(),
                                              [&](const Box& a, const Box& b)
                                              {
                                                  const int i = a.handle(), j = b.handle();
                                                  if ((x[i] - x[j]).norm() - r[i] - r[j] < alert) ++pairs;
                                              });
            }
            cgal =
                std::min(cgal, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
        std::cout << "[broad phase] dim " << dim << " n " << n << " pairs " << pairs << " grid " << grid * 1e3
                  << " ms, CGAL box_intersection_d " << cgal * 1e3 << " ms\n";
        RecordProperty(dim == 2 ? "grid2D_ms" : "grid3D_ms", std::to_string(grid * 1e3));
        RecordProperty(dim == 2 ? "cgal2D_ms" : "cgal3D_ms", std::to_string(cgal * 1e3));
        EXPECT_GT(pairs, std::size_t(0));
    }
}
