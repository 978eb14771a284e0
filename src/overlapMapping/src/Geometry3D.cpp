// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file Geometry3D.cpp
 * @brief Sphere / cell overlaps through the `overlap` library.
 */
#include "overlapMapping/Geometry3D.hpp"

#include "overlapMapping/Geometry2D.hpp"
#include "overlapMapping/SphereBox.hpp"

#include <overlap.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace overlapMapping
{

namespace
{

inline overlap::Vector ov(const Vec3& v) { return overlap::Vector(v[0], v[1], v[2]); }

/// Scratch array of n elements of T for a face's vertices: on the stack up
/// to N (the faces of hex, tet and most polyhedral cells), on the heap beyond.
template <class T, int N = 64>
class ScratchArray
{
public:
    explicit ScratchArray(std::size_t n) : data_(stack_)
    {
        if (n > std::size_t(N))
        {
            heap_.resize(n);
            data_ = heap_.data();
        }
    }
    ScratchArray(const ScratchArray&) = delete;
    ScratchArray& operator=(const ScratchArray&) = delete;
    T& operator[](std::size_t k) { return data_[k]; }
    const T* data() const { return data_; }

private:
    T stack_[N];
    std::vector<T> heap_;
    T* data_;
};

/// Sphere AABB vs points AABB.
template <int N>
inline bool aabbMiss(const Vec3& c, double r, const Vec3* v)
{
    for (int d = 0; d < 3; ++d)
    {
        double lo = v[0][d], hi = v[0][d];
        for (int i = 1; i < N; ++i)
        {
            lo = std::min(lo, v[i][d]);
            hi = std::max(hi, v[i][d]);
        }
        if (c[d] - r >= hi || c[d] + r <= lo)
        {
            return true;
        }
    }
    return false;
}

/// Face-integral term of the first moment for a planar polygon given by 3D
/// points (counter-clockwise about @p n), outward normal (for the cell)
/// @p N = +-n.
inline void addFaceMoment(Vec3& M, const Vec3& c, double r2, const Vec3& N, const Vec3& n, const Vec3& e1,
                          const Vec3& pOnPlane, const Vec3* pts, int np)
{
    const double delta = N.dot(pOnPlane - c);
    const double rho2 = r2 - delta * delta;
    if (rho2 <= 0.0)
    {
        return;
    }
    const Vec3 e2 = n.cross(e1);
    ScratchArray<Vec2> poly(np);
    for (int k = 0; k < np; ++k)
    {
        const Vec3 d = pts[k] - c;
        poly[k] = Vec2(d.dot(e1), d.dot(e2));
    }
    const DiscPolygonMoments m = discPolygonMoments(Vec2::Zero(), std::sqrt(rho2), poly.data(), np, true);
    M += N * (0.5 * (m.polar - rho2 * m.area));
}

/// sphereCellOverlap() for a box cell [lo, hi].
SphereOverlap3D sphereBoxCell(const Vec3& lo, const Vec3& hi, const Vec3& c, double r, bool withCentroid,
                              SphereCornerCache* cache)
{
    SphereOverlap3D out;
    out.centroid = c;
    double out2 = 0.0; // squared distance from c to the box
    double inside = r; // smallest distance from c to a face (c inside)
    double far2 = 0.0; // squared distance from c to the farthest corner
    for (int d = 0; d < 3; ++d)
    {
        const double l = c[d] - lo[d], h = hi[d] - c[d];
        if (l < 0.0)
        {
            out2 += l * l;
        }
        else if (h < 0.0)
        {
            out2 += h * h;
        }
        inside = std::min(inside, std::min(l, h));
        const double f = std::max(std::abs(l), std::abs(h));
        far2 += f * f;
    }
    const double r2 = r * r;
    if (out2 >= r2)
    {
        return out; // no overlap
    }
    if (inside >= r)
    {
        out.volume = sphereVolume(r); // sphere inside the box
        return out;
    }
    if (far2 <= r2)
    {
        out.volume = (hi - lo).prod(); // box inside the sphere
        out.centroid = 0.5 * (lo + hi);
        return out;
    }
    const SphereBoxOverlap o = sphereBoxOverlap(c, r, lo, hi, withCentroid, cache);
    out.volume = o.volume;
    if (withCentroid && o.volume > 0.0)
    {
        // the moment is exact to ~1e-15 r^4: for a sliver much thinner than r
        // the quotient may leave the sliver; keep it in box ∩ sphere's box
        out.centroid = c + o.moment / o.volume;
        for (int d = 0; d < 3; ++d)
        {
            out.centroid[d] =
                std::min(std::max(out.centroid[d], std::max(lo[d], c[d] - r)), std::min(hi[d], c[d] + r));
        }
    }
    return out;
}

} // namespace

double sphereTetVolume(const Vec3& c, double r, const Vec3 v[4])
{
    if (aabbMiss<4>(c, r, v))
    {
        return 0.0;
    }
    const double s = (v[1] - v[0]).cross(v[2] - v[0]).dot(v[3] - v[0]);
    if (s == 0.0)
    {
        return 0.0;
    }
    const overlap::Sphere sp(ov(c), r);
    if (s > 0.0)
    {
        return overlap::overlap_volume(sp, overlap::Tetrahedron(ov(v[0]), ov(v[1]), ov(v[2]), ov(v[3])));
    }
    return overlap::overlap_volume(sp, overlap::Tetrahedron(ov(v[0]), ov(v[2]), ov(v[1]), ov(v[3])));
}

double spherePrismVolume(const Vec3& c, double r, const Vec3 v[6])
{
    if (aabbMiss<6>(c, r, v))
    {
        return 0.0;
    }
    const overlap::Sphere sp(ov(c), r);
    return overlap::overlap_volume(
        sp, overlap::Wedge(ov(v[0]), ov(v[1]), ov(v[2]), ov(v[3]), ov(v[4]), ov(v[5])));
}

double sphereHexVolume(const Vec3& c, double r, const Vec3 v[8])
{
    if (aabbMiss<8>(c, r, v))
    {
        return 0.0;
    }
    const overlap::Sphere sp(ov(c), r);
    return overlap::overlap_volume(sp, overlap::Hexahedron(ov(v[0]), ov(v[1]), ov(v[2]), ov(v[3]), ov(v[4]),
                                                           ov(v[5]), ov(v[6]), ov(v[7])));
}

double sphereCellVolumeByTets(const CellMesh& mesh, label cell, const Vec3& c, double r)
{
    const MeshView& m = mesh.view();
    const Vec3& C = mesh.cellCentre(cell);
    const overlap::Sphere sp(ov(c), r);
    double vol = 0.0;
    for (label i = mesh.cellFacesBegin(cell); i < mesh.cellFacesEnd(cell); ++i)
    {
        const label f = mesh.cellFace(i);
        const bool own = mesh.cellFaceSign(i) > 0.0;
        const Vec3& F = mesh.faceCentre(f);
        const label b = m.faceOffsets[f];
        const label n = m.faceOffsets[f + 1] - b;
        for (label k = 0; k < n; ++k)
        {
            // edge (p, q) in the cell's outward orientation
            label ip = m.faceVertices[b + k];
            label iq = m.faceVertices[b + (k + 1) % n];
            if (!own)
            {
                std::swap(ip, iq);
            }
            const Vec3& p = m.points[ip];
            const Vec3& q = m.points[iq];
            const Vec3 v[4] = {F, q, p, C};
            if (aabbMiss<4>(c, r, v))
            {
                continue;
            }
            const double s = (q - F).cross(p - F).dot(C - F);
            if (s > 0.0)
            {
                vol += overlap::overlap_volume(sp, overlap::Tetrahedron(ov(F), ov(q), ov(p), ov(C)));
            }
            else if (s < 0.0)
            {
                vol -= overlap::overlap_volume(sp, overlap::Tetrahedron(ov(F), ov(p), ov(q), ov(C)));
            }
        }
    }
    return std::max(vol, 0.0);
}

Vec3 sphereCellFirstMoment(const CellMesh& mesh, label cell, const Vec3& c, double r)
{
    const MeshView& m = mesh.view();
    const double r2 = r * r;
    Vec3 M = Vec3::Zero();
    Vec3 tri[3];
    for (label i = mesh.cellFacesBegin(cell); i < mesh.cellFacesEnd(cell); ++i)
    {
        const label f = mesh.cellFace(i);
        const double sign = mesh.cellFaceSign(i);
        const label b = m.faceOffsets[f];
        const label n = m.faceOffsets[f + 1] - b;
        const Vec3& nf = mesh.faceNormal(f);
        const Vec3& F = mesh.faceCentre(f);
        // quick reject: face plane farther than r
        if (mesh.facePlanar(f))
        {
            const double delta = nf.dot(F - c);
            if (delta * delta >= r2)
            {
                continue;
            }
            ScratchArray<Vec3> pts(n);
            for (label k = 0; k < n; ++k)
            {
                pts[k] = m.points[m.faceVertices[b + k]];
            }
            addFaceMoment(M, c, r2, Vec3(sign * nf), nf, mesh.faceTangent(f), F, pts.data(), int(n));
        }
        else
        {
            for (label k = 0; k < n; ++k)
            {
                tri[0] = F;
                tri[1] = m.points[m.faceVertices[b + k]];
                tri[2] = m.points[m.faceVertices[b + (k + 1) % n]];
                Vec3 nt = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
                const double len = nt.norm();
                if (!(len > 0.0))
                {
                    continue;
                }
                nt /= len;
                const double delta = nt.dot(F - c);
                if (delta * delta >= r2)
                {
                    continue;
                }
                const Vec3 e1 = (tri[1] - tri[0]).normalized();
                addFaceMoment(M, c, r2, Vec3(sign * nt), nt, e1, F, tri, 3);
            }
        }
    }
    return M;
}

SphereOverlap3D sphereCellOverlap(const CellMesh& mesh, label cell, const Vec3& c, double r,
                                  bool withCentroid, bool closedFormBoxes, SphereCornerCache* cache)
{
    if (closedFormBoxes && mesh.isBox(cell))
    {
        return sphereBoxCell(mesh.boxMin(cell), mesh.boxMax(cell), c, r, withCentroid, cache);
    }
    SphereOverlap3D out;
    out.centroid = c;
    const double R = mesh.boundRadius(cell);
    const double d2 = (c - mesh.boundCentre(cell)).squaredNorm();
    if (d2 >= (r + R) * (r + R))
    {
        return out;
    }
    if (mesh.convex(cell))
    {
        const double d = mesh.outsideDistance(cell, c);
        if (d >= r)
        {
            return out; // sphere beyond one face plane: no overlap
        }
        if (-d >= r)
        {
            out.volume = sphereVolume(r); // sphere inside the cell
            return out;
        }
    }
    const MeshView& m = mesh.view();
    const CellShape shape = mesh.shape(cell);
    // cell inside the sphere
    if (d2 <= (r - R) * (r - R) && r > R)
    {
        out.volume = mesh.shapeVolume(cell);
        out.centroid = mesh.cellCentre(cell);
        return out;
    }
    double vol = 0.0;
    bool done = false;
    if (shape != CellShape::Polyhedron)
    {
        const label* sv = mesh.shapeVertices(cell);
        Vec3 v[8];
        const int nv = shape == CellShape::Tet ? 4 : (shape == CellShape::Prism ? 6 : 8);
        bool allInside = true;
        const double r2 = r * r;
        for (int k = 0; k < nv; ++k)
        {
            v[k] = m.points[sv[k]];
            allInside = allInside && (v[k] - c).squaredNorm() <= r2;
        }
        if (allInside)
        {
            out.volume = mesh.shapeVolume(cell);
            out.centroid = mesh.cellCentre(cell);
            return out;
        }
        try
        {
            switch (shape)
            {
            case CellShape::Tet:
                vol = sphereTetVolume(c, r, v);
                break;
            case CellShape::Prism:
                vol = spherePrismVolume(c, r, v);
                break;
            default:
                vol = sphereHexVolume(c, r, v);
                break;
            }
            done = true;
        }
        catch (const std::invalid_argument&)
        {
            done = false; // warped face at this scale: use the tet split
        }
    }
    if (!done)
    {
        vol = sphereCellVolumeByTets(mesh, cell, c, r);
    }
    out.volume = vol;
    if (withCentroid && vol > 0.0)
    {
        out.centroid = c + sphereCellFirstMoment(mesh, cell, c, r) / vol;
    }
    return out;
}

} // namespace overlapMapping
