// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file Geometry2D.cpp
 * @brief Disc / polygon exact intersection (thesis section 3.2.1).
 */
#include "overlapMapping/Geometry2D.hpp"

#include <cmath>

namespace overlapMapping
{

namespace
{

inline double cross2(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

/// Accumulator of the signed contributions of one edge.
struct Acc
{
    double area = 0.0;
    double mx = 0.0;
    double my = 0.0;
    double polar = 0.0;
};

/// Straight triangle (0, p, q): area, first moment, polar moment.
template <bool Polar>
inline void addTriangle(Acc& acc, double px, double py, double qx, double qy)
{
    const double a = 0.5 * cross2(px, py, qx, qy);
    acc.area += a;
    const double a3 = a * (1.0 / 3.0);
    acc.mx += a3 * (px + qx);
    acc.my += a3 * (py + qy);
    if (Polar)
    {
        acc.polar += a * (1.0 / 6.0) * (px * px + py * py + qx * qx + qy * qy + px * qx + py * qy);
    }
}

/// Pseudo-angle of a non-zero direction: monotone in the true angle, in
/// (-2, 2], opposite directions differ by 2 (a quarter turn ~ 1).
inline double pseudoAngle(double x, double y)
{
    const double p = x / (std::abs(x) + std::abs(y));
    return y >= 0.0 ? 1.0 - p : p - 1.0;
}

/// Circular arc of the polygon boundary outside the disc, swept from the
/// direction of s to the direction of e (both on or outside the circle).
/// Consecutive outside pieces are merged into one arc: the sector terms are
/// additive (angle) and telescoping (first moment), so only the end points
/// are needed. The swept angle S may exceed pi in magnitude: it is atan2 of
/// the end points plus 2 pi m, the number of turns m being read off the
/// accumulated pseudo-angle P (accurate to ~0.15 rad, so the rounding is
/// exact). Returns without any atan2 when s == e (full turn or nothing).
template <bool Polar>
inline void addArc(Acc& acc, double r, double r2, double sx, double sy, double ex, double ey, double P)
{
    constexpr double twoPi = 2.0 * pi;
    double phi = 0.0;
    if (sx != ex || sy != ey)
    {
        phi = std::atan2(cross2(sx, sy, ex, ey), sx * ex + sy * ey);
    }
    const double S = phi + twoPi * std::nearbyint((P * (0.5 * pi) - phi) / twoPi);
    acc.area += 0.5 * r2 * S;
    const double is = 1.0 / std::sqrt(sx * sx + sy * sy);
    const double ie = 1.0 / std::sqrt(ex * ex + ey * ey);
    const double r3 = r2 * r * (1.0 / 3.0);
    // ∫ x dA = r^3/3 (sin t2 - sin t1), ∫ y dA = r^3/3 (cos t1 - cos t2)
    acc.mx += r3 * (ey * ie - sy * is);
    acc.my += r3 * (sx * is - ex * ie);
    if (Polar)
    {
        acc.polar += 0.25 * r2 * r2 * S;
    }
}

/// State of the arc being accumulated.
struct Arc
{
    bool open = false;
    double sx = 0.0, sy = 0.0; // start point
    double P = 0.0;            // accumulated pseudo-angle
    double b = 0.0;            // pseudo-angle of the last point
    void start(double x, double y)
    {
        open = true;
        sx = x;
        sy = y;
        P = 0.0;
        b = pseudoAngle(x, y);
    }
    void extend(double x, double y)
    {
        const double nb = pseudoAngle(x, y);
        double d = nb - b;
        if (d > 2.0)
        {
            d -= 4.0;
        }
        else if (d <= -2.0)
        {
            d += 4.0;
        }
        P += d;
        b = nb;
    }
};

template <bool Polar>
inline void closeArc(Acc& acc, Arc& arc, double r, double r2, double ex, double ey)
{
    addArc<Polar>(acc, r, r2, arc.sx, arc.sy, ex, ey, arc.P);
    arc.open = false;
}

template <bool Polar>
inline void addEdge(Acc& acc, Arc& arc, double r, double r2, double ax, double ay, double bx, double by)
{
    const double dx = bx - ax;
    const double dy = by - ay;
    const double A = dx * dx + dy * dy;
    if (A <= 0.0)
    {
        return; // degenerate edge
    }
    const double a2 = ax * ax + ay * ay;
    const double b2 = bx * bx + by * by;
    if (a2 <= r2 && b2 <= r2)
    {
        if (arc.open)
        {
            closeArc<Polar>(acc, arc, r, r2, ax, ay);
        }
        addTriangle<Polar>(acc, ax, ay, bx, by); // edge inside the disc
        return;
    }
    const double B = ax * dx + ay * dy;
    const double C = a2 - r2;
    const double disc = B * B - A * C;
    double t1 = 1.0, t2 = 0.0;
    if (disc > 0.0)
    {
        const double s = std::sqrt(disc);
        // Numerically stable roots of A t^2 + 2 B t + C = 0
        if (B >= 0.0)
        {
            const double qq = -(B + s);
            t1 = qq / A;
            t2 = C / qq;
        }
        else
        {
            const double qq = -B + s;
            t2 = qq / A;
            t1 = C / qq;
        }
        if (t1 > t2)
        {
            const double t = t1;
            t1 = t2;
            t2 = t;
        }
    }
    if (disc <= 0.0 || t1 >= 1.0 || t2 <= 0.0)
    {
        // whole edge outside the disc (or tangent): part of an arc
        if (!arc.open)
        {
            arc.start(ax, ay);
        }
        arc.extend(bx, by);
        return;
    }
    double px = ax, py = ay, qx = bx, qy = by;
    if (t1 > 0.0)
    {
        px = ax + t1 * dx;
        py = ay + t1 * dy;
        if (!arc.open)
        {
            arc.start(ax, ay);
        }
        arc.extend(px, py);
        closeArc<Polar>(acc, arc, r, r2, px, py);
    }
    else if (arc.open)
    {
        closeArc<Polar>(acc, arc, r, r2, ax, ay);
    }
    if (t2 < 1.0)
    {
        qx = ax + t2 * dx;
        qy = ay + t2 * dy;
    }
    addTriangle<Polar>(acc, px, py, qx, qy);
    if (t2 < 1.0)
    {
        arc.start(qx, qy);
        arc.extend(bx, by);
    }
}

template <bool Polar>
inline Acc accumulate(const Vec2& c, double r, const Vec2* poly, int n)
{
    Acc acc;
    Arc arc;
    const double r2 = r * r;
    const double x0 = poly[n - 1][0] - c[0];
    const double y0 = poly[n - 1][1] - c[1];
    double ax = x0, ay = y0;
    for (int i = 0; i < n; ++i)
    {
        const double bx = poly[i][0] - c[0];
        const double by = poly[i][1] - c[1];
        addEdge<Polar>(acc, arc, r, r2, ax, ay, bx, by);
        ax = bx;
        ay = by;
    }
    if (arc.open)
    {
        closeArc<Polar>(acc, arc, r, r2, x0, y0);
    }
    return acc;
}

} // namespace

DiscPolygonMoments discPolygonMoments(const Vec2& centre, double radius, const Vec2* poly, int n,
                                      bool withPolar)
{
    DiscPolygonMoments m;
    if (n < 3 || !(radius > 0.0))
    {
        return m;
    }
    const Acc acc =
        withPolar ? accumulate<true>(centre, radius, poly, n) : accumulate<false>(centre, radius, poly, n);
    m.area = acc.area;
    m.moment = Vec2(acc.mx, acc.my);
    m.polar = acc.polar;
    return m;
}

DiscOverlap2D discPolygonOverlap(const Vec2& centre, double radius, const Vec2* poly, int n)
{
    DiscOverlap2D out;
    out.centroid = centre;
    const DiscPolygonMoments m = discPolygonMoments(centre, radius, poly, n);
    if (m.area != 0.0)
    {
        out.area = std::abs(m.area);
        out.centroid = centre + m.moment / m.area;
    }
    return out;
}

double polygonAreaCentroid(const Vec2* poly, int n, Vec2& centroid)
{
    centroid = Vec2::Zero();
    if (n < 3)
    {
        return 0.0;
    }
    // Shift to the first vertex for round-off
    const Vec2 o = poly[0];
    double a = 0.0, mx = 0.0, my = 0.0;
    for (int i = 1; i + 1 < n; ++i)
    {
        const Vec2 p = poly[i] - o;
        const Vec2 q = poly[i + 1] - o;
        const double t = 0.5 * cross2(p[0], p[1], q[0], q[1]);
        a += t;
        mx += t * (p[0] + q[0]) / 3.0;
        my += t * (p[1] + q[1]) / 3.0;
    }
    if (a != 0.0)
    {
        centroid = o + Vec2(mx / a, my / a);
    }
    else
    {
        for (int i = 0; i < n; ++i)
        {
            centroid += poly[i];
        }
        centroid /= n;
    }
    return a;
}

} // namespace overlapMapping
