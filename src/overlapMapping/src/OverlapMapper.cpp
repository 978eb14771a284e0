// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file OverlapMapper.cpp
 */
#include "overlapMapping/OverlapMapper.hpp"

#include "overlapMapping/Geometry2D.hpp"
#include "overlapMapping/Geometry3D.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace overlapMapping
{

double MappingSettings::diameterFactorForPacking(double phiTarget, double phiModel, bool twoD)
{
    if (!(phiTarget > 0.0) || !(phiModel > 0.0))
    {
        throw std::invalid_argument(
            "overlapMapping::diameterFactorForPacking: packing fractions must be > 0");
    }
    return std::pow(phiTarget / phiModel, twoD ? 0.5 : 1.0 / 3.0);
}

OverlapMapper::OverlapMapper(const CellMesh& mesh, MappingSettings settings) : mesh_(mesh)
{
    setSettings(settings);
    visited_.assign(mesh_.nCells(), 0u);
    phi_.assign(mesh_.nCells(), 0.0);
    grainOffsets_.assign(1, 0);
}

void OverlapMapper::setSettings(const MappingSettings& settings)
{
    if (!(settings.effectiveDiameterFactor > 0.0) || !std::isfinite(settings.effectiveDiameterFactor))
    {
        throw std::invalid_argument("overlapMapping::OverlapMapper: effectiveDiameterFactor must be > 0, got "
                                    + std::to_string(settings.effectiveDiameterFactor));
    }
    if (!(settings.epsMin >= 0.0) || settings.epsMin > 1.0)
    {
        throw std::invalid_argument("overlapMapping::OverlapMapper: epsMin must be in [0,1], got "
                                    + std::to_string(settings.epsMin));
    }
    settings_ = settings;
}

void OverlapMapper::map(const std::vector<Vec3>& centres, const std::vector<double>& radii)
{
    if (centres.size() != radii.size())
    {
        throw std::invalid_argument("overlapMapping::OverlapMapper::map: " + std::to_string(centres.size())
                                    + " centres but " + std::to_string(radii.size()) + " radii");
    }
    map(centres.data(), radii.data(), label(centres.size()));
}

inline void OverlapMapper::addEntry(label g, label cell, double vol, const Vec3& centroid)
{
    entryGrain_.push_back(g);
    entryCell_.push_back(cell);
    entryVolume_.push_back(vol);
    entryCentroid_.push_back(centroid);
}

void OverlapMapper::map(const Vec3* centres, const double* radii, label nGrains)
{
    if (nGrains < 0)
    {
        throw std::invalid_argument("overlapMapping::OverlapMapper::map: nGrains < 0");
    }
    if (nGrains != nGrains_ || label(grainCell_.size()) != nGrains)
    {
        grainCell_.assign(nGrains, -1); // new grain set: forget the hints
    }
    nGrains_ = nGrains;
    grainOffsets_.resize(nGrains + 1);
    grainOffsets_[0] = 0;
    grainVolume_.resize(nGrains);
    grainMapped_.resize(nGrains);
    entryGrain_.clear();
    entryCell_.clear();
    entryVolume_.clear();
    entryCentroid_.clear();
    cellsEvaluated_ = 0;

    const bool twoD = mesh_.twoD();
    const double depth = mesh_.depth();
    const double k = settings_.effectiveDiameterFactor;
    const bool pcm = settings_.method == MappingMethod::ParticleCentroid;

    for (label g = 0; g < nGrains; ++g)
    {
        const Vec3& c = centres[g];
        const double r = k * radii[g];
        if (!(r > 0.0) || !std::isfinite(r))
        {
            throw std::invalid_argument("overlapMapping::OverlapMapper::map: grain " + std::to_string(g)
                                        + " has invalid radius " + std::to_string(radii[g]));
        }
        if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || (!twoD && !std::isfinite(c[2])))
        {
            throw std::invalid_argument("overlapMapping::OverlapMapper::map: grain " + std::to_string(g)
                                        + " has a non-finite centre");
        }
        const double Vg = twoD ? pi * r * r * depth : sphereVolume(r);
        grainVolume_[g] = Vg;
        Vec3 cq = c;
        if (twoD)
        {
            cq[2] = 0.5 * (mesh_.z0() + mesh_.z1());
        }
        const label cell = mesh_.findCell(cq, grainCell_[g]);
        grainCell_[g] = cell;
        const std::size_t first = entryCell_.size();
        if (cell < 0)
        {
            if (settings_.outside == OutsideGrainPolicy::Throw)
            {
                std::ostringstream msg;
                msg.precision(10);
                msg << "overlapMapping::OverlapMapper::map: centre of grain " << g << " at (" << c[0] << ", "
                    << c[1] << ", " << c[2] << ") is outside the mesh (bounds ("
                    << mesh_.boundsMin().transpose() << ") - (" << mesh_.boundsMax().transpose() << "))";
                throw std::runtime_error(msg.str());
            }
        }
        else if (pcm)
        {
            addEntry(g, cell, Vg, cq);
        }
        else
        {
            mapExact(g, cq, r, cell);
        }
        double W = 0.0;
        for (std::size_t e = first; e < entryCell_.size(); ++e)
        {
            W += entryVolume_[e];
        }
        grainMapped_[g] = W;
        grainOffsets_[g + 1] = label(entryCell_.size());
    }

    // weights and solid fraction
    const std::size_t n = entryCell_.size();
    entryWeight_.resize(n);
    phi_.assign(mesh_.nCells(), 0.0);
    for (std::size_t e = 0; e < n; ++e)
    {
        const double W = grainMapped_[entryGrain_[e]];
        entryWeight_[e] = W > 0.0 ? entryVolume_[e] / W : 0.0;
        phi_[entryCell_[e]] += entryVolume_[e];
    }
    for (label c = 0; c < mesh_.nCells(); ++c)
    {
        phi_[c] /= mesh_.cellVolume(c);
    }
}

void OverlapMapper::mapExact(label g, const Vec3& c, double r, label cell)
{
    const bool twoD = mesh_.twoD();
    const bool withCentroid = settings_.computeCentroids;
    if (++stamp_ == 0)
    {
        std::fill(visited_.begin(), visited_.end(), 0u);
        stamp_ = 1;
    }
    // fast path: grain entirely inside its (convex) cell
    bool inside;
    if (!twoD && settings_.closedFormBoxes && mesh_.isBox(cell))
    {
        const Vec3 lo = c - mesh_.boxMin(cell), hi = mesh_.boxMax(cell) - c;
        inside = std::min(lo.minCoeff(), hi.minCoeff()) >= r;
    }
    else
    {
        inside = mesh_.convex(cell)
                 && -(twoD ? mesh_.outsideDistance2D(cell, c[0], c[1]) : mesh_.outsideDistance(cell, c)) >= r;
    }
    if (inside)
    {
        ++cellsEvaluated_;
        addEntry(g, cell, grainVolume_[g], c);
        return;
    }
    const double depth = mesh_.depth();
    const Vec2 c2(c[0], c[1]);
    queue_.clear();
    queue_.push_back(cell);
    visited_[cell] = stamp_;
    std::size_t head = 0;
    while (head < queue_.size())
    {
        const label k = queue_[head++];
        ++cellsEvaluated_;
        double vol;
        Vec3 centroid = c;
        if (twoD)
        {
            // exact reject: the disc lies beyond an edge line of a convex cell
            if (mesh_.convex(k) && mesh_.outsideDistance2D(k, c[0], c[1]) >= r)
            {
                continue;
            }
            const DiscPolygonMoments m = discPolygonMoments(c2, r, mesh_.polygon(k), mesh_.polygonSize(k));
            vol = m.area * depth;
            if (m.area > 0.0 && withCentroid)
            {
                centroid[0] += m.moment[0] / m.area;
                centroid[1] += m.moment[1] / m.area;
            }
        }
        else
        {
            const SphereOverlap3D o =
                sphereCellOverlap(mesh_, k, c, r, withCentroid, settings_.closedFormBoxes, &corners_);
            vol = o.volume;
            centroid = o.centroid;
        }
        if (!(vol > 0.0))
        {
            continue;
        }
        addEntry(g, k, vol, centroid);
        for (const label* nb = mesh_.neighboursBegin(k); nb != mesh_.neighboursEnd(k); ++nb)
        {
            const label j = *nb;
            if (visited_[j] == stamp_)
            {
                continue;
            }
            visited_[j] = stamp_;
            const Vec3& bc = mesh_.boundCentre(j);
            const double R = mesh_.boundRadius(j) + r;
            double d2 = (bc[0] - c[0]) * (bc[0] - c[0]) + (bc[1] - c[1]) * (bc[1] - c[1]);
            if (!twoD)
            {
                d2 += (bc[2] - c[2]) * (bc[2] - c[2]);
            }
            if (d2 < R * R)
            {
                queue_.push_back(j);
            }
        }
    }
}

void OverlapMapper::voidFraction(std::vector<double>& eps) const
{
    eps.resize(phi_.size());
    for (std::size_t c = 0; c < phi_.size(); ++c)
    {
        eps[c] = std::max(1.0 - phi_[c], settings_.epsMin);
    }
}

void OverlapMapper::solidVelocity(const Vec3* v, std::vector<Vec3>& phiV) const
{
    phiV.assign(mesh_.nCells(), Vec3::Zero());
    const std::size_t n = entryCell_.size();
    for (std::size_t e = 0; e < n; ++e)
    {
        phiV[entryCell_[e]] += entryVolume_[e] * v[entryGrain_[e]];
    }
    for (label c = 0; c < mesh_.nCells(); ++c)
    {
        phiV[c] /= mesh_.cellVolume(c);
    }
}

void OverlapMapper::gatherAtCentroids(const double* a, const Vec3* grad, std::vector<double>& out) const
{
    out.assign(nGrains_, 0.0);
    const std::size_t n = entryCell_.size();
    for (std::size_t e = 0; e < n; ++e)
    {
        const label c = entryCell_[e];
        Vec3 dx = entryCentroid_[e] - mesh_.cellCentre(c);
        if (mesh_.twoD())
        {
            dx[2] = 0.0;
        }
        out[entryGrain_[e]] += entryWeight_[e] * (a[c] + grad[c].dot(dx));
    }
}

void OverlapMapper::gatherAtCentroids(const Vec3* a, const Eigen::Matrix3d* grad,
                                      std::vector<Vec3>& out) const
{
    out.assign(nGrains_, Vec3::Zero());
    const std::size_t n = entryCell_.size();
    for (std::size_t e = 0; e < n; ++e)
    {
        const label c = entryCell_[e];
        Eigen::Vector3d dx = entryCentroid_[e] - mesh_.cellCentre(c);
        if (mesh_.twoD())
        {
            dx[2] = 0.0;
        }
        const Eigen::Vector3d val = a[c] + grad[c].transpose() * dx;
        out[entryGrain_[e]] += entryWeight_[e] * Vec3(val);
    }
}

} // namespace overlapMapping
