// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of OverlapMapper: partition of unity on many mesh kinds, solid
// fraction bounds, spread/gather adjointness and conservation, continuity of
// the exact solid fraction vs PCM jumps, linear exactness of the centroid
// gather, errors, and allocation-free steady state.
#include "overlapMapping/Geometry3D.hpp"
#include "overlapMapping/MeshBuilders.hpp"
#include "overlapMapping/OverlapMapper.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <stdexcept>

using namespace overlapMapping;

namespace
{

std::vector<double> lin(double a, double b, int n) { return gradedSpacing(a, b, n); }

/// Deterministic interior-point perturbation (keeps the boundary box).
PointMap perturbation(double amp, bool alsoZ)
{
    return [amp, alsoZ](const Vec3& p)
    {
        auto inside = [](double v) { return v > 1e-9 && v < 1 - 1e-9; };
        const unsigned seed = unsigned(std::llround(p[0] * 7919 + p[1] * 104729 + p[2] * 1299709));
        std::mt19937 r(seed);
        std::uniform_real_distribution<double> D(-amp, amp);
        Vec3 q = p;
        const double dx = D(r), dy = D(r), dz = D(r);
        if (inside(p[0])) q[0] += dx;
        if (inside(p[1])) q[1] += dy;
        if (alsoZ && inside(p[2])) q[2] += dz;
        return q;
    };
}

/// One hex cell [0,1]^3 next to two hexes [1,2]x[0,.5|.5,1]x[0,1]: the left
/// cell has 7 faces (two pentagons): a genuine polyhedron (hanging nodes).
MeshView polyMesh()
{
    std::vector<Vec3> pts;
    std::map<std::array<double, 3>, label> ids;
    auto P = [&](double x, double y, double z)
    {
        auto it = ids.find({x, y, z});
        if (it != ids.end()) return it->second;
        pts.emplace_back(x, y, z);
        return ids[{x, y, z}] = label(pts.size()) - 1;
    };
    std::vector<std::vector<std::vector<label>>> cells;
    cells.push_back({{P(0, 0, 0), P(0, 0, 1), P(0, 1, 1), P(0, 1, 0)},
                     {P(1, 0, 0), P(1, .5, 0), P(1, .5, 1), P(1, 0, 1)},
                     {P(1, .5, 0), P(1, 1, 0), P(1, 1, 1), P(1, .5, 1)},
                     {P(0, 0, 0), P(1, 0, 0), P(1, 0, 1), P(0, 0, 1)},
                     {P(0, 1, 0), P(0, 1, 1), P(1, 1, 1), P(1, 1, 0)},
                     {P(0, 0, 0), P(0, 1, 0), P(1, 1, 0), P(1, .5, 0), P(1, 0, 0)},
                     {P(0, 0, 1), P(1, 0, 1), P(1, .5, 1), P(1, 1, 1), P(0, 1, 1)}});
    for (double y0 : {0.0, 0.5})
    {
        const double y1 = y0 + 0.5;
        cells.push_back(cellModelFaces(CellShape::Hex, {P(1, y0, 0), P(2, y0, 0), P(2, y1, 0), P(1, y1, 0),
                                                        P(1, y0, 1), P(2, y0, 1), P(2, y1, 1), P(1, y1, 1)}));
    }
    return meshFromCellFaces(pts, cells);
}

/// Random grains wholly inside the box [lo, hi] (2D: xy only).
void randomGrains(int n, const Vec3& lo, const Vec3& hi, double rmin, double rmax, bool twoD, unsigned seed,
                  std::vector<Vec3>& x, std::vector<double>& r)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(0, 1);
    x.resize(n);
    r.resize(n);
    for (int i = 0; i < n; ++i)
    {
        r[i] = rmin + (rmax - rmin) * U(rng);
        for (int d = 0; d < 3; ++d)
        {
            x[i][d] = lo[d] + r[i] + (hi[d] - lo[d] - 2 * r[i]) * U(rng);
        }
        if (twoD) x[i][2] = 0.5 * (lo[2] + hi[2]);
    }
}

/// Max relative |W_g - V_g| / V_g over grains.
double maxUnityError(const OverlapMapper& om)
{
    double e = 0;
    for (label g = 0; g < om.nGrains(); ++g)
    {
        e = std::max(e, std::abs(om.grainMappedVolume()[g] - om.grainVolume()[g]) / om.grainVolume()[g]);
    }
    return e;
}

} // namespace

// Partition of unity in 2D: Σ_c V_gc = pi r^2 depth for discs wholly inside
// the domain, on uniform, graded, perturbed (non-orthogonal) quad meshes and
// triangle meshes, for grains smaller and larger than cells.
// Tolerance 1e-12 relative (observed ~1e-15).
TEST(Mapper, PartitionOfUnity2D)
{
    std::vector<MeshView> meshes = {
        grid2DMesh(lin(0, 1, 10), lin(0, 1, 10), 0, 0.01),
        grid2DMesh(gradedSpacing(0, 1, 12, 8.0), gradedSpacing(0, 1, 9, 0.2), 0, 0.01),
        grid2DMesh(lin(0, 1, 10), lin(0, 1, 10), 0, 0.01, false, perturbation(0.03, false)),
        grid2DMesh(lin(0, 1, 9), gradedSpacing(0, 1, 7, 3.0), 0, 0.01, true, perturbation(0.02, false))};
    double worst = 0;
    for (const auto& mv : meshes)
    {
        CellMesh m(mv);
        OverlapMapper om(m);
        std::vector<Vec3> x;
        std::vector<double> r;
        for (double rmax : {0.04, 0.12, 0.3})
        {
            randomGrains(200, Vec3(0, 0, 0), Vec3(1, 1, 0.01), 0.2 * rmax, rmax, true, 5, x, r);
            om.map(x, r);
            EXPECT_LT(maxUnityError(om), 1e-12) << "rmax " << rmax;
            worst = std::max(worst, maxUnityError(om));
            for (double v : om.entryVolume()) EXPECT_GT(v, 0.0);
        }
    }
    std::printf("[ unity 2D ] max relative |W_g - V_g| / V_g = %.2e\n", worst);
}

// Partition of unity in 3D: Σ_c V_gc = 4/3 pi r^3 for spheres wholly inside,
// on uniform and graded hex meshes, 5- and 6-tet meshes, prism meshes, a
// warped hex mesh (non-planar faces -> tetrahedral decomposition), a perturbed
// tet mesh, and a genuine polyhedral (hanging-node) mesh.
// Tolerance 1e-12 relative (the overlap library's own round-off is ~1e-14 here).
TEST(Mapper, PartitionOfUnity3D)
{
    std::vector<MeshView> meshes = {
        hexGridMesh(lin(0, 1, 5), lin(0, 1, 5), lin(0, 1, 5)),
        hexGridMesh(gradedSpacing(0, 1, 6, 5.0), gradedSpacing(0, 1, 4, 0.3), lin(0, 1, 5)),
        tetGridMesh(lin(0, 1, 3), lin(0, 1, 3), lin(0, 1, 3), 5),
        tetGridMesh(lin(0, 1, 3), lin(0, 1, 3), lin(0, 1, 3), 6),
        prismGridMesh(lin(0, 1, 4), lin(0, 1, 3), lin(0, 1, 4)),
        hexGridMesh(lin(0, 1, 4), lin(0, 1, 4), lin(0, 1, 4), perturbation(0.04, true)),
        tetGridMesh(lin(0, 1, 3), lin(0, 1, 3), lin(0, 1, 3), 6, perturbation(0.05, true))};
    int k = 0;
    double worst = 0;
    for (const auto& mv : meshes)
    {
        CellMesh m(mv);
        OverlapMapper om(m);
        std::vector<Vec3> x;
        std::vector<double> r;
        for (double rmax : {0.08, 0.2, 0.45})
        {
            randomGrains(40, Vec3(0, 0, 0), Vec3(1, 1, 1), 0.3 * rmax, rmax, false, 9 + k, x, r);
            om.map(x, r);
            EXPECT_LT(maxUnityError(om), 1e-12) << "mesh " << k << " rmax " << rmax;
            worst = std::max(worst, maxUnityError(om));
        }
        ++k;
    }
    // the warped mesh really exercises the polyhedral path
    CellMesh warped(meshes[5]);
    int nPoly = 0;
    for (label c = 0; c < warped.nCells(); ++c) nPoly += warped.shape(c) == CellShape::Polyhedron;
    EXPECT_GT(nPoly, 0);
    // polyhedral hanging-node mesh: cell 0 is a polyhedron to OpenFOAM (split
    // face, pentagons) but an axis-aligned box, like its two hex neighbours;
    // the closed form and the general path (tets, overlap library) both
    // partition the grains
    CellMesh pm(polyMesh());
    EXPECT_EQ(pm.shape(0), CellShape::Polyhedron);
    EXPECT_EQ(pm.shape(1), CellShape::Hex);
    for (label c = 0; c < pm.nCells(); ++c) EXPECT_TRUE(pm.isBox(c));
    EXPECT_EQ(pm.boxMax(0)[0], pm.boxMin(1)[0]);
    std::vector<Vec3> x;
    std::vector<double> r;
    randomGrains(60, Vec3(0.5, 0, 0), Vec3(1.5, 1, 1), 0.1, 0.45, false, 77, x, r);
    for (bool closedForm : {true, false})
    {
        MappingSettings s;
        s.closedFormBoxes = closedForm;
        OverlapMapper om(pm, s);
        om.map(x, r);
        EXPECT_LT(maxUnityError(om), 1e-12) << "closed form " << closedForm;
        worst = std::max(worst, maxUnityError(om));
    }
    std::printf("[ unity 3D ] max relative |W_g - V_g| / V_g = %.2e\n", worst);
}

// Grains partly outside the domain: W_g < V_g, and the spread of per-grain
// forces still sums exactly (1e-14 relative) to the total force (Newton's
// third law), because weights are renormalised by W_g.
TEST(Mapper, BoundaryGrainsConserveSpreadForce)
{
    for (bool twoD : {true, false})
    {
        MeshView mv = twoD ? grid2DMesh(lin(0, 1, 6), lin(0, 1, 6), 0, 0.1)
                           : hexGridMesh(lin(0, 1, 4), lin(0, 1, 4), lin(0, 1, 4));
        CellMesh m(mv);
        OverlapMapper om(m);
        std::vector<Vec3> x = {Vec3(0.02, 0.5, 0.5), Vec3(0.99, 0.99, 0.5), Vec3(0.5, 0.001, 0.05)};
        std::vector<double> r = {0.1, 0.15, 0.2};
        om.map(x, r);
        for (label g = 0; g < 3; ++g)
        {
            EXPECT_LT(om.grainMappedVolume()[g], 0.9 * om.grainVolume()[g]);
        }
        std::vector<Vec3> F = {Vec3(1, -2, 3), Vec3(-0.5, 0.25, 7), Vec3(4, 4, -1)};
        std::vector<Vec3> Fc;
        om.spread(F.data(), Fc);
        Vec3 tot = Vec3::Zero(), ref = F[0] + F[1] + F[2];
        for (const auto& f : Fc) tot += f;
        EXPECT_NEAR((tot - ref).norm(), 0.0, 1e-14 * ref.norm());
    }
}

// Mass-lumped solid fraction (eq. 3.43) of a dense hexagonal packing of
// touching discs lies in [0, 1] (upper bound 1 + 1e-12 for round-off) on
// meshes with h/d = 2, 1 and 0.5, and its mean over the fully covered cells is
// the packing fraction pi/(2 sqrt 3) ~ 0.9069 on average.
TEST(Mapper, SolidFractionBoundedDensePacking)
{
    const double d = 0.02, r = d / 2;
    std::vector<Vec3> x;
    std::vector<double> rad;
    for (int j = 0;; ++j)
    {
        const double y = r + j * d * std::sqrt(3.0) / 2;
        if (y > 1 - r) break;
        for (int i = 0;; ++i)
        {
            const double xx = r + i * d + (j % 2) * r;
            if (xx > 1 - r) break;
            x.emplace_back(xx, y, 0);
            rad.push_back(r * (1 - 1e-12));
        }
    }
    for (double hd : {2.0, 1.0, 0.5})
    {
        const int n = int(std::round(1.0 / (hd * d)));
        CellMesh m(grid2DMesh(lin(0, 1, n), lin(0, 1, n), 0, 1e-3));
        OverlapMapper om(m);
        om.map(x, rad);
        double mx = 0, mn = 1, total = 0, area = 0;
        for (label c = 0; c < m.nCells(); ++c)
        {
            mx = std::max(mx, om.solidFraction()[c]);
            mn = std::min(mn, om.solidFraction()[c]);
            total += om.solidFraction()[c] * m.cellVolume(c);
            area += m.cellVolume(c);
        }
        EXPECT_LE(mx, 1 + 1e-12) << "h/d " << hd;
        EXPECT_GE(mn, 0.0);
        EXPECT_NEAR(total, x.size() * pi * r * r * 1e-3, 1e-9 * total);
        std::vector<double> eps;
        om.voidFraction(eps);
        for (label c = 0; c < m.nCells(); ++c)
        {
            EXPECT_GE(eps[c], 1e-8);
            EXPECT_NEAR(eps[c], std::max(1 - om.solidFraction()[c], 1e-8), 1e-15);
        }
    }
}

// spread/gather adjointness, with w_gc = V_gc / W_g:
//   spread(F)_c = Σ_g w_gc F_g,  gather(a)_g = Σ_c w_gc a_c
//   Σ_g gather(a)_g F_g == Σ_c a_c spread(F)_c
// and, for a density f_g (F_g = f_g W_g) and spreadDensity = spread / V_c:
//   Σ_g gather(a)_g f_g W_g == Σ_c a_c spreadDensity(F)_c V_c.
// Tolerance 1e-13 relative (round-off of sums of ~1e3 terms).
TEST(Mapper, SpreadGatherAdjoint)
{
    for (bool twoD : {true, false})
    {
        MeshView mv = twoD ? grid2DMesh(gradedSpacing(0, 1, 15, 3), lin(0, 1, 12), 0, 0.1, true)
                           : tetGridMesh(lin(0, 1, 4), lin(0, 1, 4), lin(0, 1, 4), 5);
        CellMesh m(mv);
        OverlapMapper om(m);
        std::vector<Vec3> x;
        std::vector<double> r;
        randomGrains(150, Vec3(-0.05, -0.05, twoD ? 0 : -0.05), Vec3(1.05, 1.05, twoD ? 0.1 : 1.05), 0.02,
                     0.15, twoD, 21, x, r);
        for (auto& xi : x)
        { // centres inside, some grains stick out
            for (int d = 0; d < (twoD ? 2 : 3); ++d) xi[d] = std::clamp(xi[d], 0.001, 0.999);
        }
        om.map(x, r);
        int outside = 0;
        for (label g = 0; g < om.nGrains(); ++g)
        {
            outside += om.grainMappedVolume()[g] < (1 - 1e-9) * om.grainVolume()[g];
        }
        EXPECT_GT(outside, 5);
        std::mt19937 rng(4);
        std::normal_distribution<double> N(0, 1);
        std::vector<double> a(m.nCells()), F(x.size());
        for (auto& v : a) v = N(rng);
        for (auto& v : F) v = N(rng);
        std::vector<double> ga, sF, sD;
        om.gather(a.data(), ga);
        om.spread(F.data(), sF);
        om.spreadDensity(F.data(), sD);
        double lhs = 0, rhs = 0, rhsD = 0, scale = 0;
        for (size_t g = 0; g < x.size(); ++g)
        {
            lhs += ga[g] * F[g];
            scale += std::abs(ga[g] * F[g]);
        }
        for (label c = 0; c < m.nCells(); ++c)
        {
            rhs += a[c] * sF[c];
            rhsD += a[c] * sD[c] * m.cellVolume(c);
        }
        EXPECT_NEAR(lhs, rhs, 1e-13 * scale);
        EXPECT_NEAR(lhs, rhsD, 1e-13 * scale);
        // vector version: Σ_c spread(F)_c = Σ_g F_g
        std::vector<Vec3> Fv(x.size()), sv;
        for (auto& v : Fv) v = Vec3(N(rng), N(rng), N(rng));
        om.spread(Fv.data(), sv);
        Vec3 s1 = Vec3::Zero(), s2 = Vec3::Zero();
        for (auto& v : Fv) s1 += v;
        for (auto& v : sv) s2 += v;
        EXPECT_NEAR((s1 - s2).norm(), 0.0, 1e-12);
    }
}

// Solid flux term (eq. 3.41): with all grains at the same velocity v,
// (phi v)_c = phi_c v (1e-14).
TEST(Mapper, SolidVelocityUniform)
{
    CellMesh m(hexGridMesh(lin(0, 1, 3), lin(0, 1, 3), lin(0, 1, 3)));
    OverlapMapper om(m);
    std::vector<Vec3> x;
    std::vector<double> r;
    randomGrains(20, Vec3(0, 0, 0), Vec3(1, 1, 1), 0.05, 0.2, false, 3, x, r);
    om.map(x, r);
    std::vector<Vec3> v(x.size(), Vec3(0.1, -2.0, 0.3)), pv;
    om.solidVelocity(v.data(), pv);
    for (label c = 0; c < m.nCells(); ++c)
    {
        EXPECT_NEAR((pv[c] - om.solidFraction()[c] * v[0]).norm(), 0.0, 1e-14);
    }
}

// Linear exactness of the overlap centroids: for a linear field
// a(x) = a0 + b.x given by cell values a(x_c) and gradient b, the gather at
// sub-cell centroids equals a(grain centre) for grains inside the domain
// (average of a linear field over a ball = value at its centre).
// 2D and 3D (hex, prism, tet, polyhedral); tolerance 1e-12 (3D centroid
// relies on the exact face-moment formula of Geometry3D.hpp).
TEST(Mapper, GatherAtCentroidsExactForLinearFields)
{
    const double a0 = 0.7;
    const Vec3 b(1.3, -0.4, 2.1);
    std::vector<MeshView> meshes = {
        grid2DMesh(lin(0, 1, 7), gradedSpacing(0, 1, 6, 4.0), 0, 0.1),
        grid2DMesh(lin(0, 1, 7), lin(0, 1, 5), 0, 0.1, true, perturbation(0.03, false)),
        hexGridMesh(lin(0, 1, 4), gradedSpacing(0, 1, 3, 2), lin(0, 1, 4)),
        prismGridMesh(lin(0, 1, 3), lin(0, 1, 3), lin(0, 1, 3)),
        tetGridMesh(lin(0, 1, 3), lin(0, 1, 3), lin(0, 1, 3), 5),
        hexGridMesh(lin(0, 1, 4), lin(0, 1, 4), lin(0, 1, 4), perturbation(0.04, true))};
    for (const auto& mv : meshes)
    {
        CellMesh m(mv);
        OverlapMapper om(m);
        std::vector<Vec3> x;
        std::vector<double> r;
        randomGrains(30, Vec3(0, 0, 0), Vec3(1, 1, m.twoD() ? 0.1 : 1), 0.05, 0.3, m.twoD(), 8, x, r);
        om.map(x, r);
        std::vector<double> a(m.nCells());
        std::vector<Vec3> grad(m.nCells(), b);
        Vec3 b2 = b;
        if (m.twoD()) b2[2] = 0;
        for (label c = 0; c < m.nCells(); ++c) a[c] = a0 + b2.dot(m.cellCentre(c));
        if (m.twoD())
            for (auto& gv : grad) gv[2] = 0;
        std::vector<double> ga;
        om.gatherAtCentroids(a.data(), grad.data(), ga);
        for (size_t g = 0; g < x.size(); ++g)
        {
            EXPECT_NEAR(ga[g], a0 + b2.dot(x[g]), 1e-12) << "cells " << m.nCells();
        }
        // vector version with OpenFOAM's gradient convention (grad U)_ij = d_i U_j
        Eigen::Matrix3d G;
        G << 1, 2, 3, -1, 0.5, 0, 0.2, 0.1, -2;
        if (m.twoD()) G.row(2).setZero();
        std::vector<Vec3> U(m.nCells());
        std::vector<Eigen::Matrix3d> gU(m.nCells(), G);
        for (label c = 0; c < m.nCells(); ++c) U[c] = Vec3(G.transpose() * Eigen::Vector3d(m.cellCentre(c)));
        std::vector<Vec3> gv;
        om.gatherAtCentroids(U.data(), gU.data(), gv);
        for (size_t g = 0; g < x.size(); ++g)
        {
            const Vec3 ref = Vec3(G.transpose() * Eigen::Vector3d(x[g]));
            EXPECT_NEAR((gv[g] - ref).norm(), 0.0, 1e-12);
        }
    }
}

// A grain moving along a row of cells: the exact solid fraction of a cell is
// a continuous function of the position - the largest change between two
// positions dx apart shrinks linearly with dx (here <= 2 r dx depth / V_c
// bound, checked as: jump(dx/10) < jump(dx)/5) - whereas PCM jumps by
// V_grain / V_cell when the centre crosses a face, whatever dx.
TEST(Mapper, MovingGrainContinuityVsPCM)
{
    CellMesh m(grid2DMesh(lin(0, 5, 5), lin(0, 1, 1), 0, 0.1));
    const double r = 0.3;
    const double ratio = pi * r * r / 1.0; // V_grain / V_cell
    auto maxJump = [&](MappingMethod method, double dx)
    {
        MappingSettings s;
        s.method = method;
        OverlapMapper om(m, s);
        double prev = -1, jump = 0;
        std::vector<double> rad = {r};
        for (double xg = 0.5; xg <= 4.5 + 1e-12; xg += dx)
        {
            std::vector<Vec3> x = {Vec3(xg, 0.5, 0.05)};
            om.map(x, rad);
            const double phi = om.solidFraction()[1]; // cell x in [1, 2]
            if (prev >= 0) jump = std::max(jump, std::abs(phi - prev));
            prev = phi;
        }
        return jump;
    };
    const double e1 = maxJump(MappingMethod::Exact, 1e-2);
    const double e2 = maxJump(MappingMethod::Exact, 1e-3);
    const double e3 = maxJump(MappingMethod::Exact, 1e-4);
    EXPECT_LT(e1, 2 * r * 1e-2 * 1.01); // |d phi/dx| <= chord length 2r / cell area
    EXPECT_LT(e2, e1 / 5);
    EXPECT_LT(e3, e2 / 5);
    const double p1 = maxJump(MappingMethod::ParticleCentroid, 1e-2);
    const double p3 = maxJump(MappingMethod::ParticleCentroid, 1e-4);
    EXPECT_NEAR(p1, ratio, 1e-12);
    EXPECT_NEAR(p3, ratio, 1e-12);
    std::printf("[ moving grain ] max |dphi| exact: dx=1e-2 %.3e, 1e-3 %.3e, 1e-4 %.3e;"
                " PCM: %.4f, %.4f (V_g/V_c = %.4f)\n",
                e1, e2, e3, p1, p3, ratio);
}

// PCM (eq. 3.44-3.45): one entry per grain, the whole volume in the cell of
// the centre, centroid = grain centre.
TEST(Mapper, ParticleCentroidMethod)
{
    CellMesh m(hexGridMesh(lin(0, 1, 4), lin(0, 1, 4), lin(0, 1, 4)));
    MappingSettings s;
    s.method = MappingMethod::ParticleCentroid;
    OverlapMapper om(m, s);
    std::vector<Vec3> x = {Vec3(0.3, 0.3, 0.3), Vec3(0.74, 0.1, 0.9)};
    std::vector<double> r = {0.2, 0.1};
    om.map(x, r);
    ASSERT_EQ(om.nEntries(), 2u);
    for (label g = 0; g < 2; ++g)
    {
        EXPECT_EQ(om.entryCell()[g], m.findCell(x[g]));
        EXPECT_DOUBLE_EQ(om.entryVolume()[g], sphereVolume(r[g]));
        EXPECT_DOUBLE_EQ(om.entryWeight()[g], 1.0);
    }
    EXPECT_NEAR(om.solidFraction()[om.entryCell()[0]], sphereVolume(0.2) / m.cellVolume(om.entryCell()[0]),
                1e-14);
}

// Effective diameter factor (section 3.2.3): the mapped volume scales as k^2
// in 2D (1e-14); diameterFactorForPacking(0.64, 0.82) = sqrt(0.64/0.82).
TEST(Mapper, EffectiveDiameterFactor)
{
    CellMesh m(grid2DMesh(lin(0, 1, 5), lin(0, 1, 5), 0, 0.1));
    MappingSettings s;
    s.effectiveDiameterFactor = MappingSettings::diameterFactorForPacking();
    EXPECT_NEAR(s.effectiveDiameterFactor, std::sqrt(0.64 / 0.82), 1e-15);
    OverlapMapper om(m, s);
    std::vector<Vec3> x = {Vec3(0.5, 0.5, 0.05)};
    std::vector<double> r = {0.2};
    om.map(x, r);
    double tot = 0;
    for (label c = 0; c < m.nCells(); ++c) tot += om.solidFraction()[c] * m.cellVolume(c);
    EXPECT_NEAR(tot, pi * 0.04 * 0.1 * 0.64 / 0.82, 1e-14);
    s.effectiveDiameterFactor = 0.0;
    EXPECT_THROW(om.setSettings(s), std::invalid_argument);
    EXPECT_THROW(MappingSettings::diameterFactorForPacking(0.0, 0.8), std::invalid_argument);
}

// Errors: a grain outside the mesh throws std::runtime_error naming it (or is
// skipped with OutsideGrainPolicy::Skip); invalid radius / size mismatch
// throw std::invalid_argument.
TEST(Mapper, Errors)
{
    CellMesh m(hexGridMesh(lin(0, 1, 3), lin(0, 1, 3), lin(0, 1, 3)));
    OverlapMapper om(m);
    std::vector<Vec3> x = {Vec3(0.5, 0.5, 0.5), Vec3(1.5, 0.5, 0.5)};
    std::vector<double> r = {0.1, 0.1};
    try
    {
        om.map(x, r);
        FAIL() << "expected std::runtime_error";
    }
    catch (const std::runtime_error& e)
    {
        EXPECT_NE(std::string(e.what()).find("grain 1"), std::string::npos) << e.what();
    }
    MappingSettings s;
    s.outside = OutsideGrainPolicy::Skip;
    om.setSettings(s);
    om.map(x, r);
    EXPECT_EQ(om.grainCell()[1], -1);
    EXPECT_EQ(om.grainMappedVolume()[1], 0.0);
    std::vector<double> a(m.nCells(), 1.0), ga;
    om.gather(a.data(), ga);
    EXPECT_NEAR(ga[0], 1.0, 1e-15);
    EXPECT_EQ(ga[1], 0.0);
    r[0] = -1;
    EXPECT_THROW(om.map(x, r), std::invalid_argument);
    r.pop_back();
    EXPECT_THROW(om.map(x, r), std::invalid_argument);
}

// Steady state: repeated maps with slightly moved grains reuse the same
// buffers (no reallocation of the entry arrays), and the cost is
// proportional to the cells touched (< 12 exact evaluations per grain here).
TEST(Mapper, NoReallocationAndLocalCost)
{
    CellMesh m(grid2DMesh(lin(0, 1, 40), lin(0, 1, 40), 0, 0.01));
    OverlapMapper om(m);
    std::vector<Vec3> x;
    std::vector<double> r;
    randomGrains(500, Vec3(0, 0, 0), Vec3(1, 1, 0.01), 0.005, 0.0125, true, 2, x, r);
    om.map(x, r);
    om.map(x, r);
    const void* p1 = om.entryCell().data();
    const void* p2 = om.entryVolume().data();
    const void* p3 = om.entryCentroid().data();
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> U(-1e-4, 1e-4);
    for (int it = 0; it < 10; ++it)
    {
        for (auto& xi : x)
        {
            xi[0] += U(rng);
            xi[1] += U(rng);
        }
        om.map(x, r);
        EXPECT_LE(om.lastCellsEvaluated(), 12u * x.size());
    }
    // entries only reallocate if the count grows beyond the capacity reached
    if (om.entryCell().capacity() >= om.nEntries())
    {
        EXPECT_EQ(p1, (const void*)om.entryCell().data());
        EXPECT_EQ(p2, (const void*)om.entryVolume().data());
        EXPECT_EQ(p3, (const void*)om.entryCentroid().data());
    }
}
