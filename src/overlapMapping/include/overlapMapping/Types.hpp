// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file Types.hpp
 * @brief Basic types shared by the overlapMapping library.
 *
 * overlapMapping is a standalone C++17 + Eigen library (no OpenFOAM include)
 * computing the exact overlap of grains (discs in 2D, spheres in 3D) with the
 * cells of a finite-volume mesh, and the coupling fields derived from it
 * (thesis section 3.2.1, eq. 3.40-3.45). All lengths are in metres, areas in
 * m^2, volumes in m^3 (any consistent unit system works: nothing is hard-coded).
 */
#ifndef OVERLAPMAPPING_TYPES_HPP
#define OVERLAPMAPPING_TYPES_HPP

#include <Eigen/Core>
#include <cstdint>

namespace overlapMapping
{

/// Index type of points, faces, cells and grains (same width as OpenFOAM's
/// default 32-bit `label`).
using label = std::int32_t;

/// 3D vector (unaligned storage, safe in std::vector).
using Vec3 = Eigen::Matrix<double, 3, 1, Eigen::DontAlign>;

/// 2D vector (unaligned storage, safe in std::vector).
using Vec2 = Eigen::Matrix<double, 2, 1, Eigen::DontAlign>;

/// pi to double precision.
constexpr double pi = 3.14159265358979323846264338327950288;

} // namespace overlapMapping

#endif
