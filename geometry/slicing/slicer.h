// Uniform slicing: cross-sections of a closed mesh by horizontal planes (DESIGN.md §1).
//
// Input: a closed, outward-oriented Mesh (see repair.h), heights in mm in any order.
// Output: one Region per height, in the order of `heights`: outer loops CCW, holes CW,
// islands in holes CCW (non-zero fill), no repeated closing point.
// A plane exactly through vertices, edges or horizontal faces is resolved as the limit from
// above, C(z) = lim C(z + e): a cube [0,10]^3 cut at z = 0 gives the full square, at z = 10
// nothing. All planes are cut in one sweep over the faces sorted by height.
#pragma once

#include <span>
#include <vector>

#include "geometry/mesh/mesh.h"
#include "geometry/core/polygon.h"

namespace geometry {

std::vector<Region> slice_mesh(const Mesh& mesh, std::span<const double> heights);

}  // namespace geometry
