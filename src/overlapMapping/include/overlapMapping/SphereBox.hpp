// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file SphereBox.hpp
 * @brief Exact, closed-form volume and first moment of sphere ∩ axis-aligned
 *        box, and the detection of hexahedral cells that are such boxes.
 *
 * Why: on hex meshes whose faces are axis-aligned (blockMesh boxes,
 * snappyHexMesh interiors) these formulas replace the general sphere /
 * hexahedron routine of the `overlap` library (Strobl et al. 2016), which
 * clips the sphere against arbitrary planar faces, at a fraction of its cost.
 *
 * Derivation (done for this library from textbook results: inclusion-
 * exclusion; the divergence theorem; the Gauss-Bonnet theorem for a region of
 * the unit sphere bounded by small-circle arcs, M. P. do Carmo, Differential
 * Geometry of Curves and Surfaces, 1976, section 4-5, with the geodesic
 * curvature cot(theta) of a circle of angular radius theta).
 * Put the sphere centre at the origin, radius r.
 *
 * 1. Reduction to corner regions. For a box [x0,x1] x [y0,y1] x [z0,z1]
 *    (relative to the centre), split each axis interval at 0 and mirror its
 *    negative part onto the positive half-axis (the ball is symmetric). On a
 *    half-axis, the indicator of [l, u] (0 <= l <= u) is H(x - l) - H(x - u),
 *    so per axis the box is a signed sum of half-lines {x > t}, t >= 0:
 *      x0 >= 0:      {x0: +1, x1: -1}
 *      x1 <= 0:      {-x1: +1, -x0: -1}
 *      x0 < 0 < x1:  {0: +2, x1: -1, -x0: -1}
 *    and the box volume is the inclusion-exclusion sum over the product of
 *    the three lists (up to 27 terms; terms with t >= r vanish, and so does
 *    every term whose corner lies outside the ball) of the corner volume
 *      W(a,b,c) = |{ |p| < r, x > a, y > b, z > c }|,  a,b,c >= 0.
 *    For the first moment along x, the mirrored terms change sign (the
 *    coefficients become {-x1: -1, -x0: +1} and {0: 0, x1: -1, -x0: +1}).
 *
 * 2. Corner volume by the divergence theorem, ∫_K dV = (1/3) ∮ p·n dA. On
 *    the sphere p·n = r, on the face x = a p·n = -a (outward normal -x):
 *      3 W = r^3 Ω - a A_a - b A_b - c A_c,
 *    with A_a the area of the plane face x = a of the region (a disc of radius
 *    rho_a = sqrt(r^2 - a^2) cut by y > b, z > c) and Ω the solid angle of the
 *    spherical part. If a^2 + b^2 + c^2 >= r^2 the region is empty (every
 *    point has |p|^2 >= a^2 + b^2 + c^2); otherwise the spherical part is a
 *    triangle bounded by the three small circles x = a, y = b, z = c, with
 *    vertices at e.g. (a, b, s_ab), s_ab = sqrt(r^2 - a^2 - b^2).
 *
 * 3. Face area (2D, same theorem with p/2): for the disc corner
 *    {y > b, z > c, y^2 + z^2 < rho^2}, whose arc runs from (u, c) to (b, w)
 *    with u = sqrt(rho^2 - c^2), w = sqrt(rho^2 - b^2) and subtends the angle
 *      phi = atan2(u w - b c, u b + c w),
 *    A = rho^2 phi / 2 - (b w + c u) / 2 + b c.
 *
 * 4. Solid angle by the Gauss-Bonnet theorem on the unit sphere,
 *    Ω = 2π - Σ(exterior angles) - ∮ k_g ds. The circle x = a has geodesic
 *    curvature (a/r)/sqrt(1 - a^2/r^2) towards the region and radius
 *    sqrt(1 - a^2/r^2), so its arc contributes (a/r) phi_a. At the vertex on
 *    x = a and y = b the inward normals of the two arcs in the tangent plane
 *    are the projections of x and y, whose angle is the exterior angle,
 *    π/2 + theta_ab with theta_ab = atan2(a b, r s_ab). Hence
 *      Ω = π/2 - theta_ab - theta_ac - theta_bc - (a phi_a + b phi_b + c phi_c)/r.
 *    Checks: a = b = c = 0 gives Ω = π/2 (an octant); b = c = 0 gives a
 *    quarter of the cap volume π (r - a)^2 (2r + a) / 3. As Ω >= 0, the sum
 *    of the three theta is in [0, π/2]: one atan2 of the product of the
 *    complex numbers r s_ab + i a b, ... gives it.
 *
 * 5. First moment of the corner: ∫_K p dV = ∮ (|p|^2/2) n dA = Σ_faces N_f
 *    ∫ (|p|^2 - r^2)/2 dA (∮ n dA = 0 and |p| = r on the sphere); only the
 *    face x = a has an x normal, so ∫_K x dV = (1/2) ∫_{face a}(rho_a^2 -
 *    y^2 - z^2) dA, and for the disc corner of step 3 (2D divergence theorem
 *    with the field q (rho^2/2 - |q|^2/4)):
 *      ∫ (rho^2 - |q|^2) dA = rho^4 phi / 4
 *          - b [ (rho^2/2 - b^2/4)(w - c) - (w^3 - c^3)/12 ]
 *          - c [ (rho^2/2 - c^2/4)(u - b) - (u^3 - b^3)/12 ].
 *
 * The same moment identity is the one used for general cells in
 * Geometry3D.hpp. The closed forms are checked against the `overlap` library,
 * sphere caps, half/quarter/eighth balls and the partition of the ball over a
 * mesh in tests/testSphereBox.cpp.
 *
 * Accuracy: the inclusion-exclusion sums terms of size up to r^3; the
 * round-off is ~1e-15 r^3 absolute (1e-12 relative to the ball in the tests).
 */
#ifndef OVERLAPMAPPING_SPHEREBOX_HPP
#define OVERLAPMAPPING_SPHEREBOX_HPP

#include "overlapMapping/Types.hpp"

#include <cstdint>
#include <limits>
#include <vector>

namespace overlapMapping
{
struct MeshView;
}

namespace overlapMapping
{

/// Volume and first moment of sphere ∩ box.
struct SphereBoxOverlap
{
    double volume = 0.0;        ///< overlap volume [m^3], >= 0
    Vec3 moment = Vec3::Zero(); ///< ∫ (x - c) dV over the overlap [m^4]
};

/**
 * @brief Memo of the corner terms of step 1 for one sphere.
 *
 * Neighbouring boxes share planes, so the boxes overlapping one sphere share
 * most corner terms (on a grid with h ~ d, 27 corner terms over the ~8 cells
 * a sphere touches, 8 of them distinct). Pass the same cache to
 * sphereBoxOverlap() for the boxes of one sphere: it keys the terms by their
 * exact plane offsets and resets itself when the sphere (or withMoment)
 * changes. Not thread-safe; 150 kB on the heap, allocated once.
 */
class SphereCornerCache
{
public:
    SphereCornerCache();

private:
    friend SphereBoxOverlap sphereBoxOverlap(const Vec3&, double, const Vec3&, const Vec3&, bool,
                                             SphereCornerCache*);
    static constexpr int maxPlanes = 16; ///< distinct offsets per axis
    /// Slot of corner (a, b, c) in values_ (-1 if an axis is full); resets the
    /// cache if (centre, r, withMoment) changed.
    int slot(double a, double b, double c);
    void bind(const Vec3& centre, double r, bool withMoment);
    int planeIndex(int axis, double t);

    Vec3 centre_ = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    double r_ = 0.0;
    bool withMoment_ = false;
    std::uint32_t stamp_ = 1;
    double planes_[3][maxPlanes];
    int nPlanes_[3] = {0, 0, 0};
    std::vector<std::uint32_t> filled_; // maxPlanes^3 stamps
    std::vector<double> values_;        // maxPlanes^3 x (v, mx, my, mz)
};

/**
 * @brief Volume of the corner region {|p| < r, x > a, y > b, z > c} of a ball
 *        centred at the origin (step 2 of the file comment).
 * @param a,b,c offsets of the three planes [m], each >= 0 (not checked)
 * @param r radius [m], > 0
 * @return volume [m^3]; 0 if a^2 + b^2 + c^2 >= r^2.
 */
double sphereCornerVolume(double a, double b, double c, double r);

/**
 * @brief Exact overlap of sphere (@p c, @p r) with the axis-aligned box
 *        [@p lo, @p hi] (closed form, see the file comment).
 * @param lo,hi box corners [m], lo <= hi componentwise (an empty box gives 0)
 * @param withMoment also compute the first moment about @p c (else zero)
 * @param cache optional memo shared by the boxes of one sphere (same results
 *        to the last bit, fewer evaluations)
 * Raises nothing: r <= 0, an empty box or a non-finite input give 0.
 * @return volume [m^3] and first moment ∫ (x - c) dV [m^4]; the overlap
 *         centroid is c + moment / volume.
 */
SphereBoxOverlap sphereBoxOverlap(const Vec3& c, double r, const Vec3& lo, const Vec3& hi, bool withMoment,
                                  SphereCornerCache* cache = nullptr);

/// Volume only of sphereBoxOverlap() [m^3].
inline double sphereBoxVolume(const Vec3& c, double r, const Vec3& lo, const Vec3& hi)
{
    return sphereBoxOverlap(c, r, lo, hi, false).volume;
}

/**
 * @brief Whether cell @p cell of @p m is an axis-aligned box, and which.
 *
 * Every face must lie in one of the six planes of the bounding box of the
 * cell's vertices, all six planes must be used, and the cell volume (if the
 * view has them) must equal the box volume to 1e-9. "Lies in" means each
 * vertex within @p relTol x (largest box edge) of the plane. This accepts the
 * hexahedra of blockMesh-type grids and also cells of snappyHexMesh-type
 * refinement whose box faces are split (hanging vertices), which are boxes
 * too; anything else (sheared, rotated, warped cells) is rejected.
 * Each box bound is the smallest coordinate of the vertices on that side, so
 * two cells sharing a face get the same bound whatever their vertex order.
 * @param m mesh view with cells built (MeshView::buildCells)
 * @param lo,hi box corners [m] (written only if true is returned)
 * @param relTol tolerance relative to the cell size (default 1e-12, the same
 *        as the planarity test of CellMesh)
 */
bool axisAlignedBoxCell(const MeshView& m, label cell, Vec3& lo, Vec3& hi, double relTol = 1e-12);

} // namespace overlapMapping

#endif
