// Thin walls: centre lines for the parts of a layer too narrow for a wall loop (issue 4,
// "Toolpaths": a thin wall narrower than the bead is still printed, not dropped).
//
// Input:  a region (mm, outer loops CCW, holes CW) that is at most about one bead wide
//         everywhere: the strips perimeters() finds between the region edge and the first
//         loop, or between two loops.
// Output: paths of role thin_wall along the region's medial axis, without the branches that
//         run into its corners: a round-ended bead along such a line fills the region. Each
//         path's width is the local width of the region (twice the inscribed radius,
//         averaged along runs where it varies by less than 20%), clamped to
//         [min_width, max_width]. A thin ring gives a closed path; lines shorter than
//         min_width are dropped, and so are parts wider than 2 * max_width (not thin walls).
//         A compact piece the axis leaves bare (the blunt end of a thin feature), if a bead of
//         min_width fits in it, gets one line along its long (principal) axis, as wide as
//         its area over its length.
//         Empty input, or a region larger than 2 m, gives no paths.
// Method: Boost.Polygon's segment Voronoi diagram of the region's edges (exact predicates);
// its interior edges are the medial axis.
#pragma once

#include <vector>

#include "geometry/polygon.h"
#include "geometry/toolpaths.h"

namespace geometry {

std::vector<ExtrusionPath> thin_walls(const Region& region, double min_width, double max_width);

}  // namespace geometry
