// Thin walls: centre lines for the parts of a layer too narrow for a wall loop (a wall
// narrower than the bead is still printed, not dropped).
//
// Input:  a region (mm, outer loops CCW, holes CW) that is at most about one bead wide
//         everywhere: the strips perimeters() finds between the region edge and the first
//         loop, or between two loops.
// Output: paths of role thin_wall along the region's medial axis, without the branches that
//         run into its corners: a round-ended bead along such a line fills the region. Each
//         path's width is the local width of the region (twice the inscribed radius,
//         averaged along runs where it varies by less than 10%), clamped to
//         [min_width, max_width]. A thin ring gives a closed path; lines shorter than
//         min_width are dropped, and so are parts wider than 2 * max_width (not thin walls).
//         A compact piece the axis leaves bare (the blunt end of a thin feature), if a bead of
//         min_width fits in it, gets one line along its long (principal) axis, as wide as
//         its area over its length.
//         A run wider than pair_width (up to max_width) is laid as two beads side by side,
//         each half as wide: one closed path round its centre line, a quarter of its width
//         out on either side and round its ends (a loop in a strip 1.5 to 2 beads wide,
//         whose sides meet without overlapping).
//         With reach_within (the part, or the area the region is a gap in), a free end of a
//         line is carried on by half its width where its bead then still lies inside
//         reach_within: against a wall or another bead, the bead is full to the end of the
//         strip; at the part's edge it stops where its round end meets the edge.
//         Empty input, or a region larger than 2 m, gives no paths.
// Method: the region's exact medial axis (segment_medial_axis.h: Boost.Polygon's segment
// Voronoi diagram of its edges), pruned of spurs, split into runs of nearly constant width.
#pragma once

#include <limits>
#include <vector>

#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"

namespace geometry {

std::vector<ExtrusionPath> thin_walls(const Region& region, double min_width, double max_width,
                                      double pair_width = std::numeric_limits<double>::infinity(),
                                      const Region* reach_within = nullptr);

}  // namespace geometry
