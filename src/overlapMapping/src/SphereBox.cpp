// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file SphereBox.cpp
 * @brief Closed-form sphere ∩ axis-aligned box (derivation in SphereBox.hpp).
 *
 * Everything is computed for the unit ball (offsets divided by r) and scaled
 * back by r^3 (volume) and r^4 (moment) at the end.
 */
#include "overlapMapping/SphereBox.hpp"

#include "overlapMapping/MeshView.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace overlapMapping
{

namespace
{

/// Corner region of the unit ball: volume and first moments (x, y, z).
struct Corner
{
    double v, mx, my, mz;
};

/// Arc angle of the disc corner {y > p, z > q, |(y,z)| < rho}: the arc runs
/// from (u, q) to (p, w) (step 3 of SphereBox.hpp).
inline double arcAngle(double p, double q, double u, double w)
{
    if (p == 0.0 && q == 0.0)
    {
        return 0.5 * pi; // quarter disc
    }
    return std::atan2(u * w - p * q, u * p + q * w);
}

/// Area of the disc corner minus its arc term rho^2 phi / 2.
inline double areaLines(double p, double q, double u, double w) { return -0.5 * (p * w + q * u) + p * q; }

/// ∫ (rho^2 - |q|^2) dA over the disc corner (step 5 of SphereBox.hpp).
inline double polarDefect(double rho2, double phi, double p, double q, double u, double w)
{
    return 0.25 * rho2 * rho2 * phi
           - p * ((0.5 * rho2 - 0.25 * p * p) * (w - q) - (w * w * w - q * q * q) / 12.0)
           - q * ((0.5 * rho2 - 0.25 * q * q) * (u - p) - (u * u * u - p * p * p) / 12.0);
}

/// Corner {|p| < 1, x > a, y > b, z > c}, a, b, c in [0, 1), a^2+b^2+c^2 < 1.
inline Corner unitCorner(double a, double b, double c, bool withMoment)
{
    const double a2 = a * a, b2 = b * b, c2 = c * c;
    const double sab = std::sqrt(std::max(1.0 - a2 - b2, 0.0));
    const double sac = std::sqrt(std::max(1.0 - a2 - c2, 0.0));
    const double sbc = std::sqrt(std::max(1.0 - b2 - c2, 0.0));
    // arcs on the three faces (offsets, arc ends)
    const double phiA = arcAngle(b, c, sac, sab);
    const double phiB = arcAngle(a, c, sbc, sab);
    const double phiC = arcAngle(a, b, sbc, sac);
    // sum of the three vertex angles theta = atan2(a b, s_ab) etc.: their sum
    // is in [0, π/2] (Ω >= 0), so one atan2 of the product of the three
    // complex numbers s_ab + i a b, ... gives it.
    const double re1 = sab, im1 = a * b;
    const double re2 = sac, im2 = a * c;
    const double re3 = sbc, im3 = b * c;
    const double re12 = re1 * re2 - im1 * im2, im12 = re1 * im2 + im1 * re2;
    const double theta = (im1 == 0.0 && im2 == 0.0 && im3 == 0.0)
                             ? 0.0 // at most one plane off the centre
                             : std::atan2(re12 * im3 + im12 * re3, re12 * re3 - im12 * im3);
    // 3 W = Ω - a A_a - b A_b - c A_c (unit radius)
    const double ra2 = 1.0 - a2, rb2 = 1.0 - b2, rc2 = 1.0 - c2;
    const double Aa = 0.5 * ra2 * phiA + areaLines(b, c, sac, sab);
    const double Ab = 0.5 * rb2 * phiB + areaLines(a, c, sbc, sab);
    const double Ac = 0.5 * rc2 * phiC + areaLines(a, b, sbc, sac);
    const double omega = 0.5 * pi - theta - (a * phiA + b * phiB + c * phiC);
    Corner k;
    k.v = (omega - a * Aa - b * Ab - c * Ac) / 3.0;
    if (withMoment)
    {
        k.mx = 0.5 * polarDefect(ra2, phiA, b, c, sac, sab);
        k.my = 0.5 * polarDefect(rb2, phiB, a, c, sbc, sab);
        k.mz = 0.5 * polarDefect(rc2, phiC, a, b, sbc, sac);
    }
    else
    {
        k.mx = k.my = k.mz = 0.0;
    }
    return k;
}

/// Half-line decomposition of one axis of the box (step 1 of SphereBox.hpp):
/// offsets t in [0, 1) with volume and moment coefficients.
struct AxisTerms
{
    double t[3], cv[3], cm[3];
    int n = 0;
    void add(double tt, double v, double m)
    {
        if (tt < 1.0)
        {
            t[n] = tt;
            cv[n] = v;
            cm[n] = m;
            ++n;
        }
    }
};

inline AxisTerms axisTerms(double x0, double x1)
{
    AxisTerms a;
    if (x0 >= 0.0)
    {
        a.add(x0, 1.0, 1.0);
        a.add(x1, -1.0, -1.0);
    }
    else if (x1 <= 0.0)
    {
        a.add(-x1, 1.0, -1.0);
        a.add(-x0, -1.0, 1.0);
    }
    else
    {
        a.add(0.0, 2.0, 0.0);
        a.add(x1, -1.0, -1.0);
        a.add(-x0, -1.0, 1.0);
    }
    return a;
}

} // namespace

SphereCornerCache::SphereCornerCache()
    : filled_(maxPlanes * maxPlanes * maxPlanes, 0u), values_(4 * filled_.size(), 0.0)
{
}

void SphereCornerCache::bind(const Vec3& centre, double r, bool withMoment)
{
    if (centre == centre_ && r == r_ && withMoment == withMoment_)
    {
        return;
    }
    centre_ = centre;
    r_ = r;
    withMoment_ = withMoment;
    nPlanes_[0] = nPlanes_[1] = nPlanes_[2] = 0;
    if (++stamp_ == 0)
    {
        std::fill(filled_.begin(), filled_.end(), 0u);
        stamp_ = 1;
    }
}

int SphereCornerCache::planeIndex(int axis, double t)
{
    const int n = nPlanes_[axis];
    for (int i = 0; i < n; ++i)
    {
        if (planes_[axis][i] == t)
        {
            return i;
        }
    }
    if (n == maxPlanes)
    {
        return -1;
    }
    planes_[axis][n] = t;
    nPlanes_[axis] = n + 1;
    return n;
}

int SphereCornerCache::slot(double a, double b, double c)
{
    const int i = planeIndex(0, a), j = planeIndex(1, b), k = planeIndex(2, c);
    if (i < 0 || j < 0 || k < 0)
    {
        return -1;
    }
    return i + maxPlanes * (j + maxPlanes * k);
}

double sphereCornerVolume(double a, double b, double c, double r)
{
    const double ia = a / r, ib = b / r, ic = c / r;
    if (ia * ia + ib * ib + ic * ic >= 1.0)
    {
        return 0.0;
    }
    return std::max(unitCorner(ia, ib, ic, false).v, 0.0) * r * r * r;
}

SphereBoxOverlap sphereBoxOverlap(const Vec3& c, double r, const Vec3& lo, const Vec3& hi, bool withMoment,
                                  SphereCornerCache* cache)
{
    SphereBoxOverlap out;
    if (!(r > 0.0))
    {
        return out;
    }
    if (cache)
    {
        cache->bind(c, r, withMoment);
    }
    const double inv = 1.0 / r;
    AxisTerms ax[3];
    for (int d = 0; d < 3; ++d)
    {
        const double x0 = (lo[d] - c[d]) * inv, x1 = (hi[d] - c[d]) * inv;
        if (!(x1 > x0))
        {
            return out;
        }
        ax[d] = axisTerms(x0, x1);
        if (ax[d].n == 0)
        {
            return out; // the box lies beyond the ball along this axis
        }
    }
    const AxisTerms &X = ax[0], &Y = ax[1], &Z = ax[2];
    double v = 0.0, mx = 0.0, my = 0.0, mz = 0.0;
    for (int i = 0; i < X.n; ++i)
    {
        const double a = X.t[i];
        for (int j = 0; j < Y.n; ++j)
        {
            const double b = Y.t[j];
            const double ab2 = a * a + b * b;
            if (ab2 >= 1.0)
            {
                continue;
            }
            for (int k = 0; k < Z.n; ++k)
            {
                const double cc = Z.t[k];
                if (ab2 + cc * cc >= 1.0)
                {
                    continue;
                }
                Corner w;
                const int sl = cache ? cache->slot(a, b, cc) : -1;
                if (sl >= 0 && cache->filled_[sl] == cache->stamp_)
                {
                    const double* val = &cache->values_[4 * std::size_t(sl)];
                    w = {val[0], val[1], val[2], val[3]};
                }
                else
                {
                    w = unitCorner(a, b, cc, withMoment);
                    if (sl >= 0)
                    {
                        double* val = &cache->values_[4 * std::size_t(sl)];
                        val[0] = w.v;
                        val[1] = w.mx;
                        val[2] = w.my;
                        val[3] = w.mz;
                        cache->filled_[sl] = cache->stamp_;
                    }
                }
                const double cyz = Y.cv[j] * Z.cv[k];
                v += X.cv[i] * cyz * w.v;
                if (withMoment)
                {
                    mx += X.cm[i] * cyz * w.mx;
                    my += X.cv[i] * Y.cm[j] * Z.cv[k] * w.my;
                    mz += X.cv[i] * Y.cv[j] * Z.cm[k] * w.mz;
                }
            }
        }
    }
    const double r3 = r * r * r;
    out.volume = std::max(v, 0.0) * r3;
    if (withMoment)
    {
        out.moment = Vec3(mx, my, mz) * (r3 * r);
    }
    return out;
}

bool axisAlignedBoxCell(const MeshView& m, label cell, Vec3& lo, Vec3& hi, double relTol)
{
    const label fb = m.cellOffsets[cell], fe = m.cellOffsets[cell + 1];
    if (fe - fb < 6)
    {
        return false;
    }
    Vec3 bmin = Vec3::Constant(std::numeric_limits<double>::max());
    Vec3 bmax = -bmin;
    for (label i = fb; i < fe; ++i)
    {
        const label f = m.cellFaces[i];
        for (label k = m.faceOffsets[f]; k < m.faceOffsets[f + 1]; ++k)
        {
            const Vec3& p = m.points[m.faceVertices[k]];
            bmin = bmin.cwiseMin(p);
            bmax = bmax.cwiseMax(p);
        }
    }
    const Vec3 ext = bmax - bmin;
    const double tol = relTol * ext.maxCoeff();
    if (!(ext.minCoeff() > 2.0 * tol))
    {
        return false;
    }
    // bit 2d: on the plane x_d = min, bit 2d+1: on x_d = max
    Vec3 side[2] = {Vec3::Constant(std::numeric_limits<double>::max()),
                    Vec3::Constant(std::numeric_limits<double>::max())};
    unsigned used = 0;
    for (label i = fb; i < fe; ++i)
    {
        const label f = m.cellFaces[i];
        unsigned planes = 63;
        for (label k = m.faceOffsets[f]; k < m.faceOffsets[f + 1] && planes; ++k)
        {
            const Vec3& p = m.points[m.faceVertices[k]];
            unsigned on = 0;
            for (int d = 0; d < 3; ++d)
            {
                on |= unsigned(std::abs(p[d] - bmin[d]) <= tol) << (2 * d);
                on |= unsigned(std::abs(p[d] - bmax[d]) <= tol) << (2 * d + 1);
            }
            planes &= on;
        }
        if (planes == 0 || (planes & (planes - 1)) != 0)
        {
            return false; // face off the box planes (or degenerate)
        }
        used |= planes;
        int bit = 0;
        while (!(planes >> bit & 1u))
        {
            ++bit;
        }
        const int d = bit / 2;
        double& bound = side[bit % 2][d];
        for (label k = m.faceOffsets[f]; k < m.faceOffsets[f + 1]; ++k)
        {
            bound = std::min(bound, m.points[m.faceVertices[k]][d]);
        }
    }
    if (used != 63)
    {
        return false;
    }
    const double boxVol = (side[1] - side[0]).prod();
    if (label(m.cellVolumes.size()) > cell && !(std::abs(m.cellVolumes[cell] - boxVol) <= 1e-9 * boxVol))
    {
        return false; // not a closed box (defensive; cannot happen for a valid cell)
    }
    lo = side[0];
    hi = side[1];
    return true;
}

} // namespace overlapMapping
