// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file OverlapMapper.hpp
 * @brief Grain -> cell mapping: sparse overlap list, solid/void fraction,
 *        solid flux, spread of grain quantities, gather of cell fields.
 *
 * Thesis section 3.2.1. With V_gc the overlap volume of grain g with cell c,
 * V_c the cell volume and W_g = Σ_c V_gc (= V_g for a grain inside the mesh):
 *  - solid fraction (mass-lumped L2 projection, eq. 3.43 with cell-wise
 *    constant test functions):     phi_c = Σ_g V_gc / V_c
 *  - void fraction:                eps_c = max(1 - phi_c, epsMin)
 *  - solid flux term (eq. 3.41):   (phi v)_c = Σ_g V_gc v_g / V_c
 *  - spread (eq. 3.42), extensive: F_c = Σ_g (V_gc / W_g) F_g
 *    so that Σ_c F_c = Σ_g F_g exactly (to round-off) - also for a grain
 *    partly outside the mesh (W_g < V_g), whose force is renormalised over
 *    the cells it does overlap: Newton's third law holds exactly.
 *  - gather (adjoint of spread):   a_g = Σ_c (V_gc / W_g) a_c
 *    Adjointness: Σ_g a_g F_g == Σ_c a_c F_c  (both = Σ_gc a_c w_gc F_g).
 *  - particle-centroid method (PCM, eq. 3.44-3.45): the whole grain volume
 *    goes to the cell holding its centre (V_gc = V_g for that cell).
 */
#ifndef OVERLAPMAPPING_OVERLAPMAPPER_HPP
#define OVERLAPMAPPING_OVERLAPMAPPER_HPP

#include "overlapMapping/CellMesh.hpp"
#include "overlapMapping/SphereBox.hpp"

#include <Eigen/Core>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace overlapMapping
{

/// Volume-mapping strategy.
enum class MappingMethod
{
    Exact,           ///< exact grain/cell overlaps (section 3.2.1)
    ParticleCentroid ///< PCM: all of V_g in the centre's cell (eq. 3.44-3.45)
};

/// What to do with a grain whose centre lies in no cell.
enum class OutsideGrainPolicy
{
    Throw, ///< throw std::runtime_error naming the grain and position
    Skip   ///< give it no entry (it contributes nothing, gathers zero)
};

/// Settings of an OverlapMapper.
struct MappingSettings
{
    /// Exact overlaps or PCM.
    MappingMethod method = MappingMethod::Exact;
    /// Lower bound of the void fraction (thesis section 3.2.2: 1e-8).
    double epsMin = 1e-8;
    /**
     * Fluid-side effective diameter factor k (thesis section 3.2.3): the
     * mapping uses radius k r (2D: volume factor k^2, 3D: k^3) while the grain
     * dynamics keep r. Use diameterFactorForPacking() to match a 2D disc
     * packing fraction to a 3D sphere one. Must be > 0. Default 1.
     */
    double effectiveDiameterFactor = 1.0;
    /// Compute the centroid of each overlap (needed by gatherAtCentroids()).
    bool computeCentroids = true;
    /// Grains whose centre is outside the mesh.
    OutsideGrainPolicy outside = OutsideGrainPolicy::Throw;
    /// 3D: closed-form sphere/box overlaps for hexes with axis-aligned faces
    /// (CellMesh::isBox, SphereBox.hpp). false uses the general `overlap`
    /// library path for every cell (same volumes to round-off; for checks).
    bool closedFormBoxes = true;

    /**
     * @brief Diameter factor k making a packing of fraction @p phiModel look
     *        like one of fraction @p phiTarget to the fluid: k = (phiTarget /
     *        phiModel)^(1/2) in 2D (area ~ d^2), ^(1/3) in 3D.
     *        Defaults: random close packing of spheres 0.64 vs discs 0.82
     *        (thesis section 3.2.3) -> k = 0.883.
     * @throws std::invalid_argument for non-positive fractions.
     */
    static double diameterFactorForPacking(double phiTarget = 0.64, double phiModel = 0.82, bool twoD = true);
};

/**
 * @brief Maps grains (discs on a 2D mesh, spheres on a 3D mesh) onto cells.
 *
 * Usage: construct once per mesh, then call map() every time grains move; the
 * query functions use the last map. All arrays are reused between maps: no
 * allocation in steady state (same or fewer grains, similar overlap count).
 *
 * Candidate search (cost ~ cells touched): the cell holding the grain centre
 * is found from the previous map's cell (walk across faces, then bin search),
 * then face neighbours are visited breadth-first while the overlap is
 * non-zero; a neighbour is rejected cheaply if its bounding sphere (2D:
 * circle) misses the grain. Assumes the grain ∩ domain is face-connected
 * (true unless a grain straddles a thin baffle or a re-entrant corner).
 *
 * Not thread-safe (holds scratch buffers); use one mapper per thread.
 */
class OverlapMapper
{
public:
    /**
     * @param mesh prepared mesh; must outlive the mapper.
     * @param settings see MappingSettings.
     * @throws std::invalid_argument for invalid settings.
     */
    explicit OverlapMapper(const CellMesh& mesh, MappingSettings settings = {});

    /// Change settings (next map() uses them). @throws std::invalid_argument.
    void setSettings(const MappingSettings& settings);
    /// Current settings.
    const MappingSettings& settings() const { return settings_; }
    /// The mesh.
    const CellMesh& mesh() const { return mesh_; }

    /**
     * @brief Compute overlaps of all grains and the solid fraction.
     * @param centres grain centres [m] (2D: z ignored)
     * @param radii   grain radii [m] (> 0; the effective factor is applied)
     * @param nGrains number of grains
     * @throws std::invalid_argument for a non-positive or non-finite radius or
     *         non-finite centre; std::runtime_error if a centre is outside the
     *         mesh and settings().outside == Throw (message names the grain).
     */
    void map(const Vec3* centres, const double* radii, label nGrains);
    /// Convenience overload; @throws std::invalid_argument on size mismatch.
    void map(const std::vector<Vec3>& centres, const std::vector<double>& radii);

    /// Number of grains of the last map.
    label nGrains() const { return nGrains_; }

    // ---- sparse overlap list (sorted by grain) -------------------------------
    /// Number of (grain, cell) entries.
    std::size_t nEntries() const { return entryCell_.size(); }
    /// Entries of grain g are [grainOffsets()[g], grainOffsets()[g+1]).
    const std::vector<label>& grainOffsets() const { return grainOffsets_; }
    /// Grain of each entry.
    const std::vector<label>& entryGrain() const { return entryGrain_; }
    /// Cell of each entry.
    const std::vector<label>& entryCell() const { return entryCell_; }
    /// Overlap volume V_gc of each entry [m^3] (2D: area x depth).
    const std::vector<double>& entryVolume() const { return entryVolume_; }
    /// Spread weight V_gc / W_g of each entry [-]; sums to 1 per mapped grain.
    const std::vector<double>& entryWeight() const { return entryWeight_; }
    /**
     * Centroid of each overlap [m] (2D: z = mid depth). Exact in 2D and for
     * planar-faced 3D cells (see Geometry3D.hpp); the grain centre for PCM;
     * the grain centre if settings().computeCentroids is false.
     */
    const std::vector<Vec3>& entryCentroid() const { return entryCentroid_; }

    // ---- per grain ----------------------------------------------------------
    /// (Effective) grain volume V_g [m^3] (2D: pi r^2 depth).
    const std::vector<double>& grainVolume() const { return grainVolume_; }
    /// Mapped volume W_g = Σ_c V_gc [m^3] (< V_g if partly outside the mesh).
    const std::vector<double>& grainMappedVolume() const { return grainMapped_; }
    /// Cell holding each grain centre (-1: skipped outside grain).
    const std::vector<label>& grainCell() const { return grainCell_; }
    /// Number of exact overlap evaluations in the last map (cost measure).
    std::size_t lastCellsEvaluated() const { return cellsEvaluated_; }

    // ---- cell fields ---------------------------------------------------------
    /// Solid fraction phi_c = Σ_g V_gc / V_c (eq. 3.43), size nCells.
    const std::vector<double>& solidFraction() const { return phi_; }
    /// Void fraction eps_c = max(1 - phi_c, epsMin). @param[out] eps resized.
    void voidFraction(std::vector<double>& eps) const;
    /**
     * @brief Solid flux term of the mixture continuity (eq. 3.41):
     *        (phi v)_c = Σ_g V_gc v_g / V_c [m/s].
     * @param v grain velocities (nGrains) [m/s]; @param[out] phiV resized.
     */
    void solidVelocity(const Vec3* v, std::vector<Vec3>& phiV) const;

    /**
     * @brief Spread an extensive per-grain quantity onto cells (eq. 3.42):
     *        out_c = Σ_g w_gc in_g, w_gc = V_gc / W_g; Σ_c out_c = Σ_g in_g.
     * @tparam T double or Vec3. @param in nGrains values (e.g. force [N],
     *        heat [W]); @param[out] out resized to nCells (totals per cell).
     */
    template <class T>
    void spread(const T* in, std::vector<T>& out) const;

    /**
     * @brief Like spread() divided by the cell volume: out_c = Σ_g w_gc in_g /
     *        V_c (e.g. force density [N/m^3] from forces [N]).
     */
    template <class T>
    void spreadDensity(const T* in, std::vector<T>& out) const;

    /**
     * @brief Gather a cell field onto grains (adjoint of spread):
     *        out_g = Σ_c w_gc in_c (overlap-weighted average; 0 for unmapped
     *        grains). @tparam T double or Vec3.
     */
    template <class T>
    void gather(const T* in, std::vector<T>& out) const;

    /**
     * @brief Gather a scalar cell field linearly reconstructed at the overlap
     *        centroids: out_g = Σ_c w_gc (a_c + grad_c . (x_gc - x_c)).
     * @param a cell values, @param grad cell gradients (nCells).
     */
    void gatherAtCentroids(const double* a, const Vec3* grad, std::vector<double>& out) const;
    /**
     * @brief Vector version; @p grad follows OpenFOAM's convention
     *        (grad U)_ij = d_i U_j, i.e. U(x) = U_c + (x - x_c) & grad U.
     */
    void gatherAtCentroids(const Vec3* a, const Eigen::Matrix3d* grad, std::vector<Vec3>& out) const;

private:
    void mapExact(label g, const Vec3& c, double r, label cell);
    void addEntry(label g, label cell, double vol, const Vec3& centroid);

    template <class T>
    static T zero()
    {
        if constexpr (std::is_arithmetic_v<T>)
        {
            return T(0);
        }
        else
        {
            return T::Zero();
        }
    }

    const CellMesh& mesh_;
    MappingSettings settings_;
    label nGrains_ = 0;

    std::vector<label> grainOffsets_;
    std::vector<label> entryGrain_, entryCell_;
    std::vector<double> entryVolume_, entryWeight_;
    std::vector<Vec3> entryCentroid_;
    std::vector<double> grainVolume_, grainMapped_;
    std::vector<label> grainCell_;
    std::vector<double> phi_;

    std::vector<std::uint32_t> visited_;
    std::uint32_t stamp_ = 0;
    std::vector<label> queue_;
    SphereCornerCache corners_; // 3D box cells: corner terms of one grain
    std::size_t cellsEvaluated_ = 0;
};

// ---- templates ------------------------------------------------------------

template <class T>
void OverlapMapper::spread(const T* in, std::vector<T>& out) const
{
    out.assign(mesh_.nCells(), zero<T>());
    const std::size_t n = entryCell_.size();
    for (std::size_t e = 0; e < n; ++e)
    {
        out[entryCell_[e]] += entryWeight_[e] * in[entryGrain_[e]];
    }
}

template <class T>
void OverlapMapper::spreadDensity(const T* in, std::vector<T>& out) const
{
    spread(in, out);
    for (label c = 0; c < mesh_.nCells(); ++c)
    {
        out[c] = out[c] / mesh_.cellVolume(c);
    }
}

template <class T>
void OverlapMapper::gather(const T* in, std::vector<T>& out) const
{
    out.assign(nGrains_, zero<T>());
    const std::size_t n = entryCell_.size();
    for (std::size_t e = 0; e < n; ++e)
    {
        out[entryGrain_[e]] += entryWeight_[e] * in[entryCell_[e]];
    }
}

} // namespace overlapMapping

#endif
