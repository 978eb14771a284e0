// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the closed-form sphere / axis-aligned box overlap
// (SphereBox.hpp) and of the detection of box cells:
//  - against the general sphere/hexahedron routine of the `overlap` library
//    (Strobl, Formella, Poeschel 2016, J. Comput. Phys. 311:158; a peer code)
//    on random configurations of every kind (disjoint, sphere inside, box
//    inside, one face, edge and corner cut), volumes to 1e-12 of the ball;
//    first moments against the face-integral moments of Geometry3D.cpp;
//  - against analytic references independent of both: spherical cap
//    V = pi h^2 (3r - h) / 3 and its centroid 3 (2r - h)^2 / (4 (3r - h))
//    from the centre (e.g. CRC Standard Mathematical Tables, "spherical
//    segment"); half, quarter and eighth ball (centroid 3r/8 per cut axis);
//    the ball split over a graded hex mesh (sum = 4/3 pi r^3, moment 0);
//  - mapper level: the 3D void fraction with and without the closed form.
#include "overlapMapping/Geometry3D.hpp"
#include "overlapMapping/MeshBuilders.hpp"
#include "overlapMapping/OverlapMapper.hpp"
#include "overlapMapping/SphereBox.hpp"

#include <overlap.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>

using namespace overlapMapping;

namespace
{

/// Box [lo, hi] as an `overlap` hexahedron (OpenFOAM / blockMesh order).
double overlapLibraryVolume(const Vec3& c, double r, const Vec3& lo, const Vec3& hi)
{
    auto P = [&](int i, int j, int k)
    { return overlap::Vector(i ? hi[0] : lo[0], j ? hi[1] : lo[1], k ? hi[2] : lo[2]); };
    const overlap::Hexahedron hex(P(0, 0, 0), P(1, 0, 0), P(1, 1, 0), P(0, 1, 0), P(0, 0, 1), P(1, 0, 1),
                                  P(1, 1, 1), P(0, 1, 1));
    return overlap::overlap_volume(overlap::Sphere(overlap::Vector(c[0], c[1], c[2]), r), hex);
}

/// One-cell hex mesh of the box [lo, hi].
CellMesh boxMesh(const Vec3& lo, const Vec3& hi)
{
    return CellMesh(hexGridMesh({lo[0], hi[0]}, {lo[1], hi[1]}, {lo[2], hi[2]}));
}

/// Kind of sphere/box configuration.
enum Kind
{
    Disjoint,
    SphereInside,
    BoxInside,
    FaceCut,
    EdgeCut,
    CornerCut
};

Kind classify(const Vec3& c, double r, const Vec3& lo, const Vec3& hi)
{
    double out2 = 0, far2 = 0, inside = r;
    int cut = 0;
    for (int d = 0; d < 3; ++d)
    {
        const double l = c[d] - lo[d], h = hi[d] - c[d];
        out2 += l < 0 ? l * l : (h < 0 ? h * h : 0);
        far2 += std::pow(std::max(std::abs(l), std::abs(h)), 2);
        inside = std::min({inside, l, h});
        cut += (std::abs(l) < r) || (std::abs(h) < r);
    }
    if (out2 >= r * r) return Disjoint;
    if (inside >= r) return SphereInside;
    if (far2 <= r * r) return BoxInside;
    return cut <= 1 ? FaceCut : (cut == 2 ? EdgeCut : CornerCut);
}

} // namespace

// Random sphere/box pairs of every kind: the closed form equals the `overlap`
// library's hexahedron volume to 1e-12 of the ball volume, with and without
// the fast paths of sphereCellOverlap (one-cell mesh); the first moment
// equals the face-integral moment of sphereCellFirstMoment to 1e-12 r^4.
TEST(SphereBox, MatchesOverlapLibraryAllCases)
{
    std::mt19937_64 rng(29);
    std::uniform_real_distribution<double> U(0, 1);
    std::map<Kind, int> count;
    double worstV = 0, worstM = 0;
    const int quota = 500; // configurations of each kind
    int N = 0;
    for (long t = 0; t < 2000000 && N < 6 * quota; ++t)
    {
        const double r = std::exp(std::log(1e-3) + U(rng) * std::log(1e3)); // 1e-3..1
        // box edges from 0.05 r to 8 r, centre anywhere within 1.2 r of it
        Vec3 L;
        for (int d = 0; d < 3; ++d) L[d] = r * std::exp(std::log(0.05) + U(rng) * std::log(160.0));
        const Vec3 lo(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.5);
        const Vec3 hi = lo + L;
        Vec3 c;
        for (int d = 0; d < 3; ++d) c[d] = lo[d] - 1.2 * r + U(rng) * (L[d] + 2.4 * r);
        const Kind kind = classify(c, r, lo, hi);
        if (count[kind] >= quota) continue;
        ++count[kind];
        ++N;
        const double V = sphereVolume(r);
        const double ref = overlapLibraryVolume(c, r, lo, hi);
        const SphereBoxOverlap o = sphereBoxOverlap(c, r, lo, hi, true);
        EXPECT_NEAR(o.volume, ref, 1e-12 * V) << "kind " << kind << " t " << t;
        worstV = std::max(worstV, std::abs(o.volume - ref) / V);
        if (N % 4 == 0)
        { // through the mesh: fast paths and the general moment
            const CellMesh m = boxMesh(lo, hi);
            ASSERT_TRUE(m.isBox(0));
            const SphereOverlap3D s = sphereCellOverlap(m, 0, c, r, true);
            EXPECT_NEAR(s.volume, ref, 1e-12 * V) << "kind " << kind;
            const Vec3 M = sphereCellFirstMoment(m, 0, c, r);
            const double r4 = r * r * r * r;
            EXPECT_LT((o.moment - M).norm(), 1e-12 * r4) << "kind " << kind;
            EXPECT_LT((s.volume * (s.centroid - c) - M).norm(), 1e-12 * r4) << "kind " << kind;
            worstM = std::max(worstM, (o.moment - M).norm() / r4);
        }
    }
    for (Kind k : {Disjoint, SphereInside, BoxInside, FaceCut, EdgeCut, CornerCut})
    {
        EXPECT_EQ(count[k], quota) << "too few samples of kind " << k;
    }
    std::printf("[ sphere/box ] %d configurations (disjoint %d, sphere inside %d, box inside %d, "
                "face %d, edge %d, corner %d): max |V - V_overlap| / V_ball = %.2e, "
                "max |M - M_faces| / r^4 = %.2e\n",
                N, count[Disjoint], count[SphereInside], count[BoxInside], count[FaceCut], count[EdgeCut],
                count[CornerCut], worstV, worstM);
}

// A box cutting one face of the sphere leaves a cap of height h:
// V = pi h^2 (3r - h) / 3, centroid 3 (2r - h)^2 / (4 (3r - h)) from the
// centre (spherical segment, CRC tables), for h from 0 to 2r, along each axis
// and both directions. 1e-13 relative.
TEST(SphereBox, SphericalCap)
{
    const double r = 0.7;
    const Vec3 c(0.1, -0.2, 0.3);
    for (double h : {1e-6, 0.01, 0.3, 0.7, 1.0, 1.39, 1.4 - 1e-9})
    {
        const double Vref = pi * h * h * (3 * r - h) / 3;
        const double zref = 3 * (2 * r - h) * (2 * r - h) / (4 * (3 * r - h));
        for (int d = 0; d < 3; ++d)
        {
            for (int s : {1, -1})
            {
                Vec3 lo = c - Vec3::Constant(3 * r), hi = c + Vec3::Constant(3 * r);
                if (s > 0)
                    lo[d] = c[d] + r - h; // keep x_d > c_d + r - h
                else
                    hi[d] = c[d] - (r - h);
                const SphereBoxOverlap o = sphereBoxOverlap(c, r, lo, hi, true);
                EXPECT_NEAR(o.volume, Vref, 1e-13 * sphereVolume(r)) << "h " << h << " d " << d;
                // the moment is exact to round-off of the ball's (r^4); the
                // centroid of a cap much thinner than r is then less precise
                Vec3 Mref = Vec3::Zero();
                Mref[d] = s * zref * Vref;
                EXPECT_LT((o.moment - Mref).norm(), 1e-13 * std::pow(r, 4)) << "h " << h;
                if (h >= 0.01)
                {
                    const Vec3 cen = o.moment / o.volume;
                    EXPECT_NEAR(cen[d], s * zref, 1e-12 * r) << "h " << h << " d " << d;
                }
            }
        }
    }
    // the corner function alone: a quarter of the cap for b = c = 0
    for (double a : {0.0, 0.2, 0.5, 0.69})
    {
        const double h = r - a;
        EXPECT_NEAR(sphereCornerVolume(a, 0, 0, r), pi * h * h * (3 * r - h) / 12, 1e-14 * sphereVolume(r));
    }
    EXPECT_NEAR(sphereCornerVolume(0, 0, 0, r), sphereVolume(r) / 8, 1e-15);
    EXPECT_EQ(sphereCornerVolume(0.5, 0.4, 0.3, r), 0.0); // 0.5 > 0.49: corner outside
}

// A box corner, edge or face at the sphere centre, the box larger than the
// sphere: an eighth, a quarter or a half of the ball, centroid offset 3r/8
// along each cut axis (the eighth ball's centroid is (3r/8)(1,1,1)).
TEST(SphereBox, HalfQuarterEighthBallAtCentre)
{
    const double r = 1.3;
    const Vec3 c(2, 3, 4);
    const double V = sphereVolume(r);
    for (int mask = 1; mask < 8; ++mask)
    { // which axes are cut at the centre
        for (int sgn = 0; sgn < 8; ++sgn)
        { // on which side
            Vec3 lo = c - Vec3::Constant(2 * r), hi = c + Vec3::Constant(2 * r);
            Vec3 off = Vec3::Zero();
            int cuts = 0;
            for (int d = 0; d < 3; ++d)
            {
                if (!(mask >> d & 1)) continue;
                ++cuts;
                if (sgn >> d & 1)
                {
                    lo[d] = c[d];
                    off[d] = 3 * r / 8;
                }
                else
                {
                    hi[d] = c[d];
                    off[d] = -3 * r / 8;
                }
            }
            const SphereBoxOverlap o = sphereBoxOverlap(c, r, lo, hi, true);
            EXPECT_NEAR(o.volume, V / (1 << cuts), 1e-14 * V) << "mask " << mask;
            EXPECT_LT((o.moment / o.volume - off).norm(), 1e-13 * r) << "mask " << mask;
        }
    }
}

// Partition of the ball over a graded hex mesh that contains it: the overlaps
// sum to 4/3 pi r^3 and the first moments to zero (centroid at the centre),
// to 1e-12, for spheres covering from a few cells to the whole mesh. Every
// cell is detected as a box, so this runs the closed form only; with a
// SphereCornerCache the results are bitwise the same.
TEST(SphereBox, BallPartitionOverMesh)
{
    CellMesh m(
        hexGridMesh(gradedSpacing(0, 1, 7, 3.0), gradedSpacing(0, 1, 5, 0.4), gradedSpacing(0, 1, 6, 1.0)));
    for (label cell = 0; cell < m.nCells(); ++cell)
    {
        ASSERT_TRUE(m.isBox(cell));
        EXPECT_NEAR(m.shapeVolume(cell), m.cellVolume(cell), 1e-15);
    }
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> U(0, 1);
    double worst = 0;
    for (int t = 0; t < 300; ++t)
    {
        const double r = 0.02 + 0.46 * U(rng);
        const Vec3 c(r + (1 - 2 * r) * U(rng), r + (1 - 2 * r) * U(rng), r + (1 - 2 * r) * U(rng));
        double v = 0;
        Vec3 M = Vec3::Zero();
        SphereCornerCache cache;
        for (label cell = 0; cell < m.nCells(); ++cell)
        {
            const SphereOverlap3D o = sphereCellOverlap(m, cell, c, r, true);
            v += o.volume;
            M += o.volume * (o.centroid - c);
            // the corner memo changes nothing, to the last bit
            const SphereOverlap3D oc = sphereCellOverlap(m, cell, c, r, true, true, &cache);
            ASSERT_EQ(oc.volume, o.volume);
            ASSERT_EQ(oc.centroid, o.centroid);
        }
        const double V = sphereVolume(r);
        EXPECT_NEAR(v, V, 1e-12 * V) << "r " << r;
        EXPECT_LT(M.norm(), 1e-12 * r * r * r * r) << "r " << r;
        worst = std::max(worst, std::abs(v - V) / V);
    }
    std::printf("[ sphere/box ] ball over a graded mesh: max |sum V - 4/3 pi r^3| / V = %.2e\n", worst);
}

// A sphere over more planes than the corner memo holds (16 per axis): the
// memo is bypassed for the extra planes, the results stay bitwise the same
// and the ball is still partitioned to 1e-12.
TEST(SphereBox, CornerCacheOverflow)
{
    CellMesh m(hexGridMesh(gradedSpacing(0, 1, 30), gradedSpacing(0, 1, 30), gradedSpacing(0, 1, 30)));
    const Vec3 c(0.51, 0.49, 0.503);
    const double r = 0.45; // ~27 planes per axis within r
    SphereCornerCache cache;
    double v = 0;
    for (label cell = 0; cell < m.nCells(); ++cell)
    {
        const SphereOverlap3D o = sphereCellOverlap(m, cell, c, r, true);
        const SphereOverlap3D oc = sphereCellOverlap(m, cell, c, r, true, true, &cache);
        ASSERT_EQ(oc.volume, o.volume) << "cell " << cell;
        ASSERT_EQ(oc.centroid, o.centroid) << "cell " << cell;
        v += o.volume;
    }
    EXPECT_NEAR(v, sphereVolume(r), 1e-12 * sphereVolume(r));
}

// Detection: graded grids are boxes whatever the vertex order of the hex
// (a box with faces split by hanging vertices: Mapper.PartitionOfUnity3D);
// sheared hexes, twisted orders and vertices off by more than the tolerance
// (1e-12 of the cell size) are not, and keep the general path.
TEST(SphereBox, DetectsAxisAlignedHexes)
{
    const Vec3 lo(0.1, 0.2, 0.3), hi(0.4, 0.6, 0.5);
    std::vector<Vec3> pts;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i)
                pts.emplace_back(i ? hi[0] : lo[0], j ? hi[1] : lo[1], k ? hi[2] : lo[2]);
    // point index i + 2j + 4k; blockMesh order of the box
    const std::vector<label> base = {0, 1, 3, 2, 4, 5, 7, 6};
    auto oneCell = [&](const std::vector<Vec3>& p, const std::vector<label>& order)
    { return meshFromCellFaces(p, {cellModelFaces(CellShape::Hex, order)}); };
    Vec3 l, h;
    {
        const MeshView mv = oneCell(pts, base);
        ASSERT_TRUE(axisAlignedBoxCell(mv, 0, l, h));
        EXPECT_EQ(l, lo);
        EXPECT_EQ(h, hi);
        EXPECT_TRUE(CellMesh(mv).isBox(0));
    }
    { // another valid hex order: the box upside down, bottom face rotated
        const std::vector<label> turned = {5, 4, 6, 7, 1, 0, 2, 3};
        const MeshView mv = oneCell(pts, turned);
        ASSERT_TRUE(axisAlignedBoxCell(mv, 0, l, h));
        EXPECT_EQ(l, lo);
        EXPECT_EQ(h, hi);
    }
    { // twisted order: the same 8 corners, faces across the box
        std::vector<label> twisted = base;
        std::swap(twisted[2], twisted[3]);
        EXPECT_FALSE(axisAlignedBoxCell(oneCell(pts, twisted), 0, l, h));
    }
    { // one vertex off by 1e-14 (tolerance 4e-13): still a box, bound = smallest
        std::vector<Vec3> p = pts;
        p[7][0] += 1e-14;
        ASSERT_TRUE(axisAlignedBoxCell(oneCell(p, base), 0, l, h));
        EXPECT_EQ(h[0], hi[0]);
        p[7][0] += 1e-9; // beyond the tolerance
        EXPECT_FALSE(axisAlignedBoxCell(oneCell(p, base), 0, l, h));
    }
    // sheared grid -> Hex, not box
    auto shear = [](const Vec3& p) { return Vec3(p[0] + 0.1 * p[2], p[1], p[2]); };
    CellMesh sheared(
        hexGridMesh(gradedSpacing(0, 1, 2), gradedSpacing(0, 1, 2), gradedSpacing(0, 1, 2), shear));
    for (label cell = 0; cell < sheared.nCells(); ++cell)
    {
        EXPECT_EQ(sheared.shape(cell), CellShape::Hex);
        EXPECT_FALSE(sheared.isBox(cell));
    }
}

// Mapper level: on a hex mesh (h ~ d, graded), a dense random set of spheres
// gives the same void fraction (1e-12), mapped volumes (1e-12 relative) and
// per-grain first moments (1e-12 r^4) with the closed form as with the
// general `overlap` library path (MappingSettings::closedFormBoxes = false).
TEST(SphereBox, MapperVoidFractionUnchanged)
{
    CellMesh m(
        hexGridMesh(gradedSpacing(0, 1, 12, 2.0), gradedSpacing(0, 1, 10), gradedSpacing(0, 1, 11, 0.5)));
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(0, 1);
    std::vector<Vec3> x;
    std::vector<double> rad;
    for (int g = 0; g < 1500; ++g)
    {
        const double r = 0.01 + 0.06 * U(rng);
        x.emplace_back(U(rng), U(rng), U(rng)); // some stick out of the mesh
        rad.push_back(r);
    }
    MappingSettings s;
    s.outside = OutsideGrainPolicy::Skip;
    OverlapMapper fast(m, s);
    s.closedFormBoxes = false;
    OverlapMapper general(m, s);
    fast.map(x, rad);
    general.map(x, rad);
    std::vector<double> e1, e2;
    fast.voidFraction(e1);
    general.voidFraction(e2);
    double worst = 0;
    for (label c = 0; c < m.nCells(); ++c)
    {
        EXPECT_NEAR(e1[c], e2[c], 1e-12) << "cell " << c;
        worst = std::max(worst, std::abs(e1[c] - e2[c]));
    }
    auto moments = [&](const OverlapMapper& om)
    {
        std::vector<Vec3> M(x.size(), Vec3::Zero());
        for (std::size_t e = 0; e < om.entryGrain().size(); ++e)
        {
            const label g = om.entryGrain()[e];
            M[g] += om.entryVolume()[e] * (om.entryCentroid()[e] - x[g]);
        }
        return M;
    };
    const std::vector<Vec3> M1 = moments(fast), M2 = moments(general);
    for (std::size_t g = 0; g < x.size(); ++g)
    {
        const double V = sphereVolume(rad[g]);
        EXPECT_NEAR(fast.grainMappedVolume()[g], general.grainMappedVolume()[g], 1e-12 * V);
        EXPECT_LT((M1[g] - M2[g]).norm(), 1e-12 * std::pow(rad[g], 4)) << "grain " << g;
    }
    std::printf("[ sphere/box ] mapper: max |eps_closed - eps_general| = %.2e\n", worst);
}
