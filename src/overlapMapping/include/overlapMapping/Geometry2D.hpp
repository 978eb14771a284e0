// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file Geometry2D.hpp
 * @brief Exact disc / polygon intersection: area, first and polar moments.
 *
 * Implements the edge/centre triangle decomposition of thesis section 3.2.1
 * (figure 3.6): every polygon edge (a, b) forms with the disc centre c the
 * signed triangle (c, a, b). Its intersection with the disc is made of
 * straight triangles (c, p, q) for the parts of the edge inside the disc and of
 * circular sectors for the parts outside. Summing the signed contributions
 * over all edges gives the exact area, first moment and polar moment of
 * disc ∩ polygon in closed form (one sqrt per crossing edge, one atan2 per
 * sector), for any simple polygon (convex or not) of either orientation.
 *
 * Degenerate configurations are exact by construction: disc fully inside
 * (only sectors, summing to 2 pi), polygon fully inside (only triangles),
 * tangency (discriminant <= 0 -> pure sector), centre on a vertex or an edge
 * (zero-area triangles).
 */
#ifndef OVERLAPMAPPING_GEOMETRY2D_HPP
#define OVERLAPMAPPING_GEOMETRY2D_HPP

#include "overlapMapping/Types.hpp"

namespace overlapMapping
{

/**
 * @brief Integrals over disc ∩ polygon, relative to the disc centre.
 *
 * With s = x - c (c the disc centre):
 *  - area     = ∫ 1 dA            [m^2]
 *  - moment   = ∫ s dA            [m^3]   (centroid = c + moment / area)
 *  - polar    = ∫ |s|^2 dA        [m^4]   (only filled when requested)
 * For a clockwise polygon all three come out with a negative sign.
 */
struct DiscPolygonMoments
{
    double area = 0.0;
    Vec2 moment = Vec2::Zero();
    double polar = 0.0;
};

/**
 * @brief Exact moments of the intersection of a disc with a simple polygon.
 *
 * @param centre  disc centre c (2D coordinates) [m]
 * @param radius  disc radius r >= 0 [m]
 * @param poly    polygon vertices (n entries); counter-clockwise gives
 *                positive results, clockwise negative ones
 * @param n       number of vertices (n >= 3; fewer gives zero)
 * @param withPolar also compute the polar moment ∫|x-c|^2 dA (used for the
 *                3D centroid, see Geometry3D.hpp)
 * @return signed area, first moment and (optionally) polar moment, relative
 *         to @p centre. Closed form, no sampling (thesis section 3.2.1).
 * @note No exception is thrown; radius <= 0 gives zero.
 */
DiscPolygonMoments discPolygonMoments(const Vec2& centre, double radius, const Vec2* poly, int n,
                                      bool withPolar = false);

/// Result of discPolygonOverlap().
struct DiscOverlap2D
{
    double area = 0.0;            ///< area of disc ∩ polygon [m^2], >= 0
    Vec2 centroid = Vec2::Zero(); ///< centroid of disc ∩ polygon [m]; the
                                  ///< disc centre when area == 0
};

/**
 * @brief Area and centroid of disc ∩ polygon (thesis section 3.2.1, fig. 3.6).
 *
 * Same as discPolygonMoments() but orientation-independent (|area|) and with
 * the centroid instead of the moment.
 * @param centre disc centre [m]; @param radius disc radius [m];
 * @param poly polygon vertices (either orientation), @param n vertex count.
 */
DiscOverlap2D discPolygonOverlap(const Vec2& centre, double radius, const Vec2* poly, int n);

/**
 * @brief Signed area and centroid of a simple polygon (shoelace formula).
 * @param poly vertices, @param n count; @param[out] centroid centroid [m]
 * @return signed area [m^2] (positive for counter-clockwise)
 */
double polygonAreaCentroid(const Vec2* poly, int n, Vec2& centroid);

} // namespace overlapMapping

#endif
