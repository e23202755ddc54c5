#include "geometry/core/boundary_grid.h"

#include <array>
#include <cmath>
#include <limits>

namespace geometry {

namespace {

double distance_squared_to_segment(Vec2 p, const Segment2& s) {
  return squared_distance_to_segment(p, s.a, s.b);
}

}  // namespace

BoundaryGrid::BoundaryGrid(const Region& region) {
  std::size_t corners = 0;
  for (const Loop& loop : region.loops) corners += loop.size();
  // A loop gives at most one segment per corner: they are written in place and the vector
  // cut to them at the end (push_back's bookkeeping kept the loop's values out of registers).
  segments_.resize(corners);
  Segment2* const out = segments_.data();
  std::size_t count = 0;
  for (const Loop& loop : region.loops) {
    const std::size_t n = loop.size();
    if (n < 2) continue;
    const Vec2* const at = loop.data();
    // A vertex where the loop runs straight on (within a sine of 1e-12: 0.1 nm off the line
    // on a 10 cm edge) is no corner: its two edges are one segment. The segments join the
    // corners kept in turn, the last back to the first.
    const std::size_t before = count;
    std::size_t kept = 0;
    Vec2 first{}, last{};
    Vec2 u = at[0] - at[n - 1];
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 p = at[i];
      const Vec2 v = at[i + 1 == n ? 0 : i + 1] - p;
      const double c = cross(u, v);  // squared, against squared lengths: no roots per vertex
      const bool straight = dot(u, v) > 0 && c * c <= 1e-24 * dot(u, u) * dot(v, v);
      u = v;
      if (straight) continue;
      if (kept++ == 0) {
        first = p;
      } else if (!(last == p)) {
        out[count++] = {last, p};
      }
      last = p;
    }
    if (kept >= 2) {
      if (!(last == first)) out[count++] = {last, first};
      continue;
    }
    // Fewer than two corners: every edge as it stands.
    count = before;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 a = at[i], b = at[i + 1 == n ? 0 : i + 1];
      if (!(a == b)) out[count++] = {a, b};
    }
  }
  segments_.resize(count);
  build();
}

BoundaryGrid::BoundaryGrid(std::vector<Segment2> segments) : segments_(std::move(segments)) {
  build();
}

void BoundaryGrid::build() {
  if (segments_.empty()) return;
  Box2 box;
  double total_length = 0;
  for (const Segment2& s : segments_) {
    box.add(s.a);
    box.add(s.b);
    total_length += length(s.b - s.a);
  }
  const Vec2 lo = box.lo, hi = box.hi;
  const double width = std::max(hi.x - lo.x, 1e-9), height = std::max(hi.y - lo.y, 1e-9);
  // About two segments per occupied cell, but never more than ~4 cells per segment overall,
  // so that a long thin layer does not allocate a huge empty grid.
  const double mean = total_length / segments_.size();
  double cell = std::max(2.0 * mean, 1e-6);
  const double max_cells = 4.0 * segments_.size() + 16;
  if (width / cell * (height / cell) > max_cells) cell = std::sqrt(width * height / max_cells);
  cell_ = cell;
  inverse_cell_ = 1 / cell;
  origin_ = lo;
  nx_ = std::max(1, static_cast<int>(std::ceil(width / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(height / cell_)));

  // Counting sort of the segments into their cells' blocks: counted into cell_start_[c],
  // summed to each cell's end, then filled from the last segment down, so that each cell
  // lists its segments in increasing order and its start is left where its end was.
  // Most segments lie in one cell (three in four on the bunny's sections): those are
  // counted and placed by that cell's index alone, without the loops over a block (whose
  // set-up cost more than the one increment), the build's instructions a fifth fewer.
  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_;
  cell_start_.assign(cells + 1, 0);
  constexpr std::uint32_t kBlock = std::numeric_limits<std::uint32_t>::max();
  struct Span {
    std::uint32_t cell;  // the segment's one cell, or kBlock
    int x0, y0, x1, y1;
  };
  std::vector<Span> spans(segments_.size());  // each segment's cell or block of cells
  std::uint32_t* const start = cell_start_.data();
  for (std::size_t id = 0; id < segments_.size(); ++id) {
    const Segment2& s = segments_[id];
    const auto [x0, y0] = cell_of({std::min(s.a.x, s.b.x), std::min(s.a.y, s.b.y)});
    const auto [x1, y1] = cell_of({std::max(s.a.x, s.b.x), std::max(s.a.y, s.b.y)});
    if (x0 == x1 && y0 == y1) {
      const std::uint32_t c = static_cast<std::uint32_t>(y0 * nx_ + x0);
      spans[id].cell = c;
      ++start[c];
      continue;
    }
    spans[id] = {kBlock, x0, y0, x1, y1};
    for (int y = y0; y <= y1; ++y) {
      std::uint32_t* row = start + static_cast<std::size_t>(y) * nx_;
      for (int x = x0; x <= x1; ++x) ++row[x];
    }
  }
  for (std::size_t c = 1; c < cells; ++c) start[c] += start[c - 1];
  start[cells] = start[cells - 1];
  ids_.resize(start[cells]);
  std::uint32_t* const ids = ids_.data();
  for (std::uint32_t id = static_cast<std::uint32_t>(segments_.size()); id-- > 0;) {
    const Span& span = spans[id];
    if (span.cell != kBlock) {
      ids[--start[span.cell]] = id;
      continue;
    }
    for (int y = span.y0; y <= span.y1; ++y) {
      std::uint32_t* row = start + static_cast<std::size_t>(y) * nx_;
      for (int x = span.x0; x <= span.x1; ++x) ids[--row[x]] = id;
    }
  }
  // stamp_: on the first for_each_near.
}

double BoundaryGrid::nearest_distance(Vec2 p) const { return nearest(p).distance; }

bool BoundaryGrid::any_within(Vec2 p, double r) const {
  if (segments_.empty() || !(r > 0)) return false;
  const double r2 = r * r * (1 - 1e-12);
  const auto [cx, cy] = cell_of(p);
  // p's own cell first (the nearest segment is mostly there), then the rest of the block of
  // cells that holds every point within r.
  const auto near_in = [&](std::size_t c) {
    for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      if (distance_squared_to_segment(p, segments_[ids_[k]]) < r2) return true;
    }
    return false;
  };
  if (near_in(static_cast<std::size_t>(cy) * nx_ + cx)) return true;
  const auto [x0, y0] = cell_of({p.x - r, p.y - r});
  const auto [x1, y1] = cell_of({p.x + r, p.y + r});
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if ((x != cx || y != cy) && near_in(static_cast<std::size_t>(y) * nx_ + x)) return true;
    }
  }
  return false;
}

namespace {

// What BoundaryGrid::nearest reads of a grid, handed to the ring search by value.
struct GridCells {
  const std::uint32_t* start;  // cell_start_
  const std::uint32_t* ids;
  const Segment2* segments;
  Vec2 origin;
  double cell;
  int nx, ny;
};

// Cell c's segments nearer to p than best2, taken in the cell's order (the first of equally
// near ones stays).
inline void scan_cell(const GridCells& grid, std::size_t c, Vec2 p, double& best2,
                      std::uint32_t& segment) {
  const std::uint32_t end = grid.start[c + 1];
  for (std::uint32_t k = grid.start[c]; k < end; ++k) {
    const std::uint32_t id = grid.ids[k];
    const double d2 = distance_squared_to_segment(p, grid.segments[id]);
    if (d2 < best2) {
      best2 = d2;
      segment = id;
    }
  }
}

// Whether the block of cells within ring r of (cx, cy) holds the nearest segment: all
// beyond ring r is outside the block round p's (clamped) cell, at least r cells away and as
// far as p is from the block's sides when p is inside it; or the block is the whole grid.
inline bool settled(const GridCells& grid, Vec2 p, int cx, int cy, int r, double best2) {
  const int x0 = cx - r, x1 = cx + r, y0 = cy - r, y1 = cy + r;
  const double cell = grid.cell;
  const double left = p.x - (grid.origin.x + x0 * cell), right = grid.origin.x + (x1 + 1) * cell - p.x;
  const double below = p.y - (grid.origin.y + y0 * cell), above = grid.origin.y + (y1 + 1) * cell - p.y;
  const double reach = std::max(r * cell, std::min({left, right, below, above}));
  if (best2 <= reach * reach) return true;
  return x0 <= 0 && y0 <= 0 && x1 >= grid.nx - 1 && y1 >= grid.ny - 1;
}

// The rings from ring 1 on, each clipped to the grid, in one order: its top and bottom rows
// from left to right, then its sides from the top down. A call of its own, its arguments
// made only where p's own cell does not settle the search (three in ten on the bunny's best
// slice), so that the others stay short.
__attribute__((noinline)) void scan_rings(const GridCells grid, Vec2 p, int cx, int cy,
                                          double& best2, std::uint32_t& segment) {
  const auto visit_cell = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= grid.nx || y >= grid.ny) return;
    scan_cell(grid, static_cast<std::size_t>(y) * grid.nx + x, p, best2, segment);
  };
  for (int r = 1;; ++r) {
    const int x0 = cx - r, x1 = cx + r, y0 = cy - r, y1 = cy + r;
    for (int x = x0; x <= x1; ++x) {
      visit_cell(x, y0);
      visit_cell(x, y1);
    }
    for (int y = y0 + 1; y < y1; ++y) {
      visit_cell(x0, y);
      visit_cell(x1, y);
    }
    if (settled(grid, p, cx, cy, r, best2)) return;
  }
}

}  // namespace

BoundaryGrid::Nearest BoundaryGrid::nearest(Vec2 p) const {
  Nearest found{std::numeric_limits<double>::infinity(), Nearest::npos, p};
  if (segments_.empty()) return found;
  const auto [cx, cy] = cell_of(p);
  const GridCells grid{cell_start_.data(), ids_.data(), segments_.data(), origin_, cell_, nx_, ny_};
  double best2 = std::numeric_limits<double>::infinity();
  std::uint32_t segment = Nearest::npos;
  scan_cell(grid, static_cast<std::size_t>(cy) * nx_ + cx, p, best2, segment);  // ring 0
  if (!settled(grid, p, cx, cy, 0, best2)) scan_rings(grid, p, cx, cy, best2, segment);
  found.distance = std::sqrt(best2);
  found.segment = segment;
  found.foot = foot_on_segment(p, segments_[segment].a, segments_[segment].b);
  return found;
}

int BoundaryGrid::winding_number(Vec2 p, double* clearance) const {
  if (clearance) *clearance = cell_;
  if (segments_.empty()) return 0;
  const auto [cx, cy] = cell_of(p);
  if (clearance) {
    double best2 = cell_ * cell_;
    for_each_in_cells(std::max(cx - 1, 0), std::max(cy - 1, 0), std::min(cx + 1, nx_ - 1),
                      std::min(cy + 1, ny_ - 1), [&](std::uint32_t id) {
                        best2 = std::min(best2, distance_squared_to_segment(p, segments_[id]));
                      });
    *clearance = std::sqrt(best2);
  }
  int winding = 0;
  const std::size_t row = static_cast<std::size_t>(cy) * nx_;
  for (int x = cx; x < nx_; ++x) {
    const std::size_t c = row + x;
    for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      const Segment2& s = segments_[ids_[k]];
      const bool a_above = s.a.y > p.y, b_above = s.b.y > p.y;
      if (a_above == b_above) continue;
      const double t = (p.y - s.a.y) / (s.b.y - s.a.y);
      const double cross_x = s.a.x + t * (s.b.x - s.a.x);
      if (!(cross_x > p.x)) continue;
      // A segment spanning several cells is listed in each: count it in the cell holding its
      // crossing (cell_of clamps, so crossings left or right of the grid land in its ends).
      if (cell_of({cross_x, p.y}).first != x) continue;
      winding += b_above ? 1 : -1;
    }
  }
  return winding;
}

}  // namespace geometry
