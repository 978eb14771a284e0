// SPDX-License-Identifier: GPL-3.0-or-later
// Unit tests of the exact disc/polygon intersection (thesis section 3.2.1).
// References: closed-form areas/centroids of discs, quarter/half discs and
// circular segments; Monte-Carlo estimates (fixed seed) for generic cases.
#include "overlapMapping/Geometry2D.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace overlapMapping;

namespace
{

std::vector<Vec2> rect(double x0, double y0, double x1, double y1)
{
    return {Vec2(x0, y0), Vec2(x1, y0), Vec2(x1, y1), Vec2(x0, y1)};
}

// Circular segment beyond the line y = h of a disc of radius r at the origin.
double segmentArea(double r, double h) { return r * r * std::acos(h / r) - h * std::sqrt(r * r - h * h); }
double segmentCentroidY(double r, double h)
{
    return 2.0 / 3.0 * std::pow(r * r - h * h, 1.5) / segmentArea(r, h);
}

} // namespace

// Disc fully inside the unit square: area pi r^2, centroid = centre.
// Tolerance 1e-14 relative (round-off of a sum of 4 atan2).
TEST(DiscPolygon, DiscFullyInside)
{
    const auto sq = rect(0, 0, 1, 1);
    const double r = 0.3;
    const Vec2 c(0.45, 0.52);
    const DiscOverlap2D o = discPolygonOverlap(c, r, sq.data(), 4);
    EXPECT_NEAR(o.area, pi * r * r, 1e-14 * pi * r * r);
    EXPECT_NEAR(o.centroid[0], c[0], 1e-14);
    EXPECT_NEAR(o.centroid[1], c[1], 1e-14);
    // polar moment of the full disc: pi r^4 / 2
    const DiscPolygonMoments m = discPolygonMoments(c, r, sq.data(), 4, true);
    EXPECT_NEAR(m.polar, 0.5 * pi * std::pow(r, 4), 1e-14);
}

// Polygon fully inside the disc: polygon area and centroid (1e-14).
TEST(DiscPolygon, PolygonFullyInside)
{
    const std::vector<Vec2> tri = {Vec2(0.1, 0.1), Vec2(0.4, 0.15), Vec2(0.2, 0.35)};
    const DiscOverlap2D o = discPolygonOverlap(Vec2(0.2, 0.2), 5.0, tri.data(), 3);
    Vec2 cen;
    const double a = polygonAreaCentroid(tri.data(), 3, cen);
    EXPECT_NEAR(o.area, a, 1e-15);
    EXPECT_NEAR(o.centroid[0], cen[0], 1e-14);
    EXPECT_NEAR(o.centroid[1], cen[1], 1e-14);
}

// Disc centred on a square corner: quarter disc, centroid 4r/(3 pi) from the
// corner along both axes (1e-14).
TEST(DiscPolygon, CentredOnCorner)
{
    const auto sq = rect(0, 0, 1, 1);
    const double r = 0.4;
    const DiscOverlap2D o = discPolygonOverlap(Vec2(0, 0), r, sq.data(), 4);
    EXPECT_NEAR(o.area, 0.25 * pi * r * r, 1e-15);
    EXPECT_NEAR(o.centroid[0], 4 * r / (3 * pi), 1e-14);
    EXPECT_NEAR(o.centroid[1], 4 * r / (3 * pi), 1e-14);
}

// Disc centred on an edge: half disc, centroid 4r/(3 pi) off the edge (1e-14).
TEST(DiscPolygon, CentredOnEdgeHalfDisc)
{
    const auto sq = rect(0, 0, 1, 1);
    const double r = 0.3;
    const DiscOverlap2D o = discPolygonOverlap(Vec2(0.5, 0.0), r, sq.data(), 4);
    EXPECT_NEAR(o.area, 0.5 * pi * r * r, 1e-15);
    EXPECT_NEAR(o.centroid[0], 0.5, 1e-14);
    EXPECT_NEAR(o.centroid[1], 4 * r / (3 * pi), 1e-14);
}

// Disc cut by a straight line at signed distance h from its centre:
// circular segment area r^2 acos(h/r) - h sqrt(r^2-h^2) and centroid
// 2/3 (r^2-h^2)^{3/2} / A (1e-13 relative).
TEST(DiscPolygon, CircularSegment)
{
    const double r = 1.3;
    for (double h : {-1.2, -0.7, -0.1, 0.0, 0.05, 0.5, 0.9, 1.25})
    {
        const auto half = rect(-5, h, 5, 5);
        const DiscOverlap2D o = discPolygonOverlap(Vec2(0, 0), r, half.data(), 4);
        EXPECT_NEAR(o.area, segmentArea(r, h), 1e-13 * r * r) << "h=" << h;
        EXPECT_NEAR(o.centroid[1], segmentCentroidY(r, h), 1e-12 * r) << "h=" << h;
        EXPECT_NEAR(o.centroid[0], 0.0, 1e-13) << "h=" << h;
    }
}

// Tangency: touching from outside gives 0, from inside the full disc (exact).
TEST(DiscPolygon, Tangent)
{
    const auto sq = rect(0, 0, 1, 1);
    const double r = 0.25;
    EXPECT_NEAR(discPolygonOverlap(Vec2(1.25, 0.5), r, sq.data(), 4).area, 0.0, 1e-15);
    EXPECT_NEAR(discPolygonOverlap(Vec2(0.75, 0.5), r, sq.data(), 4).area, pi * r * r, 1e-15);
    // far away
    EXPECT_EQ(discPolygonOverlap(Vec2(5, 5), r, sq.data(), 4).area, 0.0);
}

// Disc centred on a vertex shared by 4 squares / on an edge shared by 2:
// the pieces partition the disc (1e-15 relative), each is a quarter/half.
TEST(DiscPolygon, CentredOnSharedVertexAndEdge)
{
    const double r = 0.37;
    double sum = 0.0;
    Vec2 mom = Vec2::Zero();
    for (int i = -1; i <= 0; ++i)
        for (int j = -1; j <= 0; ++j)
        {
            const auto sq = rect(i, j, i + 1, j + 1);
            const DiscOverlap2D o = discPolygonOverlap(Vec2(0, 0), r, sq.data(), 4);
            EXPECT_NEAR(o.area, 0.25 * pi * r * r, 1e-15);
            sum += o.area;
            mom += o.area * o.centroid;
        }
    EXPECT_NEAR(sum, pi * r * r, 1e-15);
    EXPECT_NEAR(mom.norm(), 0.0, 1e-16);
    // triangle fan around the centre (6 triangles) also partitions the disc
    sum = 0.0;
    for (int k = 0; k < 6; ++k)
    {
        const double a0 = k * pi / 3, a1 = (k + 1) * pi / 3;
        const std::vector<Vec2> t = {Vec2(0, 0), Vec2(cos(a0), sin(a0)), Vec2(cos(a1), sin(a1))};
        sum += discPolygonOverlap(Vec2(0, 0), r, t.data(), 3).area;
    }
    EXPECT_NEAR(sum, pi * r * r, 1e-15);
}

// Orientation: a clockwise polygon gives negated signed moments; the overlap
// (area, centroid) does not depend on it (1e-15).
TEST(DiscPolygon, Orientation)
{
    auto sq = rect(0, 0, 1, 1);
    const Vec2 c(0.9, 0.2);
    const double r = 0.33;
    const DiscPolygonMoments ccw = discPolygonMoments(c, r, sq.data(), 4, true);
    std::vector<Vec2> cw(sq.rbegin(), sq.rend());
    const DiscPolygonMoments m = discPolygonMoments(c, r, cw.data(), 4, true);
    EXPECT_NEAR(m.area, -ccw.area, 1e-15);
    EXPECT_NEAR(m.polar, -ccw.polar, 1e-15);
    EXPECT_NEAR((m.moment + ccw.moment).norm(), 0.0, 1e-15);
    EXPECT_GT(ccw.area, 0.0);
}

// Monte-Carlo check (fixed seed, N = 4e6 samples) of area, centroid and polar
// moment for a generic disc over an irregular convex hexagon and a
// non-convex polygon. Tolerance: 5 standard errors of the estimator.
TEST(DiscPolygon, MonteCarlo)
{
    const std::vector<std::vector<Vec2>> polys = {
        {Vec2(0.1, 0.0), Vec2(0.8, 0.1), Vec2(1.0, 0.6), Vec2(0.7, 1.0), Vec2(0.2, 0.9), Vec2(-0.1, 0.4)},
        {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0.5, 0.3), Vec2(0, 1)}}; // non-convex
    const Vec2 c(0.62, 0.41);
    const double r = 0.47;
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    const int N = 4000000;
    for (const auto& P : polys)
    {
        const int n = int(P.size());
        long hits = 0;
        double sx = 0, sy = 0, sp = 0, sp2 = 0;
        for (int i = 0; i < N; ++i)
        {
            const Vec2 x = c + r * Vec2(U(rng), U(rng));
            if ((x - c).squaredNorm() > r * r) continue;
            int wn = 0; // winding number
            for (int k = 0; k < n; ++k)
            {
                const Vec2& a = P[k];
                const Vec2& b = P[(k + 1) % n];
                const double cr = (b[0] - a[0]) * (x[1] - a[1]) - (x[0] - a[0]) * (b[1] - a[1]);
                if (a[1] <= x[1])
                {
                    if (b[1] > x[1] && cr > 0) ++wn;
                }
                else if (b[1] <= x[1] && cr < 0)
                    --wn;
            }
            if (wn == 0) continue;
            ++hits;
            sx += x[0];
            sy += x[1];
            const double s2 = (x - c).squaredNorm();
            sp += s2;
            sp2 += s2 * s2;
        }
        const double box = 4 * r * r;
        const double p = double(hits) / N;
        const double areaMC = box * p;
        const double seArea = box * std::sqrt(p * (1 - p) / N);
        const DiscPolygonMoments m = discPolygonMoments(c, r, P.data(), n, true);
        EXPECT_NEAR(m.area, areaMC, 5 * seArea);
        // centroid: standard error ~ r / sqrt(hits)
        const Vec2 cen = c + m.moment / m.area;
        EXPECT_NEAR(cen[0], sx / hits, 5 * r / std::sqrt(double(hits)));
        EXPECT_NEAR(cen[1], sy / hits, 5 * r / std::sqrt(double(hits)));
        const double polarMC = box * sp / N;
        const double sePolar = box * std::sqrt((sp2 / N - (sp / N) * (sp / N)) / N);
        EXPECT_NEAR(m.polar, polarMC, 5 * sePolar);
    }
}
