// Flat levels: the heights of a model's horizontal faces (a top, a floor, a step), which a
// layer plan puts on layer boundaries. A flat top strictly inside a layer prints at
// that layer's top or bottom instead: an 8.00 mm part at 0.15 mm layers from z = 0 would end
// at 7.95 or 8.10 mm.
//
// Input: a mesh (mm). A facet is horizontal when its corners' heights differ by at most
// kFlatHeightTolerance; facets at one height (within the same tolerance) make one level.
// Output: the levels whose horizontal facets cover at least min_area (mm^2) together, in
// ascending z, each at the height of its largest facet, with their area (a part standing on
// the bed has one at z = 0). Empty mesh: none.
#pragma once

#include <vector>

#include "geometry/mesh/mesh.h"

namespace geometry {

inline constexpr double kFlatHeightTolerance = 1e-6;  // mm
// Smaller horizontal patches (a scanned mesh's stray flat triangles) do not pull boundaries.
inline constexpr double kFlatMinArea = 0.1;           // mm^2

struct FlatLevel {
  double z = 0;     // mm
  double area = 0;  // of the horizontal facets there, facing up or down, mm^2
};

std::vector<FlatLevel> flat_levels(const Mesh& mesh, double min_area = kFlatMinArea);

}  // namespace geometry
