// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file MeshView.hpp
 * @brief Plain-array description of a finite-volume mesh (OpenFOAM polyMesh
 *        layout), filled by the OpenFOAM adapter or by MeshBuilders.hpp.
 */
#ifndef OVERLAPMAPPING_MESHVIEW_HPP
#define OVERLAPMAPPING_MESHVIEW_HPP

#include "overlapMapping/Types.hpp"

#include <vector>

namespace overlapMapping
{

/**
 * @brief Mesh given as plain arrays, in the layout of OpenFOAM's polyMesh.
 *
 * - points: nPoints x 3 coordinates [m].
 * - faces: CSR list (faceOffsets of size nFaces+1, faceVertices). The vertex
 *   order of face f gives, by the right-hand rule, a normal pointing OUT of
 *   owner[f] (into neighbour[f]) - OpenFOAM's convention.
 * - owner / neighbour: size nFaces; neighbour[f] = -1 for boundary faces
 *   (unlike OpenFOAM's neighbour(), which only lists internal faces: the
 *   adapter must pad it with -1).
 * - cells: optional CSR list of the faces of each cell (cellOffsets of size
 *   nCells+1, cellFaces). If left empty it is derived from owner/neighbour.
 * - cellCentres [m] and cellVolumes [m^3]: size nCells. If left empty they are
 *   computed with computeCellGeometry() (same algorithm as OpenFOAM's
 *   primitiveMesh::makeCellCentresAndVols, so values match OpenFOAM's).
 * - twoD, z0, z1: one-cell-thick 2D mesh (OpenFOAM "empty" front and back
 *   patches normal to z). Every cell is then a prism between z = z0 and
 *   z = z1; its 2D polygon is its face lying on the back plane z = z0. The
 *   depth is z1 - z0; grains are discs of volume pi r^2 (z1 - z0). If z0 == z1
 *   they are taken from the points' z range. Only z-normal 2D meshes are
 *   supported (not axisymmetric wedges).
 */
struct MeshView
{
    std::vector<Vec3> points;        ///< point coordinates [m]
    std::vector<label> faceOffsets;  ///< CSR offsets, size nFaces+1
    std::vector<label> faceVertices; ///< CSR point indices
    std::vector<label> owner;        ///< owner cell of each face
    std::vector<label> neighbour;    ///< neighbour cell, -1 on boundary
    std::vector<label> cellOffsets;  ///< optional CSR offsets, nCells+1
    std::vector<label> cellFaces;    ///< optional CSR face indices
    std::vector<Vec3> cellCentres;   ///< optional, cell centroids [m]
    std::vector<double> cellVolumes; ///< optional, cell volumes [m^3]
    bool twoD = false;               ///< one-cell-thick 2D mesh (z-normal)
    double z0 = 0.0;                 ///< back plane of a 2D mesh [m]
    double z1 = 0.0;                 ///< front plane of a 2D mesh [m]

    /// Number of faces (faceOffsets.size() - 1, or 0).
    label nFaces() const { return faceOffsets.empty() ? 0 : label(faceOffsets.size()) - 1; }

    /// Number of cells: cellOffsets.size()-1 if given, else 1 + max owner or
    /// neighbour index.
    label nCells() const;

    /// Append a face (vertex list oriented out of @p own) and return its index.
    label addFace(const std::vector<label>& verts, label own, label nei);

    /**
     * @brief Fill cellOffsets/cellFaces from owner/neighbour if empty.
     * @throws std::invalid_argument if owner/neighbour sizes are inconsistent.
     */
    void buildCells();
};

/**
 * @brief Compute cell centres and volumes exactly like OpenFOAM
 *        (primitiveMesh::makeFaceCentresAndAreas + makeCellCentresAndVols):
 *        faces are triangulated about their vertex average, cells decomposed
 *        into pyramids about the average of their face centres.
 * @param mesh mesh whose cellCentres/cellVolumes are overwritten (cells are
 *        built first if needed).
 * @throws std::invalid_argument on inconsistent connectivity.
 */
void computeCellGeometry(MeshView& mesh);

/**
 * @brief OpenFOAM-style face centre (area-weighted centroid) and area vector.
 * @param mesh mesh, @param f face index; @param[out] centre [m];
 * @param[out] areaVector |S| = area [m^2], direction = unit normal (out of owner).
 */
void faceCentreAndArea(const MeshView& mesh, label f, Vec3& centre, Vec3& areaVector);

} // namespace overlapMapping

#endif
