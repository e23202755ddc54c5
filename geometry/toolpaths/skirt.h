// Skirt: loops around the first layer that prime the nozzle before the part starts.
//
// Input:  the first layer's region (mm, any number of islands), the bead width w (mm), the
//         number of loops, and the gap between the part and the skirt (mm).
// Output: closed paths (last point = first), role skirt: loop k follows the outline of the
//         region grown by distance + w/2 + k*w (round corners; holes and the space between
//         islands closer than that are filled in, so the skirt goes around, never inside),
//         CCW, outermost first (the nozzle primes far from the part, then closes in).
// Empty region, loops <= 0 or w <= 0 give no paths; a negative distance counts as 0.
#pragma once

#include <vector>

#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"

namespace geometry {

// `loops` closed loops of `role` round the outline of `part` (non-zero union), outermost
// first: the innermost's centre line `first` mm out, each next one `width` further; holes of
// the grown outline (inside the part) left out. Empty for no loops or no width.
std::vector<ExtrusionPath> loops_around(const Region& part, double first, double width,
                                        int loops, PathRole role);

std::vector<ExtrusionPath> skirt(const Region& first_layer, double width, int loops,
                                 double distance);

}  // namespace geometry
