// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file MeshBuilders.hpp
 * @brief Small structured meshes in OpenFOAM layout (tests, benchmarks,
 *        examples): hex, tet (5 or 6 per hex), prism and 2D grids.
 */
#ifndef OVERLAPMAPPING_MESHBUILDERS_HPP
#define OVERLAPMAPPING_MESHBUILDERS_HPP

#include "overlapMapping/CellMesh.hpp"

#include <functional>
#include <vector>

namespace overlapMapping
{

/// Optional point transformation applied to grid points (e.g. perturbation).
using PointMap = std::function<Vec3(const Vec3&)>;

/**
 * @brief OpenFOAM cellModel faces (outward) of a tet/prism/hex given its
 *        vertex labels in CellShape order.
 * @throws std::invalid_argument for CellShape::Polyhedron.
 */
std::vector<std::vector<label>> cellModelFaces(CellShape shape, const std::vector<label>& verts);

/**
 * @brief Assemble a mesh from cells given as lists of outward-oriented faces.
 *
 * Faces with the same vertex set are merged (owner = lower cell index, face
 * stored with the owner's orientation), others become boundary faces.
 * Cell centres and volumes are computed (computeCellGeometry()).
 * @throws std::invalid_argument if a face is shared by more than two cells.
 */
MeshView meshFromCellFaces(const std::vector<Vec3>& points,
                           const std::vector<std::vector<std::vector<label>>>& cells);

/// Structured hex mesh on the tensor grid xs x ys x zs (coordinates [m]).
MeshView hexGridMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                     const std::vector<double>& zs, const PointMap& map = nullptr);

/**
 * @brief Tet mesh: every hex of the grid split into 6 tets (Freudenthal, about
 *        diagonal 0-6) or 5 tets (alternating pattern so faces conform).
 * @throws std::invalid_argument if tetsPerHex is not 5 or 6.
 */
MeshView tetGridMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                     const std::vector<double>& zs, int tetsPerHex = 6, const PointMap& map = nullptr);

/// Prism mesh: every hex split into 2 prisms along the bottom diagonal 0-2.
MeshView prismGridMesh(const std::vector<double>& xs, const std::vector<double>& ys,
                       const std::vector<double>& zs, const PointMap& map = nullptr);

/**
 * @brief One-cell-thick 2D mesh (twoD = true, z in [z0, z1]) of quads, or of
 *        triangles (each quad split along a diagonal) if @p triangles.
 *        @p map may move points in x and y only.
 */
MeshView grid2DMesh(const std::vector<double>& xs, const std::vector<double>& ys, double z0, double z1,
                    bool triangles = false, const PointMap& map = nullptr);

/**
 * @brief n+1 coordinates from a to b with geometric grading: the last
 *        interval is @p ratio times the first (ratio = 1: uniform).
 */
std::vector<double> gradedSpacing(double a, double b, int n, double ratio = 1.0);

} // namespace overlapMapping

#endif
