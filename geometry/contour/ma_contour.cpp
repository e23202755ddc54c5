// The medial-axis contour (paper §3.2-3.4; ma_contour.h), as the paper's steps, one function
// each, in contour/ma/:
//   per layer: slab -> footprint -> boundary pairs (slab.h, boundary_pair.h); the free faces
//     beside each pair's loops labelled solid or empty from the mid section (solid_beside);
//   per island whose loops have both labels (island_axis below):
//   1. sample the boundary pair                     ma/samples.h      sample_boundary_pair
//   2. triangulate the samples (CGAL, constrained)  ma/triangulation.h triangulate_samples
//   3. label the triangulation's vertices           ma/axis.h         vertex_labels
//   4. extract the axis (Observation 3.3.1) and
//      chain it into closed loops                   ma/axis.h         axis_loops
//   5. fair each loop (Fig. 17)                     ma/fairing.h      axis_loop
//   6. find the pockets of non-contributing samples (§3.4)  ma/pockets.h  island_pockets
//   per layer (ma_contour below):
//   - caps and walls take the mid section (ma/mid_section.h), the islands' paths are united
//     (united_contour: as they stand where only axes are, they are a Region already);
//   - floating features take the mid section (ma/mid_section.h: add_floating_features);
//   - pockets whose samples are farther from the walls than every contributing sample (Θ)
//     take the mid section where it brings them nearer (refine_pockets below). The paper's own
//     refinement (moving Voronoi vertices towards those samples) is not implemented, as in
//     the paper's implementation.
// Both replacements are one Clipper operation each, (region \ zone) ∪ (mid ∩ zone)
// (mid_inside), so the parts meet exactly on the zone's edges.
#include "geometry/contour/ma_contour.h"

#include <algorithm>
#include <optional>
#include <utility>

#include "geometry/contour/contour_strategy.h"
#include "geometry/contour/ma/axis.h"
#include "geometry/contour/ma/mid_section.h"
#include "geometry/contour/ma/pockets.h"
#include "geometry/contour/ma/samples.h"
#include "geometry/contour/ma/triangulation.h"
#include "geometry/core/boundary_grid.h"
#include "geometry/core/clipper.h"

namespace geometry {

namespace {

// Below this, mm, two distances are the same for the refinement's decisions: the distance
// metric's own tolerance (distance_error.h).
constexpr double kRefineTolerance = 0.001;

struct IslandAxis {
  std::vector<Loop> loops;
  ma::IslandPockets pockets;  // with want_pockets only
};

// Steps 1-6 for one island. `solid` per loop (loops_of order); a cap (one label only) has no
// axis loop.
IslandAxis island_axis(const BoundaryPair& pair, std::span<const char> solid,
                       const MaOptions& options, MaStats* stats, bool want_pockets) {
  IslandAxis axis;
  const std::vector<const Loop*> loops = loops_of(pair);
  if (solid.size() != loops.size()) return axis;
  if (std::all_of(solid.begin(), solid.end(), [&](char s) { return (s != 0) == (solid[0] != 0); })) {
    return axis;  // a cap: no loop separates solid from empty
  }
  const std::vector<ma::Sample> samples = ma::sample_boundary_pair(loops, options);
  if (stats) stats->samples += samples.size();
  const ma::SampleTriangulation triangulation = ma::triangulate_samples(samples);
  const std::vector<char> labels = ma::vertex_labels(triangulation, samples, solid);
  axis.loops = ma::axis_loops(triangulation, labels, samples, loops, options.fairing);
  if (stats) stats->loops += axis.loops.size();
  if (want_pockets) axis.pockets = ma::island_pockets(triangulation, labels, samples);
  return axis;
}

// The mid section on Clipper's grid, converted once per layer, where something asks for it
// (caps, walls, floating features, the mid section's replacements).
class MiddleOnGrid {
 public:
  explicit MiddleOnGrid(const Region& middle) : middle_(middle) {}
  const ClipperLib::Paths& paths() {
    if (!paths_) paths_ = to_clipper(middle_);
    return *paths_;
  }

 private:
  const Region& middle_;
  std::optional<ClipperLib::Paths> paths_;
};

// What the islands give before the layer's union: every island's paths (its axis loops, or
// a cap's or a wall's section, to add with positive winding), the floating features' zones,
// and the axes with their pockets.
struct IslandContours {
  ClipperLib::Paths paths, features;
  bool only_axes = true;  // no cap, no wall
  std::vector<IslandAxis> axes;
};

IslandContours island_contours(const Slab& slab, std::span<const BoundaryPair> pairs,
                               const Region& middle, MiddleOnGrid& middle_grid,
                               const std::function<Region(double z)>& cross_section,
                               const MaOptions& options, MaStats* stats) {
  IslandContours parts;
  ClipperLib::PolyTree middle_nesting;  // built for the first island that may have a feature
  bool nested = false;
  for (const BoundaryPair& pair : pairs) {
    const std::vector<char> solid = solid_beside(pair, middle);
    const bool cap = std::all_of(solid.begin(), solid.end(), [&](char s) { return s == solid[0]; });
    ClipperLib::Paths island;
    if (cap) {
      parts.only_axes = false;
      if (stats) ++stats->caps;
      island = ma::cap_contour(slab, pair, solid[0] != 0, middle_grid.paths(), cross_section);
    } else if (ma::is_wall(pair)) {
      // Lower contour = upper contour: the contour is that section, exactly (the axis of the
      // ring would be it to a fraction of the margin), without a triangulation.
      parts.only_axes = false;
      if (stats) ++stats->walls;
      island = ma::section_in_island(middle_grid.paths(), pair, solid[0] != 0);
    } else {
      parts.axes.push_back(island_axis(pair, solid, options, stats, options.pockets));
      for (const Loop& loop : parts.axes.back().loops) island.push_back(to_clipper(loop));
      if (options.floating_features && ma::may_float(pair, middle)) {
        if (!nested) clipper::union_nonzero_tree(middle_grid.paths(), middle_nesting);
        nested = true;
        ma::add_floating_features(pair, middle_nesting, parts.features, stats);
      }
    }
    parts.paths.insert(parts.paths.end(), island.begin(), island.end());
  }
  return parts;
}

// Whether axis loops on Clipper's grid are a Region as they stand: loops that are simple,
// pairwise disjoint and have the solid on their left (medial_axis_loops), from disjoint
// islands, which their union would only renumber. The rounding must not have merged two
// vertices (a union would drop one). On the bunny the union gave back the very same vertices
// on each of the 325 layers whose islands all have their axis.
bool on_grid_as_they_are(const ClipperLib::Paths& loops) {
  for (const ClipperLib::Path& loop : loops) {
    if (loop.size() < 3) return false;
    for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
      if (loop[i] == loop[i + 1 == n ? 0 : i + 1]) return false;
    }
  }
  return true;
}

// The islands' paths as the layer's Region. Every loop has the solid on its left, so summing
// winding numbers over all islands gives 1 exactly on the layer's region, also for islands
// nested in another's holes: their positive union.
Region united_contour(const IslandContours& parts) {
  if (parts.only_axes && on_grid_as_they_are(parts.paths)) return from_clipper(parts.paths);
  ClipperLib::PolyTree united;
  return from_clipper(clipper::union_positive_tree(parts.paths, united));
}

// max(level, the distance from p to the walls), the distance asked only where no wall is
// nearer to p than level already (any_within says so sharply when it says true): most points
// are, and any_within stops at the first wall it finds, where nearest_distance searches every
// cell round p. Bit for bit the max of the distances: on the bunny the four maxima below ask
// nearest_distance about 140 000 times without the test.
double farther_of(const BoundaryGrid& walls, Vec2 p, double level) {
  return walls.any_within(p, level) ? level : std::max(level, walls.nearest_distance(p));
}

// Θ of §3.4 for one island: the largest distance of a contributing sample to the walls, needed
// only up to `farthest` (the farthest pocket sample: most pockets are a sharp corner's few
// samples). Visited a sixteenth at a time, spread along the loops, so that where some sample
// is farther than every pocket sample it is found early (the decisions come out the same in
// any order: all pockets pass when one is, else the level is the maximum).
double contributing_level(const std::vector<Vec2>& contributing, const BoundaryGrid& walls,
                          double farthest) {
  double level = 0;
  const std::size_t count = contributing.size();
  constexpr std::size_t kStride = 16;
  for (std::size_t first = 0; first < kStride && level <= farthest; ++first) {
    for (std::size_t i = first; i < count && level <= farthest; i += kStride) {
      level = farther_of(walls, contributing[i], level);
    }
  }
  return level;
}

// Step 6's decision (paper §3.4's non-contributing points): a pocket whose samples are
// farther from the walls of `contour` than every contributing sample of its island (Θ), and
// whose corners the mid section's walls bring nearer, adds its triangles to `zone`, to take
// the mid section there. Returns how many pockets did. The mid section's grid is built only
// if some pocket gets as far as asking it (two layers in five), or taken from `grids`; the
// grid of `contour` goes out in `grids` where no pocket refined it.
std::size_t refine_pockets(const std::vector<IslandAxis>& axes, const Region& contour,
                           const Region& middle, ClipperLib::Paths& zone, MaGrids* grids) {
  BoundaryGrid walls(contour);
  std::optional<BoundaryGrid> own_middle_walls;
  const BoundaryGrid* middle_walls = nullptr;
  std::size_t refined = 0;
  std::vector<double> worst;
  for (const IslandAxis& axis : axes) {
    const std::vector<ma::Pocket>& pockets = axis.pockets.pockets;
    if (pockets.empty()) continue;
    worst.assign(pockets.size(), 0);
    double farthest = 0;
    for (std::size_t k = 0; k < pockets.size(); ++k) {
      for (Vec2 p : pockets[k].non_contributing) worst[k] = farther_of(walls, p, worst[k]);
      farthest = std::max(farthest, worst[k]);
    }
    const double level = contributing_level(axis.pockets.contributing, walls, farthest);
    for (std::size_t k = 0; k < pockets.size(); ++k) {
      const ma::Pocket& pocket = pockets[k];
      if (worst[k] <= level + kRefineTolerance) continue;
      if (!middle_walls && grids && grids->shared) middle_walls = grids->shared(middle);
      if (!middle_walls) middle_walls = &own_middle_walls.emplace(middle);
      double now = 0, with_middle = 0;
      for (Vec2 p : pocket.corners) {
        now = farther_of(walls, p, now);
        with_middle = farther_of(*middle_walls, p, with_middle);
      }
      if (with_middle >= now - kRefineTolerance) continue;
      pocket.add_triangles(zone);
      ++refined;
    }
  }
  if (grids && refined == 0) grids->walls = std::move(walls);
  return refined;
}

}  // namespace

std::vector<Loop> medial_axis_loops(const BoundaryPair& pair, std::span<const char> solid,
                                    const MaOptions& options, MaStats* stats) {
  return island_axis(pair, solid, options, stats, false).loops;
}

Region ma_contour(const Slab& slab, const std::function<Region(double z)>& cross_section,
                  const MaOptions& options, MaStats* stats) {
  if (slab.facets.empty() || !(slab.z_lo < slab.z_hi)) return {};
  return ma_contour(slab, slab_islands(slab), cross_section, options, stats);
}

Region ma_contour(const Slab& slab, const Region& footprint,
                  const std::function<Region(double z)>& cross_section, const MaOptions& options,
                  MaStats* stats) {
  if (slab.facets.empty() || !(slab.z_lo < slab.z_hi)) return {};
  return ma_contour(slab, boundary_pairs(footprint), cross_section, options, stats);
}

Region ma_contour(const Slab& slab, std::span<const BoundaryPair> pairs,
                  const std::function<Region(double z)>& cross_section, const MaOptions& options,
                  MaStats* stats, MaGrids* grids) {
  if (slab.facets.empty() || !(slab.z_lo < slab.z_hi)) return {};
  if (pairs.empty()) return {};
  const Region middle = cross_section(0.5 * (slab.z_lo + slab.z_hi));
  if (stats) stats->islands += pairs.size();
  MiddleOnGrid middle_grid(middle);
  const IslandContours parts =
      island_contours(slab, pairs, middle, middle_grid, cross_section, options, stats);
  Region basic = united_contour(parts);
  const bool any_pocket = std::any_of(parts.axes.begin(), parts.axes.end(), [](const IslandAxis& a) {
    return !a.pockets.pockets.empty();
  });
  if (parts.features.empty() && !any_pocket) return basic;

  const ClipperLib::Paths basic_paths = to_clipper(basic);
  const ClipperLib::Paths& middle_paths = middle_grid.paths();
  const ClipperLib::Paths feature_zone = clipper::union_nonzero(parts.features);
  const Region with_features = feature_zone.empty()
                                   ? std::move(basic)
                                   : ma::mid_inside(basic_paths, middle_paths, feature_zone);
  if (!any_pocket) return with_features;
  ClipperLib::Paths zone = feature_zone;
  const std::size_t refined = refine_pockets(parts.axes, with_features, middle, zone, grids);
  if (stats) stats->pockets += refined;
  if (refined == 0) return with_features;
  return ma::mid_inside(basic_paths, middle_paths, clipper::union_nonzero(zone));
}

Region ma_contour(const LayerStack& stack, std::size_t layer, const MaOptions& options,
                  MaStats& stats) {
  if (layer >= stack.size()) return {};
  return ma_contour(
      slab_of(stack, layer), [&stack](double z) { return stack.cross_section(z); }, options,
      &stats);
}

Region ma_contour(const LayerStack& stack, std::size_t layer, const MaOptions& options) {
  MaStats stats;
  return ma_contour(stack, layer, options, stats);
}

ContourResult ma_strategy(const ContourInput& input) {
  const LayerStack& stack = input.stack;
  const double middle = stack.layers()[input.layer].z_mid();
  const MaOptions& options = input.options.ma;
  if (!input.reference) return {ma_contour(stack, input.layer, options), middle};
  // The slab is clipped and its islands found already: hand them over.
  return {ma_contour(
              input.reference->slab, input.reference->islands,
              [&stack](double z) { return stack.cross_section(z); }, options),
          middle};
}

}  // namespace geometry
