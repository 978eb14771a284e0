// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file CellMesh.cpp
 * @brief CellMesh: checks, faces, adjacency, 2D polygons, bins and point
 *        location (the 3D element shapes are in CellMesh3D.cpp).
 */
#include "overlapMapping/CellMesh.hpp"

#include "overlapMapping/Geometry2D.hpp"

#include <Eigen/Geometry> // unitOrthogonal()

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace overlapMapping
{

namespace
{

std::string str(label i) { return std::to_string(i); }

} // namespace

CellMesh::CellMesh(MeshView mesh) : mesh_(std::move(mesh))
{
    const label nF = mesh_.nFaces();
    const label nP = label(mesh_.points.size());
    if (nF <= 0)
    {
        throw std::invalid_argument("overlapMapping::CellMesh: mesh has no faces");
    }
    if (mesh_.faceOffsets.front() != 0 || label(mesh_.faceVertices.size()) != mesh_.faceOffsets.back())
    {
        throw std::invalid_argument("overlapMapping::CellMesh: faceOffsets inconsistent with faceVertices");
    }
    for (label f = 0; f < nF; ++f)
    {
        if (mesh_.faceOffsets[f + 1] - mesh_.faceOffsets[f] < 3)
        {
            throw std::invalid_argument("overlapMapping::CellMesh: face " + str(f)
                                        + " has fewer than 3 vertices");
        }
    }
    for (label v : mesh_.faceVertices)
    {
        if (v < 0 || v >= nP)
        {
            throw std::invalid_argument("overlapMapping::CellMesh: face vertex index " + str(v)
                                        + " out of range [0," + str(nP) + ")");
        }
    }
    mesh_.buildCells();
    nCells_ = mesh_.nCells();
    if (nCells_ <= 0)
    {
        throw std::invalid_argument("overlapMapping::CellMesh: mesh has no cells");
    }
    for (label f = 0; f < nF; ++f)
    {
        if (mesh_.owner[f] >= nCells_ || mesh_.neighbour[f] >= nCells_)
        {
            throw std::invalid_argument("overlapMapping::CellMesh: face " + str(f)
                                        + " refers to a cell out of range");
        }
    }
    if (mesh_.cellCentres.empty() || mesh_.cellVolumes.empty())
    {
        computeCellGeometry(mesh_);
    }
    if (label(mesh_.cellCentres.size()) != nCells_ || label(mesh_.cellVolumes.size()) != nCells_)
    {
        throw std::invalid_argument("overlapMapping::CellMesh: cellCentres/cellVolumes must have nCells = "
                                    + str(nCells_) + " entries");
    }
    for (label c = 0; c < nCells_; ++c)
    {
        if (!(mesh_.cellVolumes[c] > 0.0))
        {
            throw std::invalid_argument("overlapMapping::CellMesh: cell " + str(c)
                                        + " has a non-positive volume");
        }
    }
    // bounding box
    bbMin_ = Vec3::Constant(std::numeric_limits<double>::max());
    bbMax_ = Vec3::Constant(-std::numeric_limits<double>::max());
    for (const Vec3& p : mesh_.points)
    {
        bbMin_ = bbMin_.cwiseMin(p);
        bbMax_ = bbMax_.cwiseMax(p);
    }
    if (mesh_.twoD)
    {
        if (mesh_.z0 == mesh_.z1)
        {
            mesh_.z0 = bbMin_[2];
            mesh_.z1 = bbMax_[2];
        }
        depth_ = mesh_.z1 - mesh_.z0;
        if (!(depth_ > 0.0))
        {
            throw std::invalid_argument("overlapMapping::CellMesh: 2D mesh needs z1 > z0");
        }
    }
    prepareFaces();
    prepareAdjacency();
    if (mesh_.twoD)
    {
        prepare2D();
    }
    else
    {
        prepare3D();
    }
    prepareBins();
}

void CellMesh::prepareFaces()
{
    const label nF = mesh_.nFaces();
    faceCentre_.resize(nF);
    faceNormal_.resize(nF);
    faceTangent_.resize(nF);
    facePlanar_.assign(nF, 1);
    for (label f = 0; f < nF; ++f)
    {
        Vec3 S;
        faceCentreAndArea(mesh_, f, faceCentre_[f], S);
        const double a = S.norm();
        faceNormal_[f] = a > 0.0 ? Vec3(S / a) : Vec3(0, 0, 1);
        const label b = mesh_.faceOffsets[f];
        const label n = mesh_.faceOffsets[f + 1] - b;
        const Vec3& p0 = mesh_.points[mesh_.faceVertices[b]];
        const Vec3& p1 = mesh_.points[mesh_.faceVertices[b + 1]];
        Vec3 t = p1 - p0;
        t -= faceNormal_[f] * faceNormal_[f].dot(t);
        const double tl = t.norm();
        faceTangent_[f] = tl > 0.0 ? Vec3(t / tl) : Vec3(faceNormal_[f].unitOrthogonal());
        double warp = 0.0;
        for (label k = 0; k < n; ++k)
        {
            const Vec3& p = mesh_.points[mesh_.faceVertices[b + k]];
            warp = std::max(warp, std::abs(faceNormal_[f].dot(p - faceCentre_[f])));
        }
        facePlanar_[f] = (n == 3 || warp <= 1e-12 * std::sqrt(a)) ? 1 : 0;
    }
    cellFaceSign_.resize(mesh_.cellFaces.size());
    for (label c = 0; c < nCells_; ++c)
    {
        for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1]; ++i)
        {
            const label f = mesh_.cellFaces[i];
            if (mesh_.owner[f] == c)
            {
                cellFaceSign_[i] = 1.0;
            }
            else if (mesh_.neighbour[f] == c)
            {
                cellFaceSign_[i] = -1.0;
            }
            else
            {
                throw std::invalid_argument("overlapMapping::CellMesh: cell " + str(c) + " lists face "
                                            + str(f) + " which it neither owns nor neighbours");
            }
        }
    }
    // bounding spheres (3D: around the cell centre)
    boundCentre_.resize(nCells_);
    boundRadius_.assign(nCells_, 0.0);
    for (label c = 0; c < nCells_; ++c)
    {
        boundCentre_[c] = mesh_.cellCentres[c];
        double r2 = 0.0;
        for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1]; ++i)
        {
            const label f = mesh_.cellFaces[i];
            for (label k = mesh_.faceOffsets[f]; k < mesh_.faceOffsets[f + 1]; ++k)
            {
                r2 = std::max(r2, (mesh_.points[mesh_.faceVertices[k]] - boundCentre_[c]).squaredNorm());
            }
        }
        boundRadius_[c] = std::sqrt(r2) * (1.0 + 1e-12);
    }
}

void CellMesh::prepareAdjacency()
{
    adjOffsets_.assign(nCells_ + 1, 0);
    adjCells_.clear();
    adjCells_.reserve(mesh_.cellFaces.size());
    for (label c = 0; c < nCells_; ++c)
    {
        const label start = label(adjCells_.size());
        for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1]; ++i)
        {
            const label f = mesh_.cellFaces[i];
            const label o =
                mesh_.neighbour[f] < 0 ? -1 : (mesh_.owner[f] == c ? mesh_.neighbour[f] : mesh_.owner[f]);
            if (o >= 0 && std::find(adjCells_.begin() + start, adjCells_.end(), o) == adjCells_.end())
            {
                adjCells_.push_back(o);
            }
        }
        adjOffsets_[c + 1] = label(adjCells_.size());
    }
}

void CellMesh::prepare2D()
{
    const double ztol = 1e-6 * depth_;
    const double zmid = 0.5 * (mesh_.z0 + mesh_.z1);
    polyOffsets_.assign(nCells_ + 1, 0);
    polyVerts_.clear();
    edgeNormal_.clear();
    edgeOffset_.clear();
    edgeNeighbour_.clear();
    polyArea_.assign(nCells_, 0.0);
    polyCentroid_.assign(nCells_, Vec2::Zero());
    convex_.assign(nCells_, 1);
    std::vector<label> ids;
    for (label c = 0; c < nCells_; ++c)
    {
        label back = -1;
        for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1] && back < 0; ++i)
        {
            const label f = mesh_.cellFaces[i];
            bool onBack = true;
            for (label k = mesh_.faceOffsets[f]; k < mesh_.faceOffsets[f + 1]; ++k)
            {
                onBack = onBack && std::abs(mesh_.points[mesh_.faceVertices[k]][2] - mesh_.z0) <= ztol;
            }
            if (onBack)
            {
                back = f;
            }
        }
        if (back < 0)
        {
            throw std::invalid_argument("overlapMapping::CellMesh: 2D mesh cell " + str(c)
                                        + " has no face on the back plane z0 = " + std::to_string(mesh_.z0));
        }
        ids.assign(mesh_.faceVertices.begin() + mesh_.faceOffsets[back],
                   mesh_.faceVertices.begin() + mesh_.faceOffsets[back + 1]);
        const int n = int(ids.size());
        double a2 = 0.0;
        for (int k = 0; k < n; ++k)
        {
            const Vec3& p = mesh_.points[ids[k]];
            const Vec3& q = mesh_.points[ids[(k + 1) % n]];
            a2 += p[0] * q[1] - p[1] * q[0];
        }
        if (a2 < 0.0)
        {
            std::reverse(ids.begin(), ids.end());
        }
        const label off = label(polyVerts_.size());
        for (int k = 0; k < n; ++k)
        {
            const Vec3& p = mesh_.points[ids[k]];
            polyVerts_.emplace_back(p[0], p[1]);
        }
        polyOffsets_[c + 1] = label(polyVerts_.size());
        const Vec2* P = polyVerts_.data() + off;
        polyArea_[c] = polygonAreaCentroid(P, n, polyCentroid_[c]);
        for (int k = 0; k < n; ++k)
        {
            const Vec2 e = P[(k + 1) % n] - P[k];
            Vec2 nrm(e[1], -e[0]);
            const double l = nrm.norm();
            nrm = l > 0.0 ? Vec2(nrm / l) : Vec2(0, 0);
            edgeNormal_.push_back(nrm);
            edgeOffset_.push_back(nrm.dot(P[k]));
            const Vec2 e2 = P[(k + 2) % n] - P[(k + 1) % n];
            if (e[0] * e2[1] - e[1] * e2[0] < -1e-12 * e.norm() * e2.norm())
            {
                convex_[c] = 0;
            }
            // neighbour across this edge: the side face holding both points
            label nb = -1;
            const label ia = ids[k], ib = ids[(k + 1) % n];
            for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1]; ++i)
            {
                const label f = mesh_.cellFaces[i];
                if (f == back)
                {
                    continue;
                }
                bool hasA = false, hasB = false;
                for (label j = mesh_.faceOffsets[f]; j < mesh_.faceOffsets[f + 1]; ++j)
                {
                    hasA = hasA || mesh_.faceVertices[j] == ia;
                    hasB = hasB || mesh_.faceVertices[j] == ib;
                }
                if (hasA && hasB)
                {
                    nb = mesh_.neighbour[f] < 0 ? -1
                                                : (mesh_.owner[f] == c ? mesh_.neighbour[f] : mesh_.owner[f]);
                    break;
                }
            }
            edgeNeighbour_.push_back(nb);
        }
        // bounding circle about the polygon centroid
        double r2 = 0.0;
        for (int k = 0; k < n; ++k)
        {
            r2 = std::max(r2, (P[k] - polyCentroid_[c]).squaredNorm());
        }
        boundCentre_[c] = Vec3(polyCentroid_[c][0], polyCentroid_[c][1], zmid);
        boundRadius_[c] = std::sqrt(r2) * (1.0 + 1e-12);
    }
}

void CellMesh::prepareBins()
{
    const int dim = mesh_.twoD ? 2 : 3;
    Vec3 L = bbMax_ - bbMin_;
    double vol = 1.0;
    for (int d = 0; d < dim; ++d)
    {
        L[d] = std::max(L[d], 1e-300);
        vol *= L[d];
    }
    const double h = std::pow(vol / double(nCells_), 1.0 / dim);
    for (int d = 0; d < 3; ++d)
    {
        if (d < dim)
        {
            binDims_[d] = label(std::min<double>(std::max(1.0, std::ceil(L[d] / h)), 4096.0));
            binSize_[d] = L[d] / binDims_[d];
        }
        else
        {
            binDims_[d] = 1;
            binSize_[d] = std::max(L[d], 1e-300);
        }
    }
    const size_t nBins = size_t(binDims_[0]) * binDims_[1] * binDims_[2];
    std::vector<label> count(nBins + 1, 0);
    std::vector<std::array<label, 6>> range(nCells_);
    for (label c = 0; c < nCells_; ++c)
    {
        Vec3 lo = Vec3::Constant(std::numeric_limits<double>::max());
        Vec3 hi = -lo;
        for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1]; ++i)
        {
            const label f = mesh_.cellFaces[i];
            for (label k = mesh_.faceOffsets[f]; k < mesh_.faceOffsets[f + 1]; ++k)
            {
                lo = lo.cwiseMin(mesh_.points[mesh_.faceVertices[k]]);
                hi = hi.cwiseMax(mesh_.points[mesh_.faceVertices[k]]);
            }
        }
        for (int d = 0; d < 3; ++d)
        {
            const double eps = 1e-9 * boundRadius_[c];
            range[c][d] = std::clamp(label(std::floor((lo[d] - eps - bbMin_[d]) / binSize_[d])), label(0),
                                     binDims_[d] - 1);
            range[c][3 + d] = std::clamp(label(std::floor((hi[d] + eps - bbMin_[d]) / binSize_[d])), label(0),
                                         binDims_[d] - 1);
        }
        for (label k = range[c][2]; k <= range[c][5]; ++k)
            for (label j = range[c][1]; j <= range[c][4]; ++j)
                for (label i = range[c][0]; i <= range[c][3]; ++i)
                    ++count[1 + i + binDims_[0] * (j + size_t(binDims_[1]) * k)];
    }
    for (size_t b = 0; b < nBins; ++b)
    {
        count[b + 1] += count[b];
    }
    binOffsets_ = count;
    binCells_.assign(count[nBins], -1);
    std::vector<label> fill(count.begin(), count.end() - 1);
    for (label c = 0; c < nCells_; ++c)
    {
        for (label k = range[c][2]; k <= range[c][5]; ++k)
            for (label j = range[c][1]; j <= range[c][4]; ++j)
                for (label i = range[c][0]; i <= range[c][3]; ++i)
                    binCells_[fill[i + binDims_[0] * (j + size_t(binDims_[1]) * k)]++] = c;
    }
}

double CellMesh::outsideDistance(label c, const Vec3& x) const
{
    if (mesh_.twoD)
    {
        return outsideDistance2D(c, x[0], x[1]);
    }
    double worst = -std::numeric_limits<double>::max();
    for (label i = mesh_.cellOffsets[c]; i < mesh_.cellOffsets[c + 1]; ++i)
    {
        const label f = mesh_.cellFaces[i];
        worst = std::max(worst, cellFaceSign_[i] * faceNormal_[f].dot(x - faceCentre_[f]));
    }
    return worst;
}

bool CellMesh::contains(label c, const Vec3& x) const
{
    if (mesh_.twoD && !convex_[c])
    {
        // winding number test (xy)
        const Vec2* P = polygon(c);
        const int n = polygonSize(c);
        int wn = 0;
        for (int k = 0; k < n; ++k)
        {
            const Vec2& a = P[k];
            const Vec2& b = P[(k + 1) % n];
            const double cr = (b[0] - a[0]) * (x[1] - a[1]) - (x[0] - a[0]) * (b[1] - a[1]);
            if (a[1] <= x[1])
            {
                if (b[1] > x[1] && cr > 0)
                {
                    ++wn;
                }
            }
            else if (b[1] <= x[1] && cr < 0)
            {
                --wn;
            }
        }
        return wn != 0;
    }
    if (!mesh_.twoD && !convex_[c])
    {
        return containsByTets(c, x);
    }
    return outsideDistance(c, x) <= tol(c);
}

label CellMesh::walk(const Vec3& x, label start) const
{
    label cur = start, prev = -1;
    const int maxSteps = 256;
    for (int it = 0; it < maxSteps; ++it)
    {
        double worst = -std::numeric_limits<double>::max();
        label next = -1;
        if (mesh_.twoD)
        {
            for (label k = polyOffsets_[cur]; k < polyOffsets_[cur + 1]; ++k)
            {
                const double d = edgeNormal_[k][0] * x[0] + edgeNormal_[k][1] * x[1] - edgeOffset_[k];
                if (d > worst)
                {
                    worst = d;
                    next = edgeNeighbour_[k];
                }
            }
        }
        else
        {
            for (label i = mesh_.cellOffsets[cur]; i < mesh_.cellOffsets[cur + 1]; ++i)
            {
                const label f = mesh_.cellFaces[i];
                const double d = cellFaceSign_[i] * faceNormal_[f].dot(x - faceCentre_[f]);
                if (d > worst)
                {
                    worst = d;
                    next = mesh_.neighbour[f] < 0
                               ? -1
                               : (mesh_.owner[f] == cur ? mesh_.neighbour[f] : mesh_.owner[f]);
                }
            }
        }
        if (worst <= tol(cur))
        {
            return contains(cur, x) ? cur : -1;
        }
        if (next < 0 || next == prev)
        {
            return -1;
        }
        prev = cur;
        cur = next;
    }
    return -1;
}

label CellMesh::searchBins(const Vec3& x) const
{
    label idx[3];
    for (int d = 0; d < 3; ++d)
    {
        if (mesh_.twoD && d == 2)
        {
            idx[d] = 0;
            continue;
        }
        const double t = (x[d] - bbMin_[d]) / binSize_[d];
        if (t < -1e-6 || t > binDims_[d] + 1e-6)
        {
            return -1;
        }
        idx[d] = std::clamp(label(std::floor(t)), label(0), binDims_[d] - 1);
    }
    const size_t b = idx[0] + binDims_[0] * (idx[1] + size_t(binDims_[1]) * idx[2]);
    label best = -1;
    double bestD = std::numeric_limits<double>::max();
    for (label i = binOffsets_[b]; i < binOffsets_[b + 1]; ++i)
    {
        const label c = binCells_[i];
        if (contains(c, x))
        {
            return c;
        }
        const double d = outsideDistance(c, x) / boundRadius_[c];
        if (d < bestD)
        {
            bestD = d;
            best = c;
        }
    }
    return bestD <= 1e-6 ? best : -1;
}

label CellMesh::findCell(const Vec3& x, label hint) const
{
    if (hint >= 0 && hint < nCells_)
    {
        if (contains(hint, x))
        {
            return hint;
        }
        const label c = walk(x, hint);
        if (c >= 0)
        {
            return c;
        }
    }
    return searchBins(x);
}

} // namespace overlapMapping
