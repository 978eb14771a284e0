// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file MeshView.cpp
 */
#include "overlapMapping/MeshView.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace overlapMapping
{

label MeshView::nCells() const
{
    if (!cellOffsets.empty())
    {
        return label(cellOffsets.size()) - 1;
    }
    label n = 0;
    for (label o : owner)
    {
        n = std::max(n, o + 1);
    }
    for (label o : neighbour)
    {
        n = std::max(n, o + 1);
    }
    return n;
}

label MeshView::addFace(const std::vector<label>& verts, label own, label nei)
{
    if (faceOffsets.empty())
    {
        faceOffsets.push_back(0);
    }
    faceVertices.insert(faceVertices.end(), verts.begin(), verts.end());
    faceOffsets.push_back(label(faceVertices.size()));
    owner.push_back(own);
    neighbour.push_back(nei);
    return label(owner.size()) - 1;
}

void MeshView::buildCells()
{
    if (!cellOffsets.empty())
    {
        return;
    }
    const label nF = nFaces();
    if (label(owner.size()) != nF || label(neighbour.size()) != nF)
    {
        throw std::invalid_argument("overlapMapping::MeshView: owner/neighbour must have one entry per "
                                    "face ("
                                    + std::to_string(nF) + "), got " + std::to_string(owner.size()) + "/"
                                    + std::to_string(neighbour.size()));
    }
    const label nC = nCells();
    std::vector<label> count(nC + 1, 0);
    for (label f = 0; f < nF; ++f)
    {
        if (owner[f] < 0)
        {
            throw std::invalid_argument("overlapMapping::MeshView: face " + std::to_string(f)
                                        + " has no owner");
        }
        ++count[owner[f] + 1];
        if (neighbour[f] >= 0)
        {
            ++count[neighbour[f] + 1];
        }
    }
    for (label c = 0; c < nC; ++c)
    {
        count[c + 1] += count[c];
    }
    cellOffsets = count;
    cellFaces.assign(count[nC], -1);
    std::vector<label> fill(count.begin(), count.end() - 1);
    for (label f = 0; f < nF; ++f)
    {
        cellFaces[fill[owner[f]]++] = f;
        if (neighbour[f] >= 0)
        {
            cellFaces[fill[neighbour[f]]++] = f;
        }
    }
}

void faceCentreAndArea(const MeshView& mesh, label f, Vec3& centre, Vec3& areaVector)
{
    const label b = mesh.faceOffsets[f];
    const label e = mesh.faceOffsets[f + 1];
    const label n = e - b;
    const Vec3* P = mesh.points.data();
    const label* fv = mesh.faceVertices.data() + b;
    if (n == 3)
    {
        centre = (P[fv[0]] + P[fv[1]] + P[fv[2]]) / 3.0;
        areaVector = 0.5 * (P[fv[1]] - P[fv[0]]).cross(P[fv[2]] - P[fv[0]]);
        return;
    }
    Vec3 avg = Vec3::Zero();
    for (label i = 0; i < n; ++i)
    {
        avg += P[fv[i]];
    }
    avg /= double(n);
    Vec3 sumN = Vec3::Zero();
    double sumA = 0.0;
    Vec3 sumAc = Vec3::Zero();
    for (label i = 0; i < n; ++i)
    {
        const Vec3& p = P[fv[i]];
        const Vec3& q = P[fv[(i + 1) % n]];
        const Vec3 c = p + q + avg;
        const Vec3 nn = (q - p).cross(avg - p);
        const double a = nn.norm();
        sumN += nn;
        sumA += a;
        sumAc += a * c;
    }
    centre = sumA > 1e-300 ? Vec3(sumAc / (3.0 * sumA)) : avg;
    areaVector = 0.5 * sumN;
}

void computeCellGeometry(MeshView& mesh)
{
    mesh.buildCells();
    const label nF = mesh.nFaces();
    const label nC = mesh.nCells();
    std::vector<Vec3> fc(nF), fa(nF);
    for (label f = 0; f < nF; ++f)
    {
        faceCentreAndArea(mesh, f, fc[f], fa[f]);
    }
    mesh.cellCentres.assign(nC, Vec3::Zero());
    mesh.cellVolumes.assign(nC, 0.0);
    for (label c = 0; c < nC; ++c)
    {
        const label b = mesh.cellOffsets[c];
        const label e = mesh.cellOffsets[c + 1];
        Vec3 est = Vec3::Zero();
        for (label i = b; i < e; ++i)
        {
            est += fc[mesh.cellFaces[i]];
        }
        est /= double(std::max<label>(e - b, 1));
        double vol = 0.0;
        Vec3 cen = Vec3::Zero();
        for (label i = b; i < e; ++i)
        {
            const label f = mesh.cellFaces[i];
            const double sign = (mesh.owner[f] == c) ? 1.0 : -1.0;
            const double pyr3 = sign * fa[f].dot(fc[f] - est); // 3 x volume
            const Vec3 pc = 0.75 * fc[f] + 0.25 * est;
            vol += pyr3;
            cen += pyr3 * pc;
        }
        mesh.cellCentres[c] = std::abs(vol) > 1e-300 ? Vec3(cen / vol) : est;
        mesh.cellVolumes[c] = vol / 3.0;
    }
}

} // namespace overlapMapping
