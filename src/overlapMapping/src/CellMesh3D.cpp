// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file CellMesh3D.cpp
 * @brief CellMesh, 3D part: tet/prism/hex recognition for the `overlap`
 *        library (classify3D() and its stages), polyhedron volumes, box cells
 *        and convexity (prepare3D()).
 */
#include "overlapMapping/CellMesh.hpp"

#include "overlapMapping/SphereBox.hpp"

#include <overlap.hpp>

#include <algorithm>

namespace overlapMapping
{

namespace
{

/// Insertion sort of a tiny array (avoids a GCC -Warray-bounds false positive
/// of std::sort on fixed arrays).
inline void smallSort(label* a, int n)
{
    for (int i = 1; i < n; ++i)
    {
        const label v = a[i];
        int j = i - 1;
        while (j >= 0 && a[j] > v)
        {
            a[j + 1] = a[j];
            --j;
        }
        a[j + 1] = v;
    }
}

/// Position of vertex @p p among the first @p n entries of @p v, or -1.
inline int indexOf(const label* v, int n, label p)
{
    for (int k = 0; k < n; ++k)
    {
        if (v[k] == p)
        {
            return k;
        }
    }
    return -1;
}

/// Faces of the cell models as vertex slots in CellShape order (-1: triangle).
const int tetFaces[4][4] = {{1, 2, 3, -1}, {0, 3, 2, -1}, {0, 1, 3, -1}, {0, 2, 1, -1}};
const int prismFaces[5][4] = {{0, 2, 1, -1}, {3, 4, 5, -1}, {0, 3, 5, 2}, {1, 2, 5, 4}, {0, 1, 4, 3}};
const int hexFaces[6][4] = {{0, 4, 7, 3}, {1, 2, 6, 5}, {0, 1, 5, 4},
                            {3, 7, 6, 2}, {0, 3, 2, 1}, {4, 5, 6, 7}};

} // namespace

bool CellMesh::classify3D(label c)
{
    // shape from the face counts, then the vertices in model order, checked
    // against the model's faces, then the overlap library's element volume
    CellShape s;
    int nBase;
    if (!candidateShape(c, s, nBase))
    {
        return false;
    }
    label v[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
    orientedBase(c, nBase, v);
    const bool complete = s == CellShape::Tet ? findTetApex(c, v) : findTopVertices(c, nBase, v);
    double vol;
    if (!complete || !facesMatchModel(c, s, v) || !elementVolume(s, v, vol))
    {
        return false;
    }
    shape_[c] = s;
    std::copy(v, v + 8, shapeVerts_.begin() + 8 * c);
    shapeVolume_[c] = vol;
    return true;
}

bool CellMesh::candidateShape(label c, CellShape& s, int& nBase) const
{
    const label b = mesh_.cellOffsets[c];
    const label e = mesh_.cellOffsets[c + 1];
    const label nf = e - b;
    int nTri = 0, nQuad = 0;
    for (label i = b; i < e; ++i)
    {
        const label f = mesh_.cellFaces[i];
        const label n = mesh_.faceOffsets[f + 1] - mesh_.faceOffsets[f];
        nTri += (n == 3);
        nQuad += (n == 4);
        if (!facePlanar_[f])
        {
            return false;
        }
    }
    if (nf == 4 && nTri == 4)
    {
        s = CellShape::Tet;
        nBase = 3;
    }
    else if (nf == 5 && nTri == 2 && nQuad == 3)
    {
        s = CellShape::Prism;
        nBase = 3;
    }
    else if (nf == 6 && nQuad == 6)
    {
        s = CellShape::Hex;
        nBase = 4;
    }
    else
    {
        return false;
    }
    return true;
}

void CellMesh::orientedBase(label c, int nBase, label* v) const
{
    // base face: first face with nBase vertices, oriented into the cell
    const label b = mesh_.cellOffsets[c];
    const label e = mesh_.cellOffsets[c + 1];
    label base = -1, baseSlot = -1;
    for (label i = b; i < e && base < 0; ++i)
    {
        const label f = mesh_.cellFaces[i];
        if (mesh_.faceOffsets[f + 1] - mesh_.faceOffsets[f] == nBase)
        {
            base = f;
            baseSlot = i;
        }
    }
    for (int k = 0; k < nBase; ++k)
    {
        v[k] = mesh_.faceVertices[mesh_.faceOffsets[base] + k];
    }
    if (cellFaceSign_[baseSlot] > 0.0)
    {
        std::reverse(v, v + nBase); // owner: stored normal is outward
    }
}

bool CellMesh::findTetApex(label c, label* v) const
{
    for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1] && v[3] < 0; ++i)
    {
        const label f = mesh_.cellFaces[i];
        for (label j = mesh_.faceOffsets[f]; j < mesh_.faceOffsets[f + 1]; ++j)
        {
            if (indexOf(v, 3, mesh_.faceVertices[j]) < 0)
            {
                v[3] = mesh_.faceVertices[j];
                break;
            }
        }
    }
    return v[3] >= 0;
}

bool CellMesh::findTopVertices(label c, int nBase, label* v) const
{
    // every edge from base vertex k to a non-base vertex q gives v[nBase + k] = q
    for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1]; ++i)
    {
        const label f = mesh_.cellFaces[i];
        const label fb = mesh_.faceOffsets[f];
        const label n = mesh_.faceOffsets[f + 1] - fb;
        for (label j = 0; j < n; ++j)
        {
            const label p = mesh_.faceVertices[fb + j];
            const label q = mesh_.faceVertices[fb + (j + 1) % n];
            const int kp = indexOf(v, nBase, p), kq = indexOf(v, nBase, q);
            if (kp >= 0 && kq < 0)
            {
                if (v[nBase + kp] >= 0 && v[nBase + kp] != q)
                {
                    return false;
                }
                v[nBase + kp] = q;
            }
            else if (kq >= 0 && kp < 0)
            {
                if (v[nBase + kq] >= 0 && v[nBase + kq] != p)
                {
                    return false;
                }
                v[nBase + kq] = p;
            }
        }
    }
    for (int k = 0; k < 2 * nBase; ++k)
    {
        if (v[k] < 0)
        {
            return false;
        }
    }
    return true;
}

bool CellMesh::facesMatchModel(label c, CellShape s, const label* v) const
{
    // every cell face must be a face of the model (compared as sorted vertex sets)
    const int(*model)[4] = s == CellShape::Tet ? tetFaces : (s == CellShape::Prism ? prismFaces : hexFaces);
    const label b = mesh_.cellOffsets[c];
    const label e = mesh_.cellOffsets[c + 1];
    const label nf = e - b;
    for (label i = b; i < e; ++i)
    {
        const label f = mesh_.cellFaces[i];
        const label fb = mesh_.faceOffsets[f];
        const label n = mesh_.faceOffsets[f + 1] - fb;
        if (n > 4)
        {
            return false;
        }
        label fv[4];
        for (label j = 0; j < n; ++j)
        {
            fv[j] = mesh_.faceVertices[fb + j];
        }
        smallSort(fv, int(n));
        bool found = false;
        for (label m = 0; m < nf && !found; ++m)
        {
            const int mn = model[m][3] < 0 ? 3 : 4;
            if (mn != n)
            {
                continue;
            }
            label mv[4];
            for (int j = 0; j < mn; ++j)
            {
                mv[j] = v[model[m][j]];
            }
            smallSort(mv, mn);
            found = std::equal(fv, fv + n, mv);
        }
        if (!found)
        {
            return false;
        }
    }
    return true;
}

bool CellMesh::elementVolume(CellShape s, const label* v, double& vol) const
{
    // element volume as computed by the overlap library
    auto P = [&](int k)
    {
        const Vec3& p = mesh_.points[v[k]];
        return overlap::Vector(p[0], p[1], p[2]);
    };
    if (s == CellShape::Tet)
    {
        if ((P(1) - P(0)).cross(P(2) - P(0)).dot(P(3) - P(0)) <= 0.0)
        {
            return false;
        }
        vol = overlap::Tetrahedron(P(0), P(1), P(2), P(3)).volume;
    }
    else if (s == CellShape::Prism)
    {
        vol = overlap::Wedge(P(0), P(1), P(2), P(3), P(4), P(5)).volume;
    }
    else
    {
        vol = overlap::Hexahedron(P(0), P(1), P(2), P(3), P(4), P(5), P(6), P(7)).volume;
    }
    return vol > 0.0;
}

void CellMesh::prepare3D()
{
    shape_.assign(nCells_, CellShape::Polyhedron);
    shapeVerts_.assign(8 * size_t(nCells_), -1);
    shapeVolume_.assign(nCells_, 0.0);
    convex_.assign(nCells_, 1);
    boxIndex_.assign(nCells_, -1);
    for (label c = 0; c < nCells_; ++c)
    {
        if (!classify3D(c))
        {
            shape_[c] = CellShape::Polyhedron;
            shapeVolume_[c] = decompositionVolume(c);
        }
        Vec3 lo, hi;
        if (axisAlignedBoxCell(mesh_, c, lo, hi))
        {
            boxIndex_[c] = label(boxLo_.size());
            boxLo_.push_back(lo);
            boxHi_.push_back(hi);
            shapeVolume_[c] = (hi - lo).prod();
        }
        convex_[c] = convex3D(c) ? 1 : 0;
    }
}

template <class Fn>
void CellMesh::forEachFaceTriangle(label c, Fn&& fn) const
{
    for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1]; ++i)
    {
        const label f = mesh_.cellFaces[i];
        const label fb = mesh_.faceOffsets[f];
        const label n = mesh_.faceOffsets[f + 1] - fb;
        for (label k = 0; k < n; ++k)
        {
            fn(faceCentre_[f], mesh_.points[mesh_.faceVertices[fb + k]],
               mesh_.points[mesh_.faceVertices[fb + (k + 1) % n]], cellFaceSign_[i]);
        }
    }
}

double CellMesh::decompositionVolume(label c) const
{
    // volume of the tet decomposition (cell centre, face centre, edge)
    const Vec3& C = mesh_.cellCentres[c];
    double vol = 0.0;
    forEachFaceTriangle(c, [&](const Vec3& F, const Vec3& p, const Vec3& q, double sign)
                        { vol += sign * (p - F).cross(q - F).dot(F - C) / 6.0; });
    return vol;
}

bool CellMesh::containsByTets(label c, const Vec3& x) const
{
    // signed volume x 6 of the tet (a, b, d, e)
    auto vol6 = [](const Vec3& a, const Vec3& b, const Vec3& d, const Vec3& e)
    { return (b - a).cross(d - a).dot(e - a); };
    const Vec3& C = mesh_.cellCentres[c];
    const double r = boundRadius_[c];
    bool inside = false;
    forEachFaceTriangle(c,
                        [&](const Vec3& F, const Vec3& p, const Vec3& q, double)
                        {
                            const double v = vol6(C, F, p, q);
                            if (inside || std::abs(v) <= 1e-14 * r * r * r)
                            {
                                return; // found, or degenerate (a face centre on an edge)
                            }
                            // barycentric coordinates of x: each vertex replaced by x
                            const double s = v > 0 ? 1.0 : -1.0, tolV = -1e-9 * std::abs(v);
                            inside = s * vol6(x, F, p, q) >= tolV && s * vol6(C, x, p, q) >= tolV
                                     && s * vol6(C, F, x, q) >= tolV && s * vol6(C, F, p, x) >= tolV;
                        });
    return inside;
}

bool CellMesh::convex3D(label c) const
{
    // all cell vertices behind all (planar) face planes
    const double tolC = 1e-10 * boundRadius_[c];
    for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1]; ++i)
    {
        const label f = mesh_.cellFaces[i];
        if (!facePlanar_[f])
        {
            return false;
        }
        const Vec3 N = cellFaceSign_[i] * faceNormal_[f];
        for (label j = mesh_.cellOffsets[c]; j < mesh_.cellOffsets[c + 1]; ++j)
        {
            const label g = mesh_.cellFaces[j];
            for (label k = mesh_.faceOffsets[g]; k < mesh_.faceOffsets[g + 1]; ++k)
            {
                if (N.dot(mesh_.points[mesh_.faceVertices[k]] - faceCentre_[f]) > tolC)
                {
                    return false;
                }
            }
        }
    }
    return true;
}

} // namespace overlapMapping
