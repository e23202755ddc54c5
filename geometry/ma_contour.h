// The medial-axis contour of a layer (paper §3.2-3.3).
//
// Input: the layer stack and a layer index. The slab's faces are clipped to [z_lo, z_hi] and
// projected; the union's outermost and innermost boundaries form the boundary pair (one per
// island, holes included); the pair is sampled, CGAL's Delaunay triangulation of the samples
// gives the Voronoi diagram, and the Voronoi edges whose dual Delaunay edge joins two
// different boundary loops are chained into closed loops and faired.
// Output: a valid Region, mm. A vertical wall (lower contour = upper contour) gives that
// contour; an empty slab gives an empty Region.
#pragma once

#include <cstddef>

#include "geometry/layer_stack.h"
#include "geometry/polygon.h"

namespace geometry {

struct MaOptions {
  // Sample spacing on the boundary pair, mm; 0 picks it from the layer (see ma_contour.cpp).
  double spacing = 0;
  // Cap on samples per layer, so one layer never dominates the run time.
  std::size_t max_points = 20000;
  // Local resampling where the skeleton is aliased (paper §3.3, Fig. 17).
  bool fairing = true;
};

Region ma_contour(const LayerStack& stack, std::size_t layer, const MaOptions& options = {});

}  // namespace geometry
