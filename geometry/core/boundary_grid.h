// A uniform grid over a set of boundary segments (a region's walls, a cross-section's
// contours), for the queries the error metrics ask thousands of times per layer: which
// segments come near a small box, how far a point is from the nearest segment, and whether a
// point lies inside the region the segments bound (DESIGN.md §3).
//
// Input: segments in mm (a Region's loops, each edge directed as the loop runs, so the
// region's interior lies to the left of every segment), or free segments (no inside test).
// A loop's consecutive edges that run straight on are one segment: the same boundary, and a
// planar face cut by a section in many triangles (a box's side: 70 of the 74 edges of a
// section of tests/bench's arch) is one wall, which the distance error's search settles at
// once (distance_error.h: pieces whose corners share their nearest segment).
// The grid's cell size follows the mean segment length, so a query touches a handful of
// segments whatever the layer's size. Cost of building: one pass over the segments for the
// cell size, a counting sort of them into their cells (no copy of the counts), and the
// scratch of for_each_near only on its first call. Empty input: an empty grid; nearest_distance is then
// +infinity and winding_number 0.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "geometry/core/polygon.h"

namespace geometry {

struct Segment2 {
  Vec2 a, b;
};

class BoundaryGrid {
 public:
  BoundaryGrid() = default;
  explicit BoundaryGrid(const Region& region);
  explicit BoundaryGrid(std::vector<Segment2> segments);

  const std::vector<Segment2>& segments() const { return segments_; }
  bool empty() const { return segments_.empty(); }

  // Calls visit(index) once for every segment whose bounding box meets [lo, hi].
  // Not thread-safe on one grid (it marks visited segments); use one grid per thread.
  template <class Visit>
  void for_each_near(Vec2 lo, Vec2 hi, Visit&& visit) const;

  // Distance from p to the nearest segment, mm; +infinity for an empty grid.
  double nearest_distance(Vec2 p) const;

  // Whether some segment is nearer to p than r, which is cheaper to tell than how near the
  // nearest is: the first one found nearer ends the search. A segment about r away (within a
  // relative 1e-12) may go either way, so a caller that needs the sharp answer asks
  // nearest_distance where this says false. Empty grid: false.
  bool any_within(Vec2 p, double r) const;

  // The nearest segment to p, the nearest point on it, and the distance (mm). Empty grid:
  // segment = npos, distance +infinity.
  struct Nearest {
    static constexpr std::uint32_t npos = 0xffffffffu;
    double distance;
    std::uint32_t segment;
    Vec2 foot;
  };
  Nearest nearest(Vec2 p) const;

  // Winding number of the segments' loops around p (a ray to +x, half-open in y): 1 inside a
  // region's outer loop, 0 outside or inside a hole. Undefined for p exactly on a segment, so
  // it also reports in `clearance` a lower bound on p's distance to every segment, capped at
  // the cell size; callers treat a tiny value as "p is on the boundary".
  int winding_number(Vec2 p, double* clearance = nullptr) const;

 private:
  void build();
  // The cell holding p, clamped to the grid (points outside fall in the border cells). Not
  // std::floor: that is a call on baseline x86-64, and this runs for every query.
  std::pair<int, int> cell_of(Vec2 p) const {
    const auto clamp = [](double f, int n) {
      return f > 0 ? (f < n ? static_cast<int>(f) : n - 1) : 0;  // NaN gives 0
    };
    return {clamp((p.x - origin_.x) * inverse_cell_, nx_), clamp((p.y - origin_.y) * inverse_cell_, ny_)};
  }
  template <class Visit>
  void for_each_in_cells(int x0, int y0, int x1, int y1, Visit&& visit) const;

  std::vector<Segment2> segments_;
  Vec2 origin_{};
  double cell_ = 1, inverse_cell_ = 1;
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> cell_start_;  // CSR: segments of cell c are ids_[start[c]..start[c+1])
  std::vector<std::uint32_t> ids_;
  mutable std::vector<std::uint32_t> stamp_;  // for_each_near's, allocated on its first call
  mutable std::uint32_t epoch_ = 0;
};

template <class Visit>
void BoundaryGrid::for_each_in_cells(int x0, int y0, int x1, int y1, Visit&& visit) const {
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const std::size_t c = static_cast<std::size_t>(y) * nx_ + x;
      for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) visit(ids_[k]);
    }
  }
}

template <class Visit>
void BoundaryGrid::for_each_near(Vec2 lo, Vec2 hi, Visit&& visit) const {
  if (segments_.empty()) return;
  auto [x0, y0] = cell_of(lo);
  auto [x1, y1] = cell_of(hi);
  if (stamp_.size() != segments_.size()) stamp_.assign(segments_.size(), 0);
  if (++epoch_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    epoch_ = 1;
  }
  for_each_in_cells(x0, y0, x1, y1, [&](std::uint32_t id) {
    if (stamp_[id] == epoch_) return;
    stamp_[id] = epoch_;
    const Segment2& s = segments_[id];
    if (std::max(s.a.x, s.b.x) < lo.x || std::min(s.a.x, s.b.x) > hi.x ||
        std::max(s.a.y, s.b.y) < lo.y || std::min(s.a.y, s.b.y) > hi.y) {
      return;
    }
    visit(id);
  });
}

}  // namespace geometry
