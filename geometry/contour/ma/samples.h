// Step 1 of the medial-axis contour (paper §3.3, "dense sampling points are uniformly taken
// from the boundary pair"): the points whose Voronoi diagram approximates the strip's axis.
//
// Input: the loops of one boundary pair (loops_of order: outer, then holes), mm, and the
// options' spacing (0: kDefaultSpacing) and cap on samples.
// Output: every loop vertex, plus points every `spacing` mm along longer edges, loop by loop
// and in loop order; each sample knows its loop and the loop edge it lies on. Over the cap
// the spacing grows until it fits; if the vertices alone are over the cap, every stride-th
// vertex is kept and no edge is split. At least 16 samples are allowed.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/contour/ma_contour.h"
#include "geometry/core/polygon.h"

namespace geometry::ma {

struct Sample {
  Vec2 at;
  std::uint32_t loop = 0;     // index into loops_of(pair)
  std::uint32_t segment = 0;  // the loop's edge from vertex `segment` to the next
};

// Default spacing when MaOptions::spacing is 0, mm (every loop vertex is a sample anyway).
// With fairing the contour's vertices sit on the exact axis of the boundary polygons and its
// edges are split until they follow it to 1 um, so spacing only shapes the triangulation:
// the bunny's distance errors are the same (mean 0.301 mm) at 0.1, 0.2, 0.5 mm and with loop
// vertices alone, while CPU time falls from 1.9 s to 1.2 s. 0.25 mm still gives a long edge
// (a cube's 10 mm side) forty samples, so the triangles across a strip stay short.
inline constexpr double kDefaultSpacing = 0.25;

std::vector<Sample> sample_boundary_pair(const std::vector<const Loop*>& loops,
                                         const MaOptions& options);

}  // namespace geometry::ma
