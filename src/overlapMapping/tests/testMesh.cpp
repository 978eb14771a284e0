// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the mesh layer: builders (volumes, conformity), CellMesh
// preparation (shapes, 2D polygons), point location and error reporting.
#include "overlapMapping/CellMesh.hpp"
#include "overlapMapping/MeshBuilders.hpp"
#include "overlapMapping/MeshView.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

using namespace overlapMapping;

namespace
{
std::vector<double> lin(double a, double b, int n) { return gradedSpacing(a, b, n); }
} // namespace

// Builders: cell volumes sum to the box volume (1e-13), internal faces are
// shared by exactly two cells (conformity of the 5-tet alternating split),
// boundary area equals the box surface (1e-13).
TEST(MeshBuilders, VolumesAndConformity)
{
    const auto xs = gradedSpacing(0, 2, 3, 2.0), ys = lin(0, 1, 2), zs = lin(0, 1.5, 2);
    const double box = 2 * 1 * 1.5, surf = 2 * (2 * 1 + 2 * 1.5 + 1 * 1.5);
    struct Case
    {
        MeshView mv;
        label nCells;
    };
    std::vector<Case> cases = {{hexGridMesh(xs, ys, zs), 12},
                               {tetGridMesh(xs, ys, zs, 5), 60},
                               {tetGridMesh(xs, ys, zs, 6), 72},
                               {prismGridMesh(xs, ys, zs), 24}};
    for (auto& cs : cases)
    {
        CellMesh m(cs.mv);
        EXPECT_EQ(m.nCells(), cs.nCells);
        double v = 0;
        for (label c = 0; c < m.nCells(); ++c)
        {
            v += m.cellVolume(c);
            EXPECT_NEAR(m.shapeVolume(c), m.cellVolume(c), 1e-14);
            EXPECT_TRUE(m.convex(c));
        }
        EXPECT_NEAR(v, box, 1e-13);
        double a = 0;
        for (label f = 0; f < cs.mv.nFaces(); ++f)
        {
            if (cs.mv.neighbour[f] < 0)
            {
                Vec3 fc, S;
                faceCentreAndArea(cs.mv, f, fc, S);
                a += S.norm();
            }
        }
        EXPECT_NEAR(a, surf, 1e-13) << "non-conforming faces";
    }
}

// Graded spacing: end points exact, last/first interval = ratio (1e-12).
TEST(MeshBuilders, GradedSpacing)
{
    const auto x = gradedSpacing(1.0, 3.0, 10, 4.0);
    EXPECT_EQ(x.front(), 1.0);
    EXPECT_EQ(x.back(), 3.0);
    EXPECT_NEAR((x[10] - x[9]) / (x[1] - x[0]), 4.0, 1e-12);
}

// 2D meshes: polygons are counter-clockwise, areas x depth = cell volumes
// (1e-14), triangles and quads; edge normals point outward.
TEST(CellMesh, TwoDPolygons)
{
    for (bool tri : {false, true})
    {
        MeshView mv = grid2DMesh(lin(0, 1, 4), gradedSpacing(0, 2, 3, 3.0), -0.05, 0.05, tri);
        CellMesh m(mv);
        EXPECT_TRUE(m.twoD());
        EXPECT_NEAR(m.depth(), 0.1, 1e-15);
        for (label c = 0; c < m.nCells(); ++c)
        {
            EXPECT_EQ(m.polygonSize(c), tri ? 3 : 4);
            EXPECT_GT(m.polygonArea(c), 0.0);
            EXPECT_NEAR(m.polygonArea(c) * m.depth(), m.cellVolume(c), 1e-14);
            const Vec3& cc = m.cellCentre(c);
            EXPECT_NEAR(m.polygonCentroid(c)[0], cc[0], 1e-14);
            EXPECT_NEAR(m.polygonCentroid(c)[1], cc[1], 1e-14);
            EXPECT_TRUE(m.contains(c, cc));
            EXPECT_LT(m.outsideDistance(c, cc), 0.0);
        }
    }
}

// Point location: random points in the domain are found from any hint (walk)
// and without hint (bins), and the result contains the point. Points outside
// give -1. Hex, tet, prism, perturbed 2D meshes.
TEST(CellMesh, FindCell)
{
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    auto perturb = [&](const Vec3& p)
    {
        const bool interior = p[0] > 1e-9 && p[0] < 1 - 1e-9 && p[1] > 1e-9 && p[1] < 1 - 1e-9;
        std::mt19937 r2(unsigned(1000 * p[0] + 37 * 1000 * p[1]));
        std::uniform_real_distribution<double> D(-0.03, 0.03);
        return interior ? Vec3(p[0] + D(r2), p[1] + D(r2), p[2]) : p;
    };
    std::vector<MeshView> meshes = {hexGridMesh(lin(0, 1, 5), lin(0, 1, 4), lin(0, 1, 3)),
                                    tetGridMesh(lin(0, 1, 3), lin(0, 1, 3), lin(0, 1, 3), 5),
                                    prismGridMesh(lin(0, 1, 3), lin(0, 1, 4), lin(0, 1, 2)),
                                    grid2DMesh(lin(0, 1, 8), lin(0, 1, 7), 0, 0.1, false, perturb),
                                    grid2DMesh(lin(0, 1, 8), lin(0, 1, 7), 0, 0.1, true, perturb)};
    for (const auto& mv : meshes)
    {
        CellMesh m(mv);
        for (int t = 0; t < 300; ++t)
        {
            Vec3 x(U(rng), U(rng), U(rng));
            if (m.twoD()) x[2] = 0.05;
            const label c0 = m.findCell(x);
            ASSERT_GE(c0, 0);
            EXPECT_TRUE(m.contains(c0, x));
            const label hint = label(U(rng) * m.nCells());
            const label c1 = m.findCell(x, hint);
            ASSERT_GE(c1, 0);
            EXPECT_TRUE(m.contains(c1, x));
        }
        EXPECT_EQ(m.findCell(Vec3(1.5, 0.5, 0.5)), -1);
        EXPECT_EQ(m.findCell(Vec3(-0.2, 0.5, 0.05), 0), -1);
    }
}

// A non-convex polyhedron (the cells of OpenFOAM's polyDualMesh are such):
// the unit cube whose top is four triangles meeting at (0.5, 0.5, 0.6), a
// dent. Reference: the cell by construction. (0.9, 0.5, 0.8) lies inside,
// under the dent's face over x > 0.5 (z = 0.92 there) but outside the plane of
// the opposite dent face, which the face-plane test took as outside;
// (0.5, 0.5, 0.8) lies in the dent, outside the cell.
TEST(CellMesh, NonConvexPolyhedronByTets)
{
    MeshView mv;
    mv.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),      Vec3(0, 0, 1),
                 Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1), Vec3(0.5, 0.5, 0.6)};
    mv.addFace({0, 3, 2, 1}, 0, -1); // bottom, normal -z
    mv.addFace({0, 1, 5, 4}, 0, -1); // y = 0
    mv.addFace({1, 2, 6, 5}, 0, -1); // x = 1
    mv.addFace({2, 3, 7, 6}, 0, -1); // y = 1
    mv.addFace({3, 0, 4, 7}, 0, -1); // x = 0
    mv.addFace({4, 5, 8}, 0, -1);    // the dent, outward normals up
    mv.addFace({5, 6, 8}, 0, -1);
    mv.addFace({6, 7, 8}, 0, -1);
    mv.addFace({7, 4, 8}, 0, -1);
    computeCellGeometry(mv);
    EXPECT_NEAR(mv.cellVolumes[0], 1 - 0.4 / 3, 1e-12);
    CellMesh m(mv);
    EXPECT_TRUE(m.contains(0, Vec3(0.9, 0.5, 0.8)));
    EXPECT_TRUE(m.contains(0, Vec3(0.1, 0.5, 0.8)));
    EXPECT_TRUE(m.contains(0, Vec3(0.5, 0.5, 0.55)));
    EXPECT_FALSE(m.contains(0, Vec3(0.5, 0.5, 0.8)));
    EXPECT_FALSE(m.contains(0, Vec3(0.5, 0.5, 1.01)));
    EXPECT_FALSE(m.contains(0, Vec3(1.01, 0.5, 0.5)));
    EXPECT_EQ(m.findCell(Vec3(0.9, 0.5, 0.8)), 0);
    EXPECT_EQ(m.findCell(Vec3(0.5, 0.5, 0.8)), -1);
}

// Errors: empty mesh, bad vertex index, 2D cell without a back face.
TEST(CellMesh, InvalidInputThrows)
{
    MeshView empty;
    EXPECT_THROW(CellMesh{empty}, std::invalid_argument);
    MeshView bad = hexGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1));
    bad.faceVertices[0] = 999;
    EXPECT_THROW(CellMesh{bad}, std::invalid_argument);
    MeshView mis = hexGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1));
    mis.twoD = true;
    mis.z0 = -1.0; // no face on z = -1
    mis.z1 = 1.0;
    EXPECT_THROW(CellMesh{mis}, std::invalid_argument);
    MeshView vol = hexGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1));
    vol.cellVolumes[0] = -1.0;
    EXPECT_THROW(CellMesh{vol}, std::invalid_argument);
}
