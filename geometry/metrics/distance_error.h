// Distance error of a layer (paper §3.4; DESIGN.md §3): how far, horizontally, the printed
// layer's walls stand from the model's surface.
//
// forward (the paper's D_i): the largest horizontal distance from a point of the model's
//   surface inside the slab to the walls ∂R_i x [z_lo, z_hi]. A surface point's distance to
//   the walls is the 2D distance from its projection to ∂R_i, so D_i is the maximum of the
//   distance to ∂R_i over the projected facets. It can lie inside a facet (near-horizontal
//   facets, caps), so each facet is searched by branch and bound: a lower bound from its
//   corners; upper bounds from the distance being 1-Lipschitz, from the min over the corners'
//   nearest walls s of max over corners of dist(corner, s) (the distance to one segment is
//   convex, so its maximum over a triangle is at a corner), and from the max over the piece of
//   the distance to the nearest of the corners' feet; and subdivision where the nearest wall
//   changes inside the facet, until the bounds are within `tolerance`. (Without the bound by
//   segments, on a smooth wall that each piece faces several segments of, a sphere's slice
//   with best at 0.2 mm took 0.57 against 0.31 s, 1.8 times as long.) Not done: leaving a
//   piece whose bound by the least of the planes through its corners' distances to their
//   nearest walls is below the largest distance found (the same D bit for bit, 22% fewer
//   pieces split on the bunny at 0.15 mm, but the planes cost 159 M of the 175 M
//   instructions they save: the best slice 13.494 G -> 13.478 G). The result is never
//   above the true maximum and at most `tolerance` below it. Walls are found through a grid
//   over ∂R_i (boundary_grid.h), not through the Voronoi diagram of §3.4, so any strategy's
//   region can be judged.
// reverse: the largest distance from a wall point at height z to the model's surface at that
//   height, the section boundary ∂C(z), over heights z in the slab. Measured at
//   `reverse_levels` heights: z_lo (the limit from above), z_hi (from below) and equally
//   spaced ones between; at each, exactly (to `tolerance`) by the same bounds along ∂R_i.
//   Heights where the model has no section are skipped (what a wall there overbuilds is
//   volume deviation, not distance). This direction is sampled in z; the forward one is not.
// hausdorff: max(forward, reverse).
//
// Decisions where the measure is undefined:
// - An exactly horizontal facet (a step strictly inside the slab) is judged by its edges: its
//   inside is parallel to the layer's top and bottom faces, where a horizontal distance means
//   nothing; the paper measures the slice mesh's vertices, which are on those edges.
// - Surface in an island of the slab's footprint that the region does not touch (a missed
//   feature, missed_features.h) is measured to that island's own outer outline, as if the
//   walls had shrunk onto the feature: a cone's tip left out is as bad as the radius at its
//   base, a bump left out as bad as its half-width. Measuring it to the nearest wall of some
//   other island instead would make one missed tail tip 18 mm "wrong" and drown every other
//   layer's figure; the miss itself is counted under missed features. An empty region
//   misses every island. reverse is 0 when there are no walls.
// - An empty slab: forward 0; reverse 0.
// Units: mm.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "geometry/core/boundary_grid.h"
#include "geometry/slab/boundary_pair.h"
#include "geometry/core/polygon.h"
#include "geometry/slab/slab.h"

namespace geometry {

// A forward measurement's corners, kept from a call with DistanceOptions::corners_only to the
// call that searches the triangles (for best's contest: the corners of a region that may lose
// are measured, another region is measured in full, and the first is searched only as far as
// it takes to refute it). Holds what the search holds per surface point and triangle and the
// walls of the missed islands; reusable for another measurement (each corners_only call
// starts afresh). Not shared between threads.
class ForwardState {
 public:
  ForwardState();
  ~ForwardState();
  ForwardState(const ForwardState&) = delete;
  ForwardState& operator=(const ForwardState&) = delete;
  // Forgets the corners kept: the next call given this state measures afresh. (A state kept
  // across slabs is cleared before a new slab's surface can take an old one's address.)
  void clear();
  struct Impl;
  Impl& impl() { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

struct DistanceOptions {
  double tolerance = 1e-3;  // mm
  int reverse_levels = 5;   // heights for the reverse direction, both ends included (>= 2)
  bool reverse = true;      // false: forward only (no levels built; reverse 0, Hausdorff = forward)
  // The forward search stops at the first surface point found farther than this from the
  // walls and gives that distance: then only a lower bound, enough to refuse a layer (the
  // layer plan's question is whether D exceeds a tolerance). Default: never, the exact D.
  double stop_above = std::numeric_limits<double>::infinity();
  // The forward search does not refine a piece of surface whose distance is known to stay at
  // or below this: D comes out exact (to `tolerance`) where it is at least this, else only
  // proven below it (DistanceError::settled; forward then a lower bound). For a question
  // like the layer plan's, whether D is within a tolerance, where the exact figure of a slab
  // well within it is not wanted. Default: never, the exact D.
  double settle_below = 0;
  // Surface points (indices into SlabSurface::points) whose corners are measured first, so
  // that with stop_above a region that loses is refuted on its first few points rather than
  // after most of them: the points farthest from another region's walls
  // (DistanceError::farthest), where this one's are mostly farthest too. The same D (or,
  // refuted, a lower bound above stop_above) in any order.
  std::span<const std::uint32_t> first_points = {};
  // How many of the points farthest from the walls to report in DistanceError::farthest.
  std::size_t farthest_count = 0;
  // Where the forward search keeps what it has measured, for a later call to go on from
  // (ForwardState); none: a scratch of the thread's, nothing kept.
  ForwardState* state = nullptr;
  // The forward search stops once every surface point's nearest wall is known (or, with
  // stop_above, once one is farther): `forward` is then the farthest corner's distance, a
  // lower bound on D, and `farthest` is reported. With a state, a later call for the same
  // surface, walls and missed islands given the same state searches the triangles without
  // measuring the corners again: the same D as one call measuring both (the corners'
  // distances do not depend on the order they are taken in), at a new stop_above.
  bool corners_only = false;
};

struct DistanceError {
  double forward = 0, reverse = 0, hausdorff = 0;
  // Forward D proven at most DistanceOptions::settle_below, not measured exactly: `forward`
  // is then a lower bound (and so is hausdorff).
  bool settled = false;
  // Up to DistanceOptions::farthest_count surface points (indices into SlabSurface::points)
  // farthest from the walls, farthest first, where every corner was measured (none where
  // the search stopped above stop_above, or where surface is measured to a missed island).
  std::vector<std::uint32_t> farthest;
};

// How the forward search takes a surface triangle: `side` -1 for a triangle, else k for one of
// no area, searched as its longest side from corner k to the next; `slack`, how far the
// distance inside it can rise above its farthest corner's by the bound of the distance being
// 1-Lipschitz: the longest side / sqrt(3) (a triangle), half the side (a side).
struct SurfaceShape {
  double slack;
  int side;
};

// What the distances are measured against, prepared once per slab and reused for every region.
struct SlabSurface {
  double z_lo = 0, z_hi = 0;
  // The surface seen from above: facets fanned into triangles; a horizontal facet's edges as
  // triangles of zero area (a, b, b).
  std::vector<std::array<Vec2, 3>> triangles;
  // Their corners once each (neighbouring facets share them), and each triangle's corners as
  // indices into it: the nearest wall is searched once per point.
  std::vector<Vec2> points;
  std::vector<std::array<std::uint32_t, 3>> corners;
  // Each triangle's shape, shared by every region measured (worked out per call where absent).
  std::vector<SurfaceShape> shapes;
  // ∂C(z) at each measured height, as segments (empty heights left out).
  std::vector<BoundaryGrid> levels;
};

SlabSurface slab_surface(const Slab& slab, const DistanceOptions& options = {});

// `walls`: a grid over the region's boundary (BoundaryGrid(region)); `missed`: the islands of
// the slab's footprint the region does not touch (missed_features.h).
DistanceError distance_error(const SlabSurface& surface, const BoundaryGrid& walls,
                             std::span<const BoundaryPair> missed,
                             const DistanceOptions& options = {});

// The level segments of the slab's facets at height z: from above (z_lo's convention) or from
// below (for z_hi). A facet lying in the plane z gives none.
std::vector<Segment2> surface_at(const Slab& slab, double z, bool from_above);

}  // namespace geometry
