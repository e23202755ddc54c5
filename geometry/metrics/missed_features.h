// Missed features (paper §4: "feature recognition"): islands of a slab's footprint that a
// layer's region does not touch, such as a bump or a tip that begins and ends inside the slab
// and falls between the planes a strategy looks at.
//
// Input: the slab's footprint (slab.h: the union of its facets' projections) and the layer's
// region, mm. Output: the footprint's islands (boundary_pair.h: outer boundary and holes) that
// overlap the region by no more than 1 um^2, in the footprint's order. Empty footprint: none.
// Empty region: every island.
#pragma once

#include <vector>

#include "geometry/slab/boundary_pair.h"
#include "geometry/core/polygon.h"

namespace geometry {

// Overlap below this (mm^2) is rounding, not touching: the footprint's 2 um margin alone
// gives a region that follows a wall thousands of times more.
inline constexpr double kTouchArea = 1e-6;

std::vector<BoundaryPair> missed_features(const std::vector<BoundaryPair>& islands,
                                          const Region& region);
std::vector<BoundaryPair> missed_features(const Region& footprint, const Region& region);

}  // namespace geometry
