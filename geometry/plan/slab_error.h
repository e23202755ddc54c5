// The exact error of one candidate slab, for the layer plan: the distance error D
// (distance_error.h, the paper's D_i, the forward direction, to its tolerance) of the region a
// contour strategy prints for the slab [z_lo, z_hi], measured as `mahost analyze` measures a
// layer (layer_metrics.h), so that a plan's promise is analyze's figure.
//
// Input: a layer stack (only its mesh and face index are used: a candidate slab needs no
// layer of the stack), the slab's bounds in mm, the strategies to try in order.
// Output: per strategy tried, its D (mm) and region; `best` is the one with the least D (ties
// within 1 um: the first). With `enough` > 0, stops at the first strategy whose D is within
// it (a feasibility test that usually needs only the cheapest strategy); with `refute_above`
// > 0, measures each strategy only until it is seen to exceed that (its D then a lower bound,
// `bounded`). An empty slab (above the part): D = 0 and empty regions.
//
// Cheaper where it can be, same result: surface inside an island of the slab's footprint that
// the region misses is measured to the island's outline, never farther than to the walls (the
// way out of the island crosses its outline first), so measuring everything to the walls
// bounds D from above; and a section contour (lower, mid) touches every island holding a piece
// of surface that crosses the section's height, and every island holding a piece with a point
// well inside the section. When every connected piece of the slab's surface does one or the
// other (found through the mesh's edges), no island is missed and that bound is D, with no
// footprint built (about 45% of the work for a mid section; the bunny's many small bumps and
// dents on its walls, which a mid section passes round, are pieces of the second kind). The surface's points on the
// slab's two planes are then the sections there: a section strategy's slab is first judged by
// those alone, before the slab is cut out of the mesh, and refused if one of them stands past
// `enough` (most refused candidates are refused so). Sections are cut once per height and
// kept (a grid height starts, ends or halves several candidates); the meter is safe to call
// from several threads at once.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <unordered_map>
#include <vector>

#include "geometry/contour/contour_strategy.h"
#include "geometry/core/polygon.h"
#include "geometry/metrics/distance_error.h"
#include "geometry/slicing/layer_stack.h"

namespace geometry {

class BoundaryGrid;  // geometry/core/boundary_grid.h

struct SlabTrial {
  const ContourStrategy* strategy = nullptr;
  double distance = 0;   // D, mm
  bool bounded = false;  // the search stopped past `enough`: D is at least `distance`
  bool settled = false;  // with `settle`: D proven within `enough`, at least `distance`
  std::size_t missed = 0;  // islands of the slab's footprint the region misses (missed_features.h)
  Region region;
};

struct SlabError {
  double z_lo = 0, z_hi = 0;
  std::vector<SlabTrial> trials;  // in the order tried
  std::size_t best = 0;           // index into trials of the least D
  double distance() const { return trials.empty() ? 0 : trials[best].distance; }
  // The least D known exactly, not only bounded from below (a trial within `enough` is exact
  // and below every bounded one, unless settled).
  bool exact() const { return trials.empty() || (!trials[best].bounded && !trials[best].settled); }
  // The least D proven within `enough` without being measured exactly (`settle`).
  bool settled() const { return !trials.empty() && trials[best].settled; }
};

struct SlabErrorOptions {
  ContourOptions contour;
  DistanceOptions distance{.tolerance = 1e-3, .reverse_levels = 2, .reverse = false};
};

class SlabMeter {
 public:
  // Finds each face's neighbours across its edges once; the stack must outlive the meter.
  explicit SlabMeter(const LayerStack& stack, SlabErrorOptions options = {});

  // With `settle` too (and `enough` > 0), a strategy whose D is seen to stay within `enough`
  // is not measured further (SlabTrial::settled): whether a slab is within a tolerance, not
  // by how much (DistanceOptions::settle_below).
  SlabError operator()(double z_lo, double z_hi, std::span<const ContourStrategy* const> strategies,
                       double enough = 0, double refute_above = 0, bool settle = false) const;

  // The D of a section strategy on the slab seen past `stop_above` from the sections on the
  // slab's two planes alone, as operator() would find it first; 0 where that shows nothing
  // (a D within it there, an island the section may miss, not a section strategy).
  double ends_past(double z_lo, double z_hi, const ContourStrategy& strategy, double stop_above) const;

  // Lets go of the sections kept below height z (a search that has moved on above them); one
  // asked for again is cut again.
  void forget_below(double z) const;

 private:
  // Does every connected piece of surface in [z_lo, z_hi] reach both its planes? It does where
  // no vertex that is a local top or bottom of the surface, and no flat face, lies inside.
  bool spans_every_piece(double z_lo, double z_hi) const;
  // Does every connected piece of surface in [z_lo, z_hi] cross height h, or else have a point
  // well inside the region `walls` bound (so that the piece's island of the footprint overlaps
  // the region: a bump on a wall, which a slab's mid section does not cut but passes round)?
  bool every_piece_meets(std::span<const std::uint32_t> faces, double z_lo, double z_hi, double h,
                         const BoundaryGrid& walls) const;

  // The model's section at height z, cut the first time it is asked for, and the grid over
  // its walls, likewise (only its queries that keep no state may be asked of it).
  struct Section;
  std::shared_ptr<Section> entry(double z) const;
  std::shared_ptr<const Region> section(double z) const;
  std::shared_ptr<const BoundaryGrid> section_walls(double z) const;

  // One slab's faces, slab, surface and islands, each cut the first time it is needed.
  struct Cut;
  // One strategy's trial on the slab: its region, and its D measured to the region's walls.
  SlabTrial trial(Cut& cut, const ContourStrategy& strategy) const;
  // Is the strategy a section that touches every island of the slab's footprint holding
  // surface (so no island is missed, and D is measured to the walls alone)? `walls`: its region's.
  bool section_meets_every_piece(Cut& cut, const ContourStrategy& strategy, const BoundaryGrid& walls) const;
  // D to the walls: the sections on the slab's planes first, then the whole surface.
  // `shared`: the walls' grid is a section's (section_walls), copied for the surface's search.
  void measure_to_walls(Cut& cut, const BoundaryGrid& walls, bool shared, SlabTrial& trial) const;
  // The distance from `walls` of the first vertex of the sections on the slab's planes farther
  // than the cut's stop_above; 0 when none is.
  double ends_farthest(Cut& cut, const BoundaryGrid& walls) const;
  // D with the footprint's islands the region misses measured to their outlines.
  void measure_with_islands(Cut& cut, const BoundaryGrid& walls, bool shared, SlabTrial& trial) const;

  const LayerStack& stack_;
  SlabErrorOptions options_;
  std::vector<std::array<std::uint32_t, 3>> neighbours_;  // across edge k (corners k, k+1)
  std::vector<double> flat_heights_;  // of the exactly horizontal faces, ascending, once each
  std::vector<double> extreme_heights_;  // of the vertices no neighbour rises or falls from
  mutable std::mutex sections_mutex_;
  mutable std::unordered_map<double, std::shared_ptr<Section>> sections_;
};

SlabError slab_error(const LayerStack& stack, double z_lo, double z_hi,
                     std::span<const ContourStrategy* const> strategies, double enough = 0,
                     const SlabErrorOptions& options = {});

}  // namespace geometry
