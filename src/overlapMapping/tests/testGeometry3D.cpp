// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of sphere/cell overlaps: vertex-ordering mapping OpenFOAM <->
// overlap library, closed forms (half/quarter/eighth ball and their
// centroids 3r/8), Monte-Carlo checks, and the tet decomposition of polyhedra.
#include "overlapMapping/Geometry3D.hpp"
#include "overlapMapping/MeshBuilders.hpp"

#include <overlap.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

using namespace overlapMapping;

namespace
{

std::vector<double> lin(double a, double b, int n) { return gradedSpacing(a, b, n); }

std::set<label> asSet(const std::vector<label>& v) { return {v.begin(), v.end()}; }

// Monte-Carlo estimate of volume and centroid of sphere ∩ cell, using the
// CellMesh point-in-cell test (exact for convex cells).
struct MC
{
    double vol, se;
    Vec3 cen;
    double seCen;
};
MC monteCarlo(const CellMesh& m, label cell, const Vec3& c, double r, int N, unsigned seed)
{
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(-1, 1);
    long hits = 0;
    Vec3 s = Vec3::Zero();
    for (int i = 0; i < N; ++i)
    {
        const Vec3 x = c + r * Vec3(U(rng), U(rng), U(rng));
        if ((x - c).squaredNorm() > r * r || !m.contains(cell, x)) continue;
        ++hits;
        s += x;
    }
    const double box = 8 * r * r * r;
    const double p = double(hits) / N;
    return {box * p, box * std::sqrt(p * (1 - p) / N), Vec3(s / double(hits)), r / std::sqrt(double(hits))};
}

} // namespace

// The OpenFOAM hex (blockMesh order: bottom 0123 counter-clockwise seen from
// above, top 4567, 4 above 0) is recognised and its vertex order is handed
// unchanged to overlap::Hexahedron: the 6 OpenFOAM model faces are exactly
// the 6 overlap faces (as vertex sets) and overlap's face normals point
// outward (the cell centre is "contained"). Same for prism/wedge and tet.
TEST(VertexOrdering, OpenFOAMMatchesOverlapLibrary)
{
    // unit cube, slightly sheared so that nothing is symmetric
    auto shear = [](const Vec3& p) { return Vec3(p[0] + 0.2 * p[2], p[1] + 0.1 * p[0], p[2]); };
    for (CellShape shape : {CellShape::Hex, CellShape::Prism, CellShape::Tet})
    {
        MeshView mv;
        if (shape == CellShape::Hex) mv = hexGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1), shear);
        if (shape == CellShape::Prism) mv = prismGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1), shear);
        if (shape == CellShape::Tet) mv = tetGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1), 6, shear);
        CellMesh m(mv);
        for (label c = 0; c < m.nCells(); ++c)
        {
            ASSERT_EQ(m.shape(c), shape);
            const label* v = m.shapeVertices(c);
            const int nv = shape == CellShape::Tet ? 4 : (shape == CellShape::Prism ? 6 : 8);
            std::vector<label> verts(v, v + nv);
            std::array<overlap::Vector, 8> P;
            for (int k = 0; k < nv; ++k)
            {
                const Vec3& p = mv.points[verts[k]];
                P[k] = overlap::Vector(p[0], p[1], p[2]);
            }
            // OpenFOAM model faces of the recognised order == mesh faces
            std::set<std::set<label>> meshFaces, modelFaces;
            for (label i = m.cellFacesBegin(c); i < m.cellFacesEnd(c); ++i)
            {
                const label f = m.cellFace(i);
                meshFaces.insert(asSet(std::vector<label>(mv.faceVertices.begin() + mv.faceOffsets[f],
                                                          mv.faceVertices.begin() + mv.faceOffsets[f + 1])));
            }
            for (const auto& f : cellModelFaces(shape, verts)) modelFaces.insert(asSet(f));
            EXPECT_EQ(meshFaces, modelFaces);
            const overlap::Vector cc(m.cellCentre(c)[0], m.cellCentre(c)[1], m.cellCentre(c)[2]);
            if (shape == CellShape::Hex)
            {
                overlap::Hexahedron h(P[0], P[1], P[2], P[3], P[4], P[5], P[6], P[7]);
                EXPECT_NEAR(h.volume, m.cellVolume(c), 1e-14);
                EXPECT_TRUE(overlap::detail::contains(h, cc)); // outward normals
                // overlap faces are OpenFOAM faces with the same orientation:
                // overlap face normal . OpenFOAM outward normal > 0
                for (const auto& f : h.faces)
                {
                    EXPECT_LT(f.normal.dot(cc - f.center), 0.0);
                }
            }
            else if (shape == CellShape::Prism)
            {
                overlap::Wedge w(P[0], P[1], P[2], P[3], P[4], P[5]);
                EXPECT_NEAR(w.volume, m.cellVolume(c), 1e-14);
                EXPECT_TRUE(overlap::detail::contains(w, cc));
            }
            else
            {
                // overlap's orientation requirement: (v1-v0)x(v2-v0).(v3-v0) > 0
                EXPECT_GT((P[1] - P[0]).cross(P[2] - P[0]).dot(P[3] - P[0]), 0.0);
                overlap::Tetrahedron t(P[0], P[1], P[2], P[3]);
                EXPECT_NEAR(t.volume, m.cellVolume(c), 1e-14);
                EXPECT_TRUE(overlap::detail::contains(t, cc));
            }
        }
    }
    // A wrong ordering (top and bottom swapped) is NOT a valid overlap
    // element: overlap's faces then point inward and the result is wrong.
    MeshView mv = hexGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1));
    CellMesh m(mv);
    const label* v = m.shapeVertices(0);
    const Vec3 c(0, 0, 0); // sphere on a vertex: exact = 1/8 ball
    Vec3 good[8], bad[8];
    for (int k = 0; k < 8; ++k)
    {
        good[k] = mv.points[v[k]];
        bad[k] = mv.points[v[(k + 4) % 8]];
    }
    const double r = 0.5;
    EXPECT_NEAR(sphereHexVolume(c, r, good), sphereVolume(r) / 8, 1e-12);
    EXPECT_GT(std::abs(sphereHexVolume(c, r, bad) - sphereVolume(r) / 8), 1e-3);
}

// Sphere centred on a face / edge / vertex of a cube: 1/2, 1/4, 1/8 of the
// ball, centroid offset 3r/8 from the centre along each cut axis. For hex,
// prism (2 per cube) and tet (5 and 6 per cube) meshes of the cube, summing the
// cells. Tolerance 1e-12 relative on volumes, 1e-10 r on centroids.
TEST(SphereCell, HalfQuarterEighthBall)
{
    const double r = 0.35;
    const double V = sphereVolume(r);
    struct Case
    {
        Vec3 c;
        double frac;
        Vec3 off;
    };
    const std::vector<Case> cases = {{Vec3(0.5, 0.5, 0.0), 0.5, Vec3(0, 0, 1)},
                                     {Vec3(0.5, 0.0, 0.0), 0.25, Vec3(0, 1, 1)},
                                     {Vec3(0.0, 0.0, 0.0), 0.125, Vec3(1, 1, 1)},
                                     {Vec3(1.0, 0.5, 0.5), 0.5, Vec3(-1, 0, 0)},
                                     {Vec3(1.0, 1.0, 1.0), 0.125, Vec3(-1, -1, -1)}};
    std::vector<MeshView> meshes = {hexGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1)),
                                    prismGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1)),
                                    tetGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1), 5),
                                    tetGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1), 6)};
    for (const auto& mv : meshes)
    {
        CellMesh m(mv);
        for (const auto& cs : cases)
        {
            double vol = 0;
            Vec3 mom = Vec3::Zero();
            for (label c = 0; c < m.nCells(); ++c)
            {
                const SphereOverlap3D o = sphereCellOverlap(m, c, cs.c, r, true);
                vol += o.volume;
                mom += o.volume * (o.centroid - cs.c);
            }
            EXPECT_NEAR(vol, cs.frac * V, 1e-12 * V) << "cells " << m.nCells();
            const Vec3 cen = mom / vol;
            for (int d = 0; d < 3; ++d)
            {
                EXPECT_NEAR(cen[d], cs.off[d] * 3 * r / 8, 1e-10 * r)
                    << "cells " << m.nCells() << " dir " << d;
            }
        }
    }
}

// Monte-Carlo (fixed seeds, N = 2e6) volume and centroid of a sphere over a
// generic (sheared, non-axis-aligned) hex, prism and tet cell.
// Tolerance: 5 standard errors.
TEST(SphereCell, MonteCarlo)
{
    auto warpFree = [](const Vec3& p) { // affine map keeps faces planar
        return Vec3(1.1 * p[0] + 0.3 * p[1] - 0.1 * p[2], 0.2 * p[0] + 0.9 * p[1], 0.15 * p[1] + 1.2 * p[2]);
    };
    std::vector<MeshView> meshes = {hexGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1), warpFree),
                                    prismGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1), warpFree),
                                    tetGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1), 6, warpFree)};
    const Vec3 c(0.9, 0.35, 0.8);
    const double r = 0.55;
    unsigned seed = 7;
    for (const auto& mv : meshes)
    {
        CellMesh m(mv);
        for (label cell = 0; cell < std::min<label>(m.nCells(), 3); ++cell)
        {
            const SphereOverlap3D o = sphereCellOverlap(m, cell, c, r, true);
            const MC mc = monteCarlo(m, cell, c, r, 2000000, seed++);
            EXPECT_NEAR(o.volume, mc.vol, 5 * mc.se + 1e-12) << "cell " << cell;
            if (o.volume > 1e-3)
            {
                for (int d = 0; d < 3; ++d)
                {
                    EXPECT_NEAR(o.centroid[d], mc.cen[d], 5 * mc.seCen) << "cell " << cell;
                }
            }
        }
    }
}

// The tetrahedral decomposition used for polyhedra agrees with the overlap
// library's hex/prism/tet volumes (1e-12 relative) for many positions.
TEST(SphereCell, TetDecompositionMatchesElements)
{
    std::vector<MeshView> meshes = {hexGridMesh(lin(0, 1, 2), lin(0, 1.5, 2), gradedSpacing(0, 1, 2, 3.0)),
                                    prismGridMesh(lin(0, 1, 2), lin(0, 1, 2), lin(0, 1, 1)),
                                    tetGridMesh(lin(0, 1, 1), lin(0, 1, 1), lin(0, 1, 1), 5)};
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-0.2, 1.2);
    for (const auto& mv : meshes)
    {
        CellMesh m(mv);
        for (int t = 0; t < 50; ++t)
        {
            const Vec3 c(U(rng), U(rng), U(rng));
            const double r = 0.1 + 0.4 * (U(rng) + 0.2) / 1.4;
            for (label cell = 0; cell < m.nCells(); ++cell)
            {
                const double a = sphereCellOverlap(m, cell, c, r, false).volume;
                const double b = sphereCellVolumeByTets(m, cell, c, r);
                EXPECT_NEAR(a, b, 1e-12 * sphereVolume(r));
            }
        }
    }
}

// Scale robustness: a sphere 1e-6 times smaller than the cell centred on a
// face of a unit cube gives half a ball, and one much larger than the mesh
// gives the cell volumes (1e-10 relative; the overlap library's planarity
// check works in sphere-normalised units, the tet fallback covers it).
TEST(SphereCell, ExtremeSizeRatios)
{
    MeshView mv = hexGridMesh(lin(0, 1, 2), lin(0, 1, 2), lin(0, 1, 2));
    CellMesh m(mv);
    for (double r : {1e-6, 1e-3})
    {
        const Vec3 c(0.25, 0.25, 0.0); // on the boundary face z = 0
        double v = 0;
        for (label cell = 0; cell < m.nCells(); ++cell)
        {
            v += sphereCellOverlap(m, cell, c, r, false).volume;
        }
        EXPECT_NEAR(v, 0.5 * sphereVolume(r), 1e-10 * sphereVolume(r)) << "r " << r;
    }
    for (label cell = 0; cell < m.nCells(); ++cell)
    {
        const SphereOverlap3D o = sphereCellOverlap(m, cell, Vec3(0.5, 0.5, 0.5), 10.0, true);
        EXPECT_NEAR(o.volume, m.cellVolume(cell), 1e-14);
        EXPECT_NEAR((o.centroid - m.cellCentre(cell)).norm(), 0.0, 1e-14);
    }
}
