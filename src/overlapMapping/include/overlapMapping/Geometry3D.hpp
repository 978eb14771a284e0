// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file Geometry3D.hpp
 * @brief Sphere / cell overlap volume and centroid.
 *
 * Volumes come from the `overlap` library (Strobl, Formella, Poeschel 2016,
 * J. Comput. Phys. 311:158-172, MIT licence; ThirdParty/overlap/overlap.hpp),
 * exact for tetrahedra, wedges (prisms) and hexahedra with planar faces,
 * except for hexahedra with axis-aligned faces (boxes), which use the cheaper
 * closed form of SphereBox.hpp (volume and centroid).
 * General polyhedra (and tet/prism/hex cells with warped faces) are split into
 * tetrahedra (cell centre, face centre, edge) whose signed overlaps are summed.
 *
 * Centroids: the `overlap` library gives volumes (and surface areas) only. The
 * first moment of sphere ∩ cell is computed here EXACTLY for planar faces from
 * the divergence theorem: with s = x - c,
 *   ∫_{S∩K} s dV = ∫_{∂(S∩K)} (|s|^2/2) n dA
 *                = Σ_faces N_f ∫_{F ∩ D_f} (|s|^2 - r^2)/2 dA,
 * because |s| = r on the spherical part and the spherical part plus the clipped
 * faces form a closed surface (∮ n dA = 0). D_f is the disc cut by the face
 * plane from the sphere (radius rho, |s|^2 = delta^2 + |s_plane|^2), so each
 * face term is (polar - rho^2 area)/2 of face ∩ disc, computed in closed form
 * by the 2D edge/centre decomposition (Geometry2D.hpp). Warped faces are
 * triangulated about the face centre (the same decomposition as used for the
 * volume of such cells), which is then exact for that decomposition.
 */
#ifndef OVERLAPMAPPING_GEOMETRY3D_HPP
#define OVERLAPMAPPING_GEOMETRY3D_HPP

#include "overlapMapping/CellMesh.hpp"
#include "overlapMapping/SphereBox.hpp"

namespace overlapMapping
{

/// Volume and centroid of sphere ∩ cell.
struct SphereOverlap3D
{
    double volume = 0.0;          ///< overlap volume [m^3], >= 0
    Vec3 centroid = Vec3::Zero(); ///< overlap centroid [m] (sphere centre if
                                  ///< volume == 0 or not requested)
};

/// Volume of a sphere [m^3].
inline double sphereVolume(double r) { return 4.0 / 3.0 * pi * r * r * r; }

/**
 * @brief Overlap volume of a sphere with a tetrahedron (overlap library).
 * @param c centre [m], @param r radius [m], @param v vertices in any order
 *        (re-oriented internally).
 * @return overlap volume [m^3]
 */
double sphereTetVolume(const Vec3& c, double r, const Vec3 v[4]);

/**
 * @brief Overlap volume of a sphere with a prism (OpenFOAM/overlap vertex order,
 *        see CellShape). @throws std::invalid_argument for warped quad faces.
 */
double spherePrismVolume(const Vec3& c, double r, const Vec3 v[6]);

/**
 * @brief Overlap volume of a sphere with a hexahedron (OpenFOAM/overlap vertex
 *        order, see CellShape). @throws std::invalid_argument for warped faces.
 */
double sphereHexVolume(const Vec3& c, double r, const Vec3 v[8]);

/**
 * @brief First moment ∫_{S∩K} (x - c) dV [m^4] of sphere ∩ cell @p cell,
 *        exact for planar faces (see file comment).
 */
Vec3 sphereCellFirstMoment(const CellMesh& mesh, label cell, const Vec3& c, double r);

/**
 * @brief Overlap volume (and optionally centroid) of sphere (c, r) with 3D
 *        cell @p cell of @p mesh.
 *
 * Box cells (CellMesh::isBox: hexes with axis-aligned faces), unless
 * @p closedFormBoxes is false: exact sphere-box distance reject; sphere inside
 * the box (4/3 pi r^3, centroid c); box inside the sphere (box volume, box
 * centre); otherwise the closed form sphereBoxOverlap() (SphereBox.hpp).
 * Other cells: bounding-sphere reject; sphere inside a convex cell (volume
 * 4/3 pi r^3, centroid c); cell inside the sphere (shapeVolume, cell centre).
 * Otherwise the overlap library (tet/prism/hex) or the tetrahedral
 * decomposition (polyhedra, warped faces).
 * @param withCentroid compute the centroid (see file comment), else the
 *        returned centroid is c.
 * @param closedFormBoxes false sends box cells through the general path too
 *        (the `overlap` library hexahedron), for checks.
 * @param cache optional corner memo for the box cells of one sphere (see
 *        SphereCornerCache).
 */
SphereOverlap3D sphereCellOverlap(const CellMesh& mesh, label cell, const Vec3& c, double r,
                                  bool withCentroid, bool closedFormBoxes = true,
                                  SphereCornerCache* cache = nullptr);

/**
 * @brief Volume of sphere (c, r) ∩ cell by the tetrahedral decomposition
 *        (cell centre, face centre, edge), used for polyhedra; exact for any
 *        star-shaped cell (inverted tets are subtracted).
 */
double sphereCellVolumeByTets(const CellMesh& mesh, label cell, const Vec3& c, double r);

} // namespace overlapMapping

#endif
