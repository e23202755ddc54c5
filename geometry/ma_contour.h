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
#include <functional>
#include <span>
#include <vector>

#include "geometry/boundary_pair.h"
#include "geometry/layer_stack.h"
#include "geometry/polygon.h"
#include "geometry/slab.h"

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

// What one layer's contour took, for benchmarks and reports.
struct MaStats {
  std::size_t islands = 0;  // boundary pairs of the footprint
  std::size_t caps = 0;     // of them, caps (all free faces solid or all empty)
  std::size_t walls = 0;    // of them, vertical walls (rings a few margins wide)
  std::size_t samples = 0;  // points given to the Delaunay triangulations
  std::size_t loops = 0;    // closed medial-axis loops before the final union
};

Region ma_contour(const LayerStack& stack, std::size_t layer, const MaOptions& options,
                  MaStats& stats);

// The same from a slab and the model's cross-section at any height of it (ma_contour.cpp
// documents what a cap becomes); with the slab's footprint if the caller has it already
// (slab_footprint(slab), about a third of the time here).
Region ma_contour(const Slab& slab, const std::function<Region(double z)>& cross_section,
                  const MaOptions& options = {}, MaStats* stats = nullptr);
Region ma_contour(const Slab& slab, const Region& footprint,
                  const std::function<Region(double z)>& cross_section,
                  const MaOptions& options = {}, MaStats* stats = nullptr);

// One island's medial-axis loops: the Voronoi edges whose dual Delaunay edge joins a loop with
// solid beside it to one with empty beside it (solid[k] for loops_of(pair)[k], see
// boundary_pair.h), chained into closed loops, each with the solid on its left. Loops are
// simple and pairwise disjoint. A cap (all solid or all empty) gives none.
std::vector<Loop> medial_axis_loops(const BoundaryPair& pair, std::span<const char> solid,
                                    const MaOptions& options = {}, MaStats* stats = nullptr);

}  // namespace geometry
