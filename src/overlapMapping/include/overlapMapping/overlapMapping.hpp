// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file overlapMapping.hpp
 * @brief Umbrella header of the overlapMapping library (grain/cell overlaps,
 *        thesis section 3.2.1). See README.md in src/overlapMapping.
 */
#ifndef OVERLAPMAPPING_OVERLAPMAPPING_HPP
#define OVERLAPMAPPING_OVERLAPMAPPING_HPP

#include "overlapMapping/CellMesh.hpp"
#include "overlapMapping/Geometry2D.hpp"
#include "overlapMapping/Geometry3D.hpp"
#include "overlapMapping/MeshBuilders.hpp"
#include "overlapMapping/MeshView.hpp"
#include "overlapMapping/OverlapMapper.hpp"
#include "overlapMapping/SphereBox.hpp"
#include "overlapMapping/Types.hpp"

#endif
