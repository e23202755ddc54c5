// Brim: loops on the first layer, out from the part's edge, that hold it to the bed.
//
// Input:  the first layer's footprint (mm: the part's first layer and the support on it, or
//         the raft), the bead width w (mm), the brim's width (mm).
// Output: closed paths (last point = first), role brim: n = ceil(brim_width / w) loops, loop
//         k (from 0, innermost) following the footprint grown by w/2 + k w (round corners;
//         holes of the grown outline dropped: the brim goes round the outside, never into a
//         hole), printed outermost first, CCW. brim_extent(...) = n w, how far it reaches.
// Empty footprint, w <= 0 or brim_width <= 0 give no paths (and an extent of 0).
#pragma once

#include <vector>

#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"

namespace geometry {

std::vector<ExtrusionPath> brim(const Region& footprint, double width, double brim_width);

double brim_extent(double width, double brim_width);

}  // namespace geometry
