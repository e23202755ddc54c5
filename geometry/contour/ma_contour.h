// The medial-axis contour of a layer (paper §3.2-3.3).
//
// Input: the layer stack and a layer index. The slab's faces are clipped to [z_lo, z_hi] and
// projected; the union's outermost and innermost boundaries form the boundary pair (one per
// island, holes included); the pair is sampled, CGAL's Delaunay triangulation of the samples
// gives the Voronoi diagram, and the Voronoi edges whose dual Delaunay edge joins two
// different boundary loops are chained into closed loops and faired.
// Output: a valid Region, mm. A vertical wall (lower contour = upper contour) gives that
// contour; an empty slab gives an empty Region.
//
// Which side is solid, and where the axis does not apply. Each loop of an island's boundary
// pair has one free face beside it (outside the footprint: the vertical line through it meets
// no surface in the slab), solid or empty over the whole slab; the mid section tells which.
// The axis separates the solid loops' territory from the empty loops'. That is the paper's
// strip: the surface runs from the solid loops to the empty ones. Where it does not, the
// contour is the mid section (the least volume deviation a column can have, DESIGN.md §3),
// decided from the geometry, island by island and part by part:
//   - a cap (every free face of the island solid, or every one empty: a feature beginning or
//     ending inside the slab) is the mid section inside the island, or the section half-way
//     through the feature's height if the middle misses it;
//   - a floating feature (a solid or empty face of the mid section inside a strip that holds
//     none of the island's loops: a bump, a dip, a nearly flat patch whose height wobbles round
//     the middle) keeps that face of the mid section;
//   - a pocket (same-side Delaunay triangles holding samples no contour edge is dual to: a
//     neck or septum merging inside the slab, a groove, a lobe; paper §3.4) whose samples are
//     farther from the walls than every contributing sample takes the mid section inside its
//     triangles where that brings them nearer.
// Sibling: toolpaths/segment_medial_axis.h, the exact medial axis of a region from the
// Voronoi diagram of its edges (Boost.Polygon), for thin walls. This one is sampled, as the
// paper's is (§3.2.3), because what it needs is the axis between loops labelled solid and
// empty (Observation 3.3.1 reads it off the Delaunay edges between samples of different loops),
// closed loops only, and the Delaunay triangles round the non-contributing samples (§3.4);
// fairing then moves it onto the loops' exact axis. That header says why the thin walls need
// the other.
//
// ma_contour.cpp lists the paper's steps and the files of contour/ma/ that make them; their
// headers have the details and the bunny's figures.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "geometry/contour/contour_input.h"
#include "geometry/core/boundary_grid.h"
#include "geometry/slab/boundary_pair.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/core/polygon.h"
#include "geometry/slab/slab.h"

namespace geometry {

struct MaOptions {
  // Sample spacing on the boundary pair, mm; 0: ma/samples.h's default, 0.25 mm.
  double spacing = 0;
  // Cap on samples per layer, so one layer never dominates the run time.
  std::size_t max_points = 20000;
  // Local resampling where the skeleton is aliased (paper §3.3, Fig. 17).
  bool fairing = true;
  // Features inside a strip that the boundary pair does not show: the mid section there.
  bool floating_features = true;
  // Pockets of non-contributing samples (paper §3.4): the mid section where it serves them.
  bool pockets = true;
};

Region ma_contour(const LayerStack& stack, std::size_t layer, const MaOptions& options = {});

// What one layer's contour took, for benchmarks and reports.
struct MaStats {
  std::size_t islands = 0;  // boundary pairs of the footprint
  std::size_t caps = 0;     // of them, caps (all free faces solid or all empty)
  std::size_t walls = 0;    // of them, vertical walls (rings a few margins wide)
  std::size_t samples = 0;  // points given to the Delaunay triangulations
  std::size_t loops = 0;    // closed medial-axis loops before the final union
  std::size_t features = 0; // floating features of the mid section kept inside strips
  std::size_t pockets = 0;  // pockets given the mid section
};

Region ma_contour(const LayerStack& stack, std::size_t layer, const MaOptions& options,
                  MaStats& stats);

// The same from a slab and the model's cross-section at any height of it (ma/mid_section.h
// documents what a cap becomes); with the slab's footprint if the caller has it already
// (slab_footprint(slab), about a third of the time here).
Region ma_contour(const Slab& slab, const std::function<Region(double z)>& cross_section,
                  const MaOptions& options = {}, MaStats* stats = nullptr);
Region ma_contour(const Slab& slab, const Region& footprint,
                  const std::function<Region(double z)>& cross_section,
                  const MaOptions& options = {}, MaStats* stats = nullptr);
// ... and with its boundary pairs (boundary_pairs(footprint)), as layer_metrics.h keeps them.
// `grids`, if given: the walls' grids ma shares with a caller that indexes the same regions
// (best measures ma's region and the middle section's: best_contour.h).
struct MaGrids;
Region ma_contour(const Slab& slab, std::span<const BoundaryPair> islands,
                  const std::function<Region(double z)>& cross_section,
                  const MaOptions& options = {}, MaStats* stats = nullptr,
                  MaGrids* grids = nullptr);

// Grids over regions (boundary_grid.h) that ma builds for its pockets' decisions (step 6) and
// its caller builds too. In: `shared(region)`, the caller's grid over `region` (built there on
// the first ask and kept), or null where it has none; ma asks it for the middle section's
// walls. Out: `walls`, ma's grid over the region it returns, where it built one (a layer with
// pockets, none of which took the middle section); else left empty.
struct MaGrids {
  std::function<const BoundaryGrid*(const Region& region)> shared;
  std::optional<BoundaryGrid> walls;
};

// The strategy "ma" (contour_strategy.h): the contour from the reference's slab and islands
// where there is one, else from the stack; options.ma; the height is the layer's middle.
ContourResult ma_strategy(const ContourInput& input);

// One island's medial-axis loops: the Voronoi edges whose dual Delaunay edge joins a loop with
// solid beside it to one with empty beside it (solid[k] for loops_of(pair)[k], see
// boundary_pair.h), chained into closed loops, each with the solid on its left. Loops are
// simple and pairwise disjoint. A cap (all solid or all empty) gives none.
std::vector<Loop> medial_axis_loops(const BoundaryPair& pair, std::span<const char> solid,
                                    const MaOptions& options = {}, MaStats* stats = nullptr);

}  // namespace geometry
