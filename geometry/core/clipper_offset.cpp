// The toolpaths' offset (clipper.h): ClipperOffset's joins, most of its union left out; and
// proven_inside, proven_specks and proven_outside, on the grid of edges the offset checks
// its loops on.
#include "geometry/core/clipper_specks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <span>

#include "geometry/core/clipper_engine.h"

namespace geometry::clipper {

namespace {

// Round joins within this distance of the true arc: finer than any printer resolves, coarse
// enough that a 0.2 mm arc has a dozen points rather than thousands of nanometre steps.
constexpr double kArcTolerance = 0.005;  // mm

// A loop with less area than a micrometre square is a sliver of rounding, in nm^2.
constexpr double kNoArea = 1e6;

// The element after i and the one before it round a loop (a Path's points, or anything kept
// per vertex): the end of edge i, and the start of the edge that ends at i.
template <class Loop>
const auto& next_of(const Loop& loop, std::size_t i) {
  return loop[i + 1 < loop.size() ? i + 1 : 0];
}
template <class Loop>
const auto& prev_of(const Loop& loop, std::size_t i) {
  return loop[i > 0 ? i - 1 : loop.size() - 1];
}

struct Normal {
  double x, y;
};

// How one offset makes its joins; distances in units (nm).
struct Joins {
  ClipperLib::JoinType type;
  double delta;
  double miter_min;  // a mitre where 1 + cos(turn) is at least this, else a square end
  double steps_per_radian, step_sin, step_cos;  // round joins: the arc's chords
};

Joins joins_for(ClipperLib::JoinType type, double delta, double miter_limit) {
  Joins j{type, delta, miter_limit > 2 ? 2 / (miter_limit * miter_limit) : 0.5, 0, 0, 0};
  // Chords of the arc within the arc tolerance (a quarter of the radius at most), and no
  // more of them than the radius in units times pi.
  const double radius = std::abs(delta);
  const double tolerance = std::min(kArcTolerance * kClipperScale, radius / 4);
  const double steps = std::min(std::numbers::pi / std::acos(1 - tolerance / radius),
                                radius * std::numbers::pi);
  j.steps_per_radian = steps / (2 * std::numbers::pi);
  j.step_sin = std::sin(2 * std::numbers::pi / steps) * (delta < 0 ? -1 : 1);
  j.step_cos = std::cos(2 * std::numbers::pi / steps);
  return j;
}

ClipperLib::IntPoint moved(const ClipperLib::IntPoint& p, double dx, double dy) {
  return {p.X + rounded_units(dx), p.Y + rounded_units(dy)};
}

// Appends the raw offset of one closed loop (no repeated points, at least 3) to `out`, as
// Clipper's offsetter draws it: each edge moved along its normal, joined round the vertices
// the offset turns away from, and, where the moved edges cross (the offset's inner side of
// a vertex), back through the vertex, a small loop the union with the positive (growing) or
// negative (shrinking) fill rule removes. Except where the moved edges cross within the
// first half of each: there they are joined at their crossing (the mitre point), which is
// what that union makes of the loop, without the crossing and two points per vertex it
// costs the union to find out. (A curved edge of n vertices has n such crossings, on the
// inner side of every offset.) Returns whether it went back through a vertex anywhere.
// `normal` and `length` are room for the edges' normals and lengths, the caller's to reuse.
bool raw_offset(const Path& loop, const Joins& j, Path& out, std::vector<Normal>& normal,
                std::vector<double>& length) {
  const std::size_t n = loop.size();
  // Each edge's length and unit normal on its right (outward on a CCW loop).
  normal.resize(n);
  length.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = loop[i];
    const auto& b = next_of(loop, i);
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
    length[i] = std::sqrt(dx * dx + dy * dy);  // no overflow: nm on a bed
    normal[i] = length[i] > 0 ? Normal{dy / length[i], -dx / length[i]} : Normal{0, 0};
  }
  const double delta = j.delta;
  bool back = false;
  for (std::size_t v = 0, e = n - 1; v < n; e = v, ++v) {  // vertex v, edge e before it
    const ClipperLib::IntPoint& p = loop[v];
    const Normal a = normal[e], b = normal[v];
    double sin_turn = a.x * b.y - b.x * a.y;
    const double cos_turn = a.x * b.x + a.y * b.y;
    if (std::abs(sin_turn * delta) < 1) {
      if (cos_turn > 0) {  // straight on, within a unit
        out.push_back(moved(p, a.x * delta, a.y * delta));
        continue;
      }
    } else {
      sin_turn = std::clamp(sin_turn, -1.0, 1.0);
    }
    const double r = 1 + cos_turn;
    if (sin_turn * delta < 0) {
      // The moved edges cross at the mitre point, cut back by this from their ends.
      const double cut = std::abs(delta * sin_turn) / r;
      if (r > 0 && 2 * cut <= std::min(length[e], length[v])) {
        out.push_back(moved(p, (a.x + b.x) * delta / r, (a.y + b.y) * delta / r));
      } else {
        out.push_back(moved(p, a.x * delta, a.y * delta));
        out.push_back(p);
        out.push_back(moved(p, b.x * delta, b.y * delta));
        back = true;
      }
      continue;
    }
    if (j.type == ClipperLib::jtRound) {
      const double angle = std::atan2(sin_turn, cos_turn);
      const int steps = std::max(static_cast<int>(std::llround(j.steps_per_radian *
                                                               std::abs(angle))), 1);
      double x = a.x, y = a.y;
      for (int s = 0; s < steps; ++s) {
        out.push_back(moved(p, x * delta, y * delta));
        const double x0 = x;
        x = x * j.step_cos - j.step_sin * y;
        y = x0 * j.step_sin + y * j.step_cos;
      }
      out.push_back(moved(p, b.x * delta, b.y * delta));
    } else if (j.type == ClipperLib::jtMiter && r >= j.miter_min) {
      out.push_back(moved(p, (a.x + b.x) * delta / r, (a.y + b.y) * delta / r));
    } else {  // square: cut across at delta from the vertex
      const double t = std::tan(std::atan2(sin_turn, cos_turn) / 4);
      out.push_back(moved(p, delta * (a.x - a.y * t), delta * (a.y + a.x * t)));
      out.push_back(moved(p, delta * (b.x + b.y * t), delta * (b.y - b.x * t)));
    }
  }
  return back;
}

// Exact side of c from the line a -> b: 1 left, -1 right, 0 on it.
int side(const ClipperLib::IntPoint& a, const ClipperLib::IntPoint& b,
         const ClipperLib::IntPoint& c) {
  const __int128 v = static_cast<__int128>(b.X - a.X) * (c.Y - a.Y) -
                     static_cast<__int128>(b.Y - a.Y) * (c.X - a.X);
  return (v > 0) - (v < 0);
}

// Whether c, on the line through a and b, lies on the segment [a, b].
bool within(const ClipperLib::IntPoint& a, const ClipperLib::IntPoint& b,
            const ClipperLib::IntPoint& c) {
  return std::min(a.X, b.X) <= c.X && c.X <= std::max(a.X, b.X) && std::min(a.Y, b.Y) <= c.Y &&
         c.Y <= std::max(a.Y, b.Y);
}

// Whether the segments [a, b] and [c, d], whose bounding boxes meet, have a point in common.
bool meet_within_boxes(const ClipperLib::IntPoint& a, const ClipperLib::IntPoint& b,
                       const ClipperLib::IntPoint& c, const ClipperLib::IntPoint& d) {
  const int s1 = side(a, b, c), s2 = side(a, b, d), s3 = side(c, d, a), s4 = side(c, d, b);
  if (s1 * s2 < 0 && s3 * s4 < 0) return true;
  return (s1 == 0 && within(a, b, c)) || (s2 == 0 && within(a, b, d)) ||
         (s3 == 0 && within(c, d, a)) || (s4 == 0 && within(c, d, b));
}

// Winding number of the loop round p, which is not on it.
int winding(const Path& loop, const ClipperLib::IntPoint& p) {
  int w = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const auto& a = loop[i];
    const auto& b = loop[(i + 1) % n];
    if (a.Y <= p.Y) {
      if (b.Y > p.Y && side(a, b, p) > 0) ++w;
    } else if (b.Y <= p.Y && side(a, b, p) < 0) {
      --w;
    }
  }
  return w;
}

// A grid of square cells over `box`, about one edge per cell for `edges` edges.
struct EdgeGrid {
  EdgeGrid(const ClipperLib::IntRect& b, std::size_t edges) : box(b) {
    const double w = double(box.right - box.left) + 1, h = double(box.bottom - box.top) + 1;
    cell = std::max(std::sqrt(w * h / double(edges)), 1.0);
    columns = static_cast<std::int64_t>(w / cell) + 1;
  }
  std::int64_t column(ClipperLib::cInt x) const {
    return static_cast<std::int64_t>(double(x - box.left) / cell);
  }
  std::int64_t row(ClipperLib::cInt y) const {
    return static_cast<std::int64_t>(double(y - box.top) / cell);
  }

  ClipperLib::IntRect box;
  double cell = 1;
  std::int64_t columns = 1;
};

// An edge (from vertex `edge` of loop `loop`) with its bounding box and the columns and rows
// of the cells that cover it.
struct GridEdge {
  ClipperLib::cInt left, right, top, bottom;
  std::uint32_t loop, edge;
  std::uint32_t c0, c1, r0, r1;
};

// The loops' edges on a grid: each cell c holds the edges whose bounding boxes cover it,
// edges[index[start[c]]] to edges[index[start[c + 1] - 1]], in the loops' order.
struct EdgeCells {
  explicit EdgeCells(const EdgeGrid& g) : grid(g) {}
  EdgeGrid grid;
  std::vector<GridEdge> edges;
  std::vector<std::uint32_t> start, index;
};

// With start[c] holding how many edges cover cell c (of `cell_count`, `columns` to a row):
// start[c] becomes where cell c ends, then, placing the edges from the last down each just
// before the last placed in its cell, where it begins: every cell's edges in the order of
// `edges`.
void place_edges(EdgeCells& cells, std::size_t columns, std::size_t cell_count) {
  for (std::size_t c = 1; c <= cell_count; ++c) cells.start[c] += cells.start[c - 1];
  cells.index.resize(cells.start[cell_count]);
  for (std::size_t k = cells.edges.size(); k-- > 0;) {
    const GridEdge& edge = cells.edges[k];
    for (std::size_t r = edge.r0; r <= edge.r1; ++r) {
      for (std::size_t c = edge.c0; c <= edge.c1; ++c) {
        cells.index[--cells.start[r * columns + c]] = static_cast<std::uint32_t>(k);
      }
    }
  }
}

// The loops' edges (`count` of them) in the cells their bounding boxes cover (a counting sort:
// the cells are about as many as the edges); false if an edge covers more than 64 cells (a
// long edge: left to the union).
bool fill_cells(std::span<const Path> loops, std::size_t count, EdgeCells& cells) {
  const EdgeGrid& grid = cells.grid;
  const auto rows = static_cast<std::size_t>(grid.row(grid.box.bottom) + 1);
  const std::size_t cell_count = rows * static_cast<std::size_t>(grid.columns);
  cells.edges.reserve(count);
  cells.start.assign(cell_count + 1, 0);
  for (std::uint32_t l = 0; l < loops.size(); ++l) {
    const Path& loop = loops[l];
    const auto n = static_cast<std::uint32_t>(loop.size());
    for (std::uint32_t i = 0; i < n; ++i) {
      const auto& a = loop[i];
      const auto& b = next_of(loop, i);
      const ClipperLib::cInt left = std::min(a.X, b.X), right = std::max(a.X, b.X);
      const ClipperLib::cInt top = std::min(a.Y, b.Y), bottom = std::max(a.Y, b.Y);
      const auto c0 = grid.column(left), c1 = grid.column(right);
      const auto r0 = grid.row(top), r1 = grid.row(bottom);
      if ((c1 - c0 + 1) * (r1 - r0 + 1) > 64) return false;
      for (auto r = r0; r <= r1; ++r) {
        for (auto c = c0; c <= c1; ++c) ++cells.start[static_cast<std::size_t>(r * grid.columns + c)];
      }
      cells.edges.push_back({left, right, top, bottom, l, i, static_cast<std::uint32_t>(c0),
                             static_cast<std::uint32_t>(c1), static_cast<std::uint32_t>(r0),
                             static_cast<std::uint32_t>(r1)});
    }
  }
  place_edges(cells, static_cast<std::size_t>(grid.columns), cell_count);
  return true;
}

// Calls visit(p, q) for every two edges whose bounding boxes meet, p before q in the loops'
// order, once each (in the cell of the corner of least x and y of the boxes' overlap), until
// it returns true; returns whether it did.
template <class Visit>
bool any_pair_near(const EdgeCells& cells, Visit&& visit) {
  const auto columns = static_cast<std::size_t>(cells.grid.columns);
  const std::size_t cell_count = cells.start.size() - 1;
  for (std::size_t c = 0; c < cell_count; ++c) {
    const std::uint32_t first = cells.start[c], last = cells.start[c + 1];
    if (last - first < 2) continue;
    for (std::uint32_t i = first; i < last; ++i) {
      const GridEdge& p = cells.edges[cells.index[i]];
      for (std::uint32_t k = i + 1; k < last; ++k) {
        const GridEdge& q = cells.edges[cells.index[k]];
        if (p.right < q.left || q.right < p.left || p.bottom < q.top || q.bottom < p.top) continue;
        // The corner's cell: columns and rows grow with x and y.
        const std::size_t corner = std::size_t{std::max(p.r0, q.r0)} * columns + std::max(p.c0, q.c0);
        if (corner != c) continue;
        if (visit(p, q)) return true;
      }
    }
  }
  return false;
}

// Whether two edges of the loops meet other than neighbours at their common end.
bool any_edges_meet(const Paths& loops, const EdgeCells& cells) {
  return any_pair_near(cells, [&](const GridEdge& p, const GridEdge& q) {
    const Path& lp = loops[p.loop];
    const Path& lq = loops[q.loop];
    const std::uint32_t f = p.edge, e = q.edge;
    const auto np = static_cast<std::uint32_t>(lp.size()), nq = static_cast<std::uint32_t>(lq.size());
    const auto& a = lp[f];
    const auto& b = next_of(lp, f);
    const auto& c = lq[e];
    const auto& d = next_of(lq, e);
    const bool f_first = p.loop == q.loop && (f + 1 < np ? f + 1 : 0) == e;
    const bool e_first = p.loop == q.loop && (e + 1 < nq ? e + 1 : 0) == f;
    if (f_first || e_first) {
      // Neighbours share an end; they meet elsewhere only folding back along a line: in line,
      // the shared end not between the other two.
      const auto& from = f_first ? a : c;
      const auto& shared = f_first ? b : d;
      const auto& to = f_first ? d : b;
      return side(from, shared, to) == 0 && !within(from, to, shared);
    }
    return meet_within_boxes(a, b, c, d);
  });
}

// Calls visit(loop of a, edge of a, loop of b, edge of b) for each edge of `a` that meets an
// edge of `b`, where both sets' edges are tested within the box `within` (where their boxes
// overlap): on a grid over it, the edges of each cut to it, about one edge per cell. Until it
// returns true; returns whether it did, or nullopt where an edge covers more than 64 cells (a
// long edge across it).
template <class Visit>
std::optional<bool> each_meeting(const Paths& a, const Paths& b, const ClipperLib::IntRect& within,
                                 Visit&& visit) {
  const auto near = [&](const ClipperLib::IntPoint& p, const ClipperLib::IntPoint& q) {
    return std::max(p.X, q.X) >= within.left && std::min(p.X, q.X) <= within.right &&
           std::max(p.Y, q.Y) >= within.top && std::min(p.Y, q.Y) <= within.bottom;
  };
  std::size_t count = 0;
  for (const Paths* set : {&a, &b}) {
    for (const Path& loop : *set) {
      for (std::size_t i = 0, n = loop.size(); i < n; ++i) count += near(loop[i], next_of(loop, i));
    }
  }
  if (count == 0) return false;
  EdgeCells cells{EdgeGrid(within, count)};
  const EdgeGrid& grid = cells.grid;
  const auto columns = static_cast<std::size_t>(grid.columns);
  const auto rows = static_cast<std::size_t>(grid.row(within.bottom) + 1);
  cells.edges.reserve(count);
  cells.start.assign(rows * columns + 1, 0);
  // The edges of a, then b's (loop numbers of b's past a's): in each cell a's come first.
  const auto a_loops = static_cast<std::uint32_t>(a.size());
  for (const Paths* set : {&a, &b}) {
    const std::uint32_t first_loop = set == &a ? 0 : a_loops;
    for (std::uint32_t l = 0; l < set->size(); ++l) {
      const Path& loop = (*set)[l];
      const auto n = static_cast<std::uint32_t>(loop.size());
      for (std::uint32_t i = 0; i < n; ++i) {
        const auto& p = loop[i];
        const auto& q = next_of(loop, i);
        if (!near(p, q)) continue;
        const ClipperLib::cInt left = std::min(p.X, q.X), right = std::max(p.X, q.X);
        const ClipperLib::cInt top = std::min(p.Y, q.Y), bottom = std::max(p.Y, q.Y);
        const auto c0 = grid.column(std::max(left, within.left));
        const auto c1 = grid.column(std::min(right, within.right));
        const auto r0 = grid.row(std::max(top, within.top));
        const auto r1 = grid.row(std::min(bottom, within.bottom));
        if ((c1 - c0 + 1) * (r1 - r0 + 1) > 64) return std::nullopt;
        for (auto r = r0; r <= r1; ++r) {
          for (auto c = c0; c <= c1; ++c) ++cells.start[static_cast<std::size_t>(r) * columns + static_cast<std::size_t>(c)];
        }
        cells.edges.push_back({left, right, top, bottom, first_loop + l, i, static_cast<std::uint32_t>(c0),
                               static_cast<std::uint32_t>(c1), static_cast<std::uint32_t>(r0),
                               static_cast<std::uint32_t>(r1)});
      }
    }
  }
  const std::size_t cell_count = rows * columns;
  place_edges(cells, columns, cell_count);
  for (std::size_t c = 0; c < cell_count; ++c) {
    const std::uint32_t first = cells.start[c], last = cells.start[c + 1];
    std::uint32_t split = first;
    while (split < last && cells.edges[cells.index[split]].loop < a_loops) ++split;
    for (std::uint32_t i = first; i < split; ++i) {
      const GridEdge& p = cells.edges[cells.index[i]];
      const Path& lp = a[p.loop];
      for (std::uint32_t k = split; k < last; ++k) {
        const GridEdge& q = cells.edges[cells.index[k]];
        if (p.right < q.left || q.right < p.left || p.bottom < q.top || q.bottom < p.top) continue;
        // Once per pair: in the cell of the corner of least x and y of the boxes' overlap.
        if (std::size_t{std::max(p.r0, q.r0)} * columns + std::max(p.c0, q.c0) != c) continue;
        const Path& lq = b[q.loop - a_loops];
        if (meet_within_boxes(lp[p.edge], next_of(lp, p.edge), lq[q.edge], next_of(lq, q.edge)) &&
            visit(p.loop, p.edge, q.loop - a_loops, q.edge)) {
          return true;
        }
      }
    }
  }
  return false;
}

// Whether an edge of `a` meets an edge of `b` (each_meeting's grid); nullopt where an edge
// covers more than 64 cells of it.
std::optional<bool> sets_meet(const Paths& a, const Paths& b, const ClipperLib::IntRect& within) {
  return each_meeting(a, b, within, [](std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t) {
    return true;
  });
}

// The non-zero winding number of the loops round p, which is on none of them (`boxes`: the
// loops' bounding boxes).
int winding_of(const Paths& loops, const std::vector<ClipperLib::IntRect>& boxes,
               const ClipperLib::IntPoint& p) {
  int w = 0;
  for (std::size_t m = 0; m < loops.size(); ++m) {
    const ClipperLib::IntRect& b = boxes[m];
    if (p.X < b.left || p.X > b.right || p.Y < b.top || p.Y > b.bottom) continue;
    w += winding(loops[m], p);
  }
  return w;
}

// Whether the others wind 0 times round each outer loop's first point and once round each
// hole's (`boxes`: the loops' bounding boxes).
bool windings_agree(const Paths& loops, const std::vector<char>& outer,
                    const std::vector<ClipperLib::IntRect>& boxes) {
  for (std::size_t l = 0; l < loops.size(); ++l) {
    const ClipperLib::IntPoint& p = loops[l][0];
    int w = 0;
    for (std::size_t m = 0; m < loops.size(); ++m) {
      const ClipperLib::IntRect& b = boxes[m];
      if (m == l || p.X < b.left || p.X > b.right || p.Y < b.top || p.Y > b.bottom) continue;
      w += winding(loops[m], p);
    }
    if (w != (outer[l] ? 0 : 1)) return false;
  }
  return true;
}

// Whether loops (no repeated points, at least 3 each) are a region as they stand: no two
// edges meet but neighbours at their common end, each loop runs the way `outer` says (CCW
// for an outer loop), and outer loops lie where the others wind 0 times, holes where they
// wind once. Then the union of their positive winding is the loops themselves. Edges are
// compared only with those sharing a cell of a grid about one edge per cell.
bool already_a_region(const Paths& loops, const std::vector<char>& outer) {
  std::size_t edges = 0;
  ClipperLib::IntRect box = bounding_box(Path{});
  std::vector<ClipperLib::IntRect> boxes;
  boxes.reserve(loops.size());
  for (std::size_t l = 0; l < loops.size(); ++l) {
    const Path& loop = loops[l];
    if ((ClipperLib::Area(loop) > 0) != bool(outer[l])) return false;
    boxes.push_back(bounding_box(loop));
    add_to_box(box, boxes.back());
    edges += loop.size();
  }
  EdgeCells cells{EdgeGrid(box, edges)};
  if (!fill_cells(loops, edges, cells) || any_edges_meet(loops, cells)) return false;
  return windings_agree(loops, outer, boxes);
}

// Where the edges [a, b] and [c, d] cross as Clipper's union computes it (IntersectPoint in
// clipper.cpp: each edge as its lower end and the x it gains per unit of y, the crossing's y
// rounded, then x from the steeper of the two), into `at`; false where Clipper would take
// another branch (an edge level or upright, the two as steep) or pull the point back into
// the scanbeam (it lies outside either edge's span of y).
bool clipper_crossing(const ClipperLib::IntPoint& a, const ClipperLib::IntPoint& b,
                      const ClipperLib::IntPoint& c, const ClipperLib::IntPoint& d,
                      ClipperLib::IntPoint& at) {
  if (a.Y == b.Y || c.Y == d.Y || a.X == b.X || c.X == d.X) return false;
  // Clipper's edge: Bot the end of greater y, Top the other, Dx = dx / dy from Bot to Top.
  const ClipperLib::IntPoint& bot1 = a.Y > b.Y ? a : b;
  const ClipperLib::IntPoint& top1 = a.Y > b.Y ? b : a;
  const ClipperLib::IntPoint& bot2 = c.Y > d.Y ? c : d;
  const ClipperLib::IntPoint& top2 = c.Y > d.Y ? d : c;
  const double dx1 = double(top1.X - bot1.X) / double(top1.Y - bot1.Y);
  const double dx2 = double(top2.X - bot2.X) / double(top2.Y - bot2.Y);
  if (std::abs(dx1) == std::abs(dx2)) return false;
  const double b1 = double(bot1.X) - double(bot1.Y) * dx1;
  const double b2 = double(bot2.X) - double(bot2.Y) * dx2;
  const double q = (b2 - b1) / (dx1 - dx2);
  at.Y = clipper_rounded(q);
  at.X = std::abs(dx1) < std::abs(dx2) ? clipper_rounded(dx1 * q + b1) : clipper_rounded(dx2 * q + b2);
  return at.Y > std::max(top1.Y, top2.Y) && at.Y < std::min(bot1.Y, bot2.Y);
}

// Twice the signed area of a loop (CCW positive), exactly.
__int128 twice_area(const Path& loop) {
  __int128 sum = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const auto& a = loop[i];
    const auto& b = next_of(loop, i);
    sum += static_cast<__int128>(a.X) * b.Y - static_cast<__int128>(b.X) * a.Y;
  }
  return sum;
}

// Whether some vertex of the loop lies on the line through its neighbours (Clipper's union
// drops such vertices, from its input and its output).
bool any_in_line(const Path& loop) {
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    if (side(prev_of(loop, i), loop[i], next_of(loop, i)) == 0) return true;
  }
  return false;
}

// The crossings of one loop's edges, as pairs of edge indices (first < second), of a loop with
// no vertex in line with its neighbours (any_in_line: then neighbours meet only at their
// common end); false where edges meet otherwise (touching) or an edge is long for the grid
// (fill_cells).
bool edge_crossings(const Path& loop, std::vector<std::pair<std::uint32_t, std::uint32_t>>& crossings) {
  const std::uint32_t n = static_cast<std::uint32_t>(loop.size());
  EdgeCells cells{EdgeGrid(bounding_box(loop), n)};
  if (!fill_cells({&loop, 1}, n, cells)) return false;
  const bool touching = any_pair_near(cells, [&](const GridEdge& p, const GridEdge& q) {
    const std::uint32_t f = p.edge, e = q.edge;  // f < e
    if (f + 1 == e || (f == 0 && e + 1 == n)) return false;  // neighbours
    const auto& a = loop[f];
    const auto& b = loop[f + 1];
    const auto& c = loop[e];
    const auto& d = next_of(loop, e);
    const int s1 = side(a, b, c), s2 = side(a, b, d), s3 = side(c, d, a), s4 = side(c, d, b);
    if (s1 * s2 < 0 && s3 * s4 < 0) {
      crossings.emplace_back(f, e);
      return false;
    }
    return (s1 == 0 && within(a, b, c)) || (s2 == 0 && within(a, b, d)) ||
           (s3 == 0 && within(c, d, a)) || (s4 == 0 && within(c, d, b));
  });
  if (touching) return false;
  std::sort(crossings.begin(), crossings.end());
  return true;
}


// Where a loop's edge [a, b] (not level) lies at height y, as Clipper's sweep places it
// (TopX: from its end of greater y, the x it gains per unit of y, rounded), and the sign of
// its exact x there minus that of [c, d]'s.
ClipperLib::cInt clipper_x(const ClipperLib::IntPoint& a, const ClipperLib::IntPoint& b,
                           ClipperLib::cInt y) {
  const ClipperLib::IntPoint& bot = a.Y > b.Y ? a : b;
  const ClipperLib::IntPoint& top = a.Y > b.Y ? b : a;
  if (y == top.Y) return top.X;
  const double dx = double(top.X - bot.X) / double(top.Y - bot.Y);
  return bot.X + clipper_rounded(dx * double(y - bot.Y));
}

int exact_x_order(const ClipperLib::IntPoint& a, const ClipperLib::IntPoint& b,
                  const ClipperLib::IntPoint& c, const ClipperLib::IntPoint& d, ClipperLib::cInt y) {
  // x of [a, b] at y times (b.Y - a.Y): a.X (b.Y - a.Y) + (y - a.Y) (b.X - a.X); the same for
  // [c, d]; compared over the product of the two heights, made positive.
  const __int128 h1 = b.Y - a.Y, h2 = d.Y - c.Y;
  const __int128 x1 = static_cast<__int128>(a.X) * h1 + static_cast<__int128>(y - a.Y) * (b.X - a.X);
  const __int128 x2 = static_cast<__int128>(c.X) * h2 + static_cast<__int128>(y - c.Y) * (d.X - c.X);
  __int128 v = x1 * h2 - x2 * h1;
  if (h1 * h2 < 0) v = -v;
  return (v > 0) - (v < 0);
}

// Whether Clipper's sweep finds the crossing of [a, b] and [c, d] (at height y, off every
// vertex's y by more than a unit) within the scanbeam it lies in, from `bottom` to `top`
// (the nearest vertices' y around it): the two edges' rounded x in their exact order at both
// ends of it, unequal, the other way round at the top. (Where they round alike at the top,
// the sweep finds the crossing in the next scanbeam, at another point.)
bool swept_as_crossing(const ClipperLib::IntPoint& a, const ClipperLib::IntPoint& b,
                       const ClipperLib::IntPoint& c, const ClipperLib::IntPoint& d,
                       ClipperLib::cInt bottom, ClipperLib::cInt top) {
  const int at_bottom = exact_x_order(a, b, c, d, bottom);
  const int at_top = exact_x_order(a, b, c, d, top);
  if (at_bottom == 0 || at_top != -at_bottom) return false;
  const auto order = [](ClipperLib::cInt p, ClipperLib::cInt q) { return (p > q) - (p < q); };
  return order(clipper_x(a, b, bottom), clipper_x(c, d, bottom)) == at_bottom &&
         order(clipper_x(a, b, top), clipper_x(c, d, top)) == at_top;
}

// A crossing of the loop's edge with another, as it lies on the edge: where along it
// (num / den of the way from its start, den > 0), the crossing's index, and whether the
// other edge crosses it from its right to its left.
struct EdgeCrossing {
  std::uint32_t edge, crossing;
  __int128 num, den;
  bool from_right;
};

// The crossings on edge [a, b] of the edge [c, d] that crosses it, placed along it.
EdgeCrossing crossing_on(std::uint32_t edge, std::uint32_t crossing, const ClipperLib::IntPoint& a,
                         const ClipperLib::IntPoint& b, const ClipperLib::IntPoint& c,
                         const ClipperLib::IntPoint& d) {
  const __int128 dx = d.X - c.X, dy = d.Y - c.Y;
  __int128 num = static_cast<__int128>(c.X - a.X) * dy - static_cast<__int128>(c.Y - a.Y) * dx;
  __int128 den = static_cast<__int128>(b.X - a.X) * dy - static_cast<__int128>(b.Y - a.Y) * dx;
  const bool from_right = den > 0;
  if (den < 0) {
    num = -num;
    den = -den;
  }
  return {edge, crossing, num, den, from_right};
}

// The point of a (non-empty) loop's least y, if no other point shares that y.
std::optional<std::size_t> lone_least_y(const Path& loop) {
  std::size_t low = 0;
  bool tie = false;
  for (std::size_t k = 1; k < loop.size(); ++k) {
    if (loop[k].Y < loop[low].Y) {
      low = k;
      tie = false;
    } else if (loop[k].Y == loop[low].Y) {
      tie = true;
    }
  }
  if (tie) return std::nullopt;
  return low;
}

// `loop` rotated to start where Clipper's union starts a lone loop: at the point after its
// least y. False (and `loop` as it was) where two points share the least y, which Clipper
// settles by an order this does not reproduce.
bool started_as_clipper_starts(Path& loop) {
  const std::optional<std::size_t> low = lone_least_y(loop);
  if (!low) return false;
  std::rotate(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>((*low + 1) % loop.size()), loop.end());
  return true;
}

// The loop with its folds cut off. Each crossing of edges i < j cuts off the piece between
// them (the ends of i and j past the crossing, and edges i + 1 to j - 1), which must be
// simple (no crossing shares an edge with another or lies within another's piece, and the
// piece does not wrap past vertex 0) and where it changes nothing: running CCW and inside
// what is left (adding to a winding of 1; the loop turns right at the crossing), or CW and
// outside it (taking from a winding of 0; the loop turns left). What is left, with the
// crossings as points (clipper_crossing), is the union, started at the vertex after its least
// y. False where a fold is not simple, a crossing lies within a unit of a vertex's y, or a
// point at a cut repeats or is in line with its neighbours.
bool cut_folds(const Path& raw, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& crossings,
               Path& out) {
  const std::size_t n = raw.size();
  out.clear();
  out.reserve(n);
  std::vector<ClipperLib::cInt> at_y;  // the crossings' y, to keep off the scanbeams
  std::vector<std::size_t> at_index;   // where each crossing is in `out`
  std::size_t next = 0;                // the first vertex not yet taken
  Path piece;
  for (const auto& [i, j] : crossings) {
    if (i < next || 2 * (j - i) > n) return false;  // shares an edge, or no small piece
    ClipperLib::IntPoint at;
    if (!clipper_crossing(raw[i], raw[i + 1], raw[j], raw[(j + 1) % n], at)) return false;
    piece.assign(raw.begin() + i + 1, raw.begin() + j + 1);
    piece.push_back(at);
    const __int128 area = twice_area(piece);
    const auto& c = raw[j];
    const auto& d = raw[(j + 1) % n];
    const __int128 cross = static_cast<__int128>(raw[i + 1].X - raw[i].X) * (d.Y - c.Y) -
                           static_cast<__int128>(raw[i + 1].Y - raw[i].Y) * (d.X - c.X);
    if (!((cross < 0 && area > 0) || (cross > 0 && area < 0))) return false;
    out.insert(out.end(), raw.begin() + next, raw.begin() + i + 1);
    at_index.push_back(out.size());
    out.push_back(at);
    at_y.push_back(at.Y);
    next = j + 1;
  }
  out.insert(out.end(), raw.begin() + next, raw.end());
  const std::size_t m = out.size();
  if (m < 3 || twice_area(out) <= 0) return false;
  // No crossing within a unit of a vertex's y; no point repeated or in line with its
  // neighbours where the loop was cut (elsewhere the neighbours are the raw loop's).
  std::sort(at_y.begin(), at_y.end());
  for (const auto& p : raw) {
    const auto near = std::lower_bound(at_y.begin(), at_y.end(), p.Y - 1);
    if (near != at_y.end() && *near <= p.Y + 1) return false;
  }
  for (const std::size_t k : at_index) {
    for (const std::size_t v : {k + m - 1, k, k + 1}) {
      const auto& a = out[(v + m - 1) % m];
      const auto& b = out[v % m];
      const auto& c = out[(v + 1) % m];
      if (a == b || b == c || side(a, b, c) == 0) return false;
    }
  }
  return started_as_clipper_starts(out);
}


// The union's boundary traced: the crossings placed along both their edges, which they cut
// into pieces. Each piece's right side has a winding number: 0 or -1 at the lowest vertex
// (its outer side, as the loop turns there), one less past a crossing by an edge from the
// right, one more past one from the left, the same round a vertex. The union's boundary is
// the pieces with 0 on their right (1 on their left), and it turns onto the crossing edge at
// every crossing it meets: traced from one such piece, it must take all of them (else the
// union has more than one loop, or holes). It is Clipper's very loop where the crossings are
// computed as Clipper computes them (clipper_crossing) and its sweep finds each where it lies
// (swept_as_crossing: off every vertex's y by more than a unit, the edges' rounded x in order
// at the scanbeam's ends), no two on an edge or on the boundary within a unit of y of each
// other (the sweep takes them in the order of their rounded y), no point of the union repeats
// or is in line with its neighbours (Clipper drops those), and it starts where Clipper's
// union starts a lone loop: at the point after its least y. Found by comparing with Clipper
// (the offsets of the bunny's slices and the benchmark models, random tangles in the tests),
// where each of these conditions was seen to matter but the last two. False where any fails.
bool traced_boundary(const Path& raw,
                     const std::vector<std::pair<std::uint32_t, std::uint32_t>>& crossings,
                     Path& out) {
  const std::size_t n = raw.size();
  if (n >= (std::size_t{1} << 30)) return false;
  // Coordinates within 2^30 units keep the crossings' places exact in 128 bits.
  const ClipperLib::IntRect box = bounding_box(raw);
  constexpr ClipperLib::cInt kReach = ClipperLib::cInt{1} << 30;
  if (box.left <= -kReach || box.right >= kReach || box.top <= -kReach || box.bottom >= kReach) {
    return false;
  }
  const std::size_t count = crossings.size();
  std::vector<ClipperLib::IntPoint> at(count);
  std::vector<EdgeCrossing> on;  // by edge, then along it
  on.reserve(2 * count);
  for (std::uint32_t c = 0; c < count; ++c) {
    const auto [i, j] = crossings[c];
    if (!clipper_crossing(raw[i], next_of(raw, i), raw[j], next_of(raw, j), at[c])) return false;
    on.push_back(crossing_on(i, c, raw[i], next_of(raw, i), raw[j], next_of(raw, j)));
    on.push_back(crossing_on(j, c, raw[j], next_of(raw, j), raw[i], next_of(raw, i)));
  }
  bool tied = false;
  std::sort(on.begin(), on.end(), [&](const EdgeCrossing& p, const EdgeCrossing& q) {
    if (p.edge != q.edge) return p.edge < q.edge;
    const __int128 l = p.num * q.den, r = q.num * p.den;
    if (l == r) tied = true;
    return l < r;
  });
  if (tied) return false;  // three edges through one point
  // Crossings along an edge at least two units apart in y: Clipper's sweep meets them in the
  // order of their rounded y, which is then their order along the edge.
  for (std::size_t k = 1; k < on.size(); ++k) {
    if (on[k].edge == on[k - 1].edge &&
        std::abs(at[on[k].crossing].Y - at[on[k - 1].crossing].Y) <= 1) {
      return false;
    }
  }
  // first[e]: where edge e's crossings begin in `on`; twin[k]: where the crossing of on[k]
  // lies on its other edge.
  std::vector<std::uint32_t> first(n + 1, 0), twin(on.size()), seen(count, UINT32_MAX);
  for (const EdgeCrossing& c : on) ++first[c.edge + 1];
  for (std::size_t e = 0; e < n; ++e) first[e + 1] += first[e];
  for (std::uint32_t k = 0; k < on.size(); ++k) {
    std::uint32_t& other = seen[on[k].crossing];
    if (other == UINT32_MAX) {
      other = k;
    } else {
      twin[k] = other;
      twin[other] = k;
    }
  }
  // Every crossing off the vertices' y by more than a unit (else Clipper pulls it onto the
  // scanbeam's edge) and found by the sweep where it lies.
  std::vector<ClipperLib::cInt> ys(n);
  for (std::size_t v = 0; v < n; ++v) ys[v] = raw[v].Y;
  std::sort(ys.begin(), ys.end());
  for (std::uint32_t c = 0; c < count; ++c) {
    const ClipperLib::cInt y = at[c].Y;
    const auto above = std::lower_bound(ys.begin(), ys.end(), y - 1);
    if (above == ys.begin() || above == ys.end() || *above <= y + 1) return false;
    const auto [i, j] = crossings[c];
    if (!swept_as_crossing(raw[i], next_of(raw, i), raw[j], next_of(raw, j), *above, *(above - 1))) return false;
  }
  // The right side's winding of each piece: piece p of edge e is number first[e] + e + p.
  const std::optional<std::size_t> least = lone_least_y(raw);
  if (!least) return false;
  const std::size_t lowest = *least;
  std::vector<int> winding(on.size() + n);
  const int outside = side(prev_of(raw, lowest), raw[lowest], next_of(raw, lowest)) > 0 ? 0 : -1;
  int w = outside;
  std::size_t boundary = 0;
  for (std::size_t step = 0; step < n; ++step) {
    const std::size_t e = (lowest + step) % n;
    for (std::uint32_t k = first[e];; ++k) {
      winding[k + e] = w;
      boundary += w == 0;
      if (k == first[e + 1]) break;
      w += on[k].from_right ? -1 : 1;
    }
  }
  if (w != outside || boundary == 0) return false;
  // Traced from the first piece on the boundary.
  std::uint32_t edge = 0, piece = 0;
  while (winding[first[edge] + edge + piece] != 0) {
    if (first[edge] + piece == first[edge + 1]) {
      ++edge;
      piece = 0;
    } else {
      ++piece;
    }
  }
  out.clear();
  out.reserve(boundary);
  std::vector<ClipperLib::cInt> at_y;  // the boundary's crossings' y
  const std::uint32_t start_edge = edge, start_piece = piece;
  do {
    const std::uint32_t k = first[edge] + piece;
    if (k < first[edge + 1]) {
      out.push_back(at[on[k].crossing]);
      at_y.push_back(out.back().Y);
      const std::uint32_t t = twin[k];
      edge = on[t].edge;
      piece = t - first[edge] + 1;
    } else {
      edge = edge + 1 < n ? edge + 1 : 0;
      piece = 0;
      out.push_back(raw[edge]);
    }
    if (out.size() > boundary || winding[first[edge] + edge + piece] != 0) return false;
  } while (edge != start_edge || piece != start_piece);
  const std::size_t m = out.size();
  if (m != boundary || m < 3 || twice_area(out) <= 0) return false;
  // No crossing on the boundary within a unit of a vertex's y or of another's; no point
  // repeated or in line with its neighbours.
  std::sort(at_y.begin(), at_y.end());
  for (std::size_t k = 1; k < at_y.size(); ++k) {
    if (at_y[k] - at_y[k - 1] <= 1) return false;
  }
  for (std::size_t v = 0; v < m; ++v) {
    const auto& a = prev_of(out, v);
    const auto& b = out[v];
    const auto& c = next_of(out, v);
    if (a == b || b == c || side(a, b, c) == 0) return false;
  }
  return started_as_clipper_starts(out);
}

}  // namespace

// How union_of_folded_loop (clipper.h) finds Clipper's loop: all crossings of the loop's
// edges found (edge_crossings, on the grid already_a_region uses), its folds cut off where
// each is simple (cut_folds), else the union's boundary traced (traced_boundary), which also
// takes folds that nest or share edges. cut_folds goes first so that a loop it takes keeps its
// points: over the bunny's best, mid and ma slices and the benchmark models' (the G-code
// checks of this file's changes), 5 of the 14,502 loops taken are a unit off Clipper's where
// cut_folds took them (a crossing the sweep finds in another scanbeam); traced_boundary, which
// checks for that, alone takes 14,461 of them, each Clipper's very loop.
bool union_of_folded_loop(const Path& raw, Path& out) {
  const std::size_t n = raw.size();
  if (n < 4 || any_in_line(raw)) return false;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> crossings;
  if (!edge_crossings(raw, crossings) || crossings.empty()) return false;
  return cut_folds(raw, crossings, out) || traced_boundary(raw, crossings, out);
}

bool islands_of_loops_apart(const Paths& region, std::vector<Paths>& out) {
  std::vector<std::pair<ClipperLib::cInt, std::size_t>> tops;  // each loop's greatest y
  tops.reserve(region.size());
  for (std::size_t l = 0; l < region.size(); ++l) {
    const Path& loop = region[l];
    if (loop.size() < 3 || any_in_line(loop)) return false;
    ClipperLib::cInt top = loop.front().Y;
    for (const auto& p : loop) top = std::max(top, p.Y);
    tops.emplace_back(top, l);
  }
  if (!already_a_region(region, std::vector<char>(region.size(), 1))) return false;
  std::sort(tops.begin(), tops.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  out.clear();
  for (std::size_t k = 0; k < tops.size(); ++k) {
    if (k > 0 && tops[k].first == tops[k - 1].first) return false;
    Path loop = region[tops[k].second];
    if (!started_as_clipper_starts(loop)) return false;
    out.push_back({std::move(loop)});
  }
  return true;
}

namespace {

// The loops an offset by `units` takes (see offset): the region's own, or where one repeats a
// point, a copy without (in `cleaned`, reserved, so that pointers into it hold); and whether
// each is an outer loop (its area is the same with or without the repeats: a repeated point
// adds an edge of no area). Filled in place: the pointers are into `region` and `cleaned`.
struct OffsetLoops {
  std::vector<const Path*> loops;
  std::vector<char> outer;
  Paths cleaned;
};

// Loops are taken as they come, outer loops positive and holes negative (ClipperOffset
// turns them all over when the loop with the lowest vertex runs the other way: after a
// simplification a speck of a hole can lie there, outside the outer loop, and the region
// came out inside out). Left out: loops of next to no area, and loops the offset closes
// (holes when growing, outer loops when shrinking) that are no more than twice the
// distance across, so that no disc of that radius fits in them. Inside the region they
// would make nothing; a speck of a hole outside it, turned inside out by growing, would
// add its own speck.
void take_loops(const Paths& region, double units, OffsetLoops& taken) {
  taken.loops.reserve(region.size());
  taken.outer.reserve(region.size());
  for (const Path& path : region) {
    const double area = ClipperLib::Area(path);
    if (std::abs(area) < kNoArea) continue;
    if ((area < 0) == (units > 0)) {
      const ClipperLib::IntRect b = bounding_box(path);
      if (double(std::min(b.right - b.left, b.bottom - b.top)) <= 2 * std::abs(units)) continue;
    }
    const bool repeats = path.size() > 1 && (path.front() == path.back() ||
                                             std::adjacent_find(path.begin(), path.end()) != path.end());
    const Path* loop = &path;
    if (repeats) {
      // Reserved before the first is taken, so that pointers into it hold.
      if (taken.cleaned.empty()) taken.cleaned.reserve(region.size());
      Path& clean = taken.cleaned.emplace_back();
      clean.reserve(path.size());
      for (const auto& p : path) {
        if (clean.empty() || !(p == clean.back())) clean.push_back(p);
      }
      while (clean.size() > 1 && clean.front() == clean.back()) clean.pop_back();
      loop = &clean;
    }
    if (loop->size() < 3) continue;
    taken.loops.push_back(loop);
    taken.outer.push_back(area > 0);
  }
}

// The raw offsets of the loops (raw_offset), repeated points dropped, into `raw`; whether one
// went back through a vertex or was left with fewer than 3 points.
bool raw_loops(const std::vector<const Path*>& loops, const Joins& joins, Paths& raw) {
  raw.assign(loops.size(), Path{});
  // Kept from call to call on this thread (raw_offset sizes them to each loop): the offset
  // runs tens of thousands of times a slice.
  thread_local std::vector<Normal> normal;
  thread_local std::vector<double> length;
  bool back = false;
  for (std::size_t l = 0; l < loops.size(); ++l) {
    Path& out = raw[l];
    out.reserve(2 * loops[l]->size());
    back = raw_offset(*loops[l], joins, out, normal, length) || back;
    out.erase(std::unique(out.begin(), out.end()), out.end());
    while (out.size() > 1 && out.front() == out.back()) out.pop_back();
    back = back || out.size() < 3;
  }
  return back;
}

}  // namespace

Paths offset(const Paths& region, double delta, ClipperLib::JoinType join, double miter_limit) {
  if (region.empty()) return {};
  const double units = delta * kClipperScale;
  OffsetLoops taken;
  take_loops(region, units, taken);
  const std::vector<const Path*>& loops = taken.loops;
  const std::vector<char>& outer = taken.outer;
  if (loops.empty()) return {};
  ReusedEngine engine;
  if (units == 0) {
    for (const Path* loop : loops) engine->AddPath(*loop, ClipperLib::ptSubject, true);
  } else {
    // Where no loop went back through a vertex, the raw loops are often the offset as they
    // stand (a region with no narrow part the offset closes): checked, that costs a
    // fraction of the union.
    const Joins joins = joins_for(join, units, miter_limit);
    Paths raw;
    const bool back = raw_loops(loops, joins, raw);
    if (!back && already_a_region(raw, outer)) return raw;
    // One loop that went back through vertices: Clipper's union of it is, more often than not,
    // the loop with its folds cut off (union_of_folded_loop), found for a fraction of the cost.
    if (back && raw.size() == 1 && outer[0]) {
      Path loop;
      if (union_of_folded_loop(raw[0], loop)) return {std::move(loop)};
    }
    engine->AddPaths(raw, ClipperLib::ptSubject, true);
  }
  Paths result;
  if (units >= 0) {
    engine->Execute(ClipperLib::ctUnion, result, ClipperLib::pftPositive, ClipperLib::pftPositive);
    return result;
  }
  // Shrinking: the union of the negative winding inside a frame round it all (-1), whose
  // holes, where the raw loops (+1) cancel the frame, are the offset.
  const ClipperLib::IntRect r = engine->GetBounds();
  engine->AddPath({{r.left - 10, r.bottom + 10}, {r.right + 10, r.bottom + 10},
                   {r.right + 10, r.top - 10}, {r.left - 10, r.top - 10}},
                  ClipperLib::ptSubject, true);
  engine->ReverseSolution(true);
  engine->Execute(ClipperLib::ctUnion, result, ClipperLib::pftNegative, ClipperLib::pftNegative);
  if (!result.empty()) result.erase(result.begin());
  return result;
}

namespace {

// Whether p lies where the loops wind once or more, more than 4 units from every edge: in
// their union with the positive rule wherever Clipper rounds its crossings (within a unit).
bool wound_clear(const Paths& loops, const ClipperLib::IntPoint& p) {
  constexpr double kClear2 = 16;  // units^2
  const Vec2 q{double(p.X), double(p.Y)};
  int w = 0;
  for (const Path& loop : loops) {
    for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
      const auto& a = loop[i];
      const auto& b = next_of(loop, i);
      if (!(squared_distance_to_segment(q, {double(a.X), double(a.Y)}, {double(b.X), double(b.Y)}) > kClear2)) {
        return false;
      }
    }
    w += winding(loop, p);
  }
  return w >= 1;
}

// The centroid of a loop, rounded to units; none for a loop of no area.
std::optional<ClipperLib::IntPoint> centroid(const Path& loop) {
  const ClipperLib::IntPoint o = loop.front();
  double a2 = 0, cx = 0, cy = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const double x0 = double(loop[i].X - o.X), y0 = double(loop[i].Y - o.Y);
    const auto& b = next_of(loop, i);
    const double x1 = double(b.X - o.X), y1 = double(b.Y - o.Y);
    const double c = x0 * y1 - x1 * y0;
    a2 += c;
    cx += (x0 + x1) * c;
    cy += (y0 + y1) * c;
  }
  if (!(std::abs(a2) > 0)) return std::nullopt;
  return ClipperLib::IntPoint{o.X + rounded_units(cx / (3 * a2)), o.Y + rounded_units(cy / (3 * a2))};
}

}  // namespace

bool offset_is_empty(const Paths& region, double delta, ClipperLib::JoinType join, double miter_limit) {
  const double units = delta * kClipperScale;
  if (region.empty()) return true;
  if (units == 0) return offset(region, delta, join, miter_limit).empty();
  OffsetLoops taken;
  take_loops(region, units, taken);
  if (taken.loops.empty()) return true;
  // The raw loops wind once or more round a point clear of them: then the union the offset
  // is made of (or the loops themselves, where they are it) holds that point. The points
  // tried: each outer loop's centroid, where a part wide enough is likely to be.
  Paths raw;
  raw_loops(taken.loops, joins_for(join, units, miter_limit), raw);
  for (std::size_t l = 0; l < taken.loops.size(); ++l) {
    if (!taken.outer[l]) continue;
    const std::optional<ClipperLib::IntPoint> p = centroid(*taken.loops[l]);
    if (p && wound_clear(raw, *p)) return false;
  }
  return offset(region, delta, join, miter_limit).empty();
}

namespace {

// The box both boxes cover (of boxes that meet).
ClipperLib::IntRect box_overlap(const ClipperLib::IntRect& a, const ClipperLib::IntRect& b) {
  return {std::max(a.left, b.left), std::max(a.top, b.top), std::min(a.right, b.right),
          std::min(a.bottom, b.bottom)};
}

// Whether `outer` winds round the first point of each loop of `inner` and `inner` round that
// of no loop of `outer` that meets inner's box (`*_boxes`: the loops' bounding boxes). Where no
// edge of one meets an edge of the other, each loop lies on one side of the other region's
// boundary, so that is every loop of inner inside outer, and no loop of outer inside inner
// (where a hole of outer, or a part of its boundary, would lie in inner). A point on an edge of
// the other may give any winding, but then edges meet.
bool first_points_inside(const Paths& inner, const std::vector<ClipperLib::IntRect>& inner_boxes,
                         const ClipperLib::IntRect& inner_box, const Paths& outer,
                         const std::vector<ClipperLib::IntRect>& outer_boxes) {
  for (const Path& loop : inner) {
    if (!loop.empty() && winding_of(outer, outer_boxes, loop[0]) == 0) return false;
  }
  for (std::size_t l = 0; l < outer.size(); ++l) {
    if (outer[l].empty() || !boxes_meet(outer_boxes[l], inner_box)) continue;
    if (winding_of(inner, inner_boxes, outer[l][0]) != 0) return false;
  }
  return true;
}

// The lattice point nearest (x, y) of the four round it that lie on the right of the line
// a -> b or on it (a line through a point of a unit square leaves a corner of it on each side).
ClipperLib::IntPoint right_of(const ClipperLib::IntPoint& a, const ClipperLib::IntPoint& b,
                              double x, double y) {
  const auto x0 = static_cast<ClipperLib::cInt>(std::floor(x));
  const auto y0 = static_cast<ClipperLib::cInt>(std::floor(y));
  ClipperLib::IntPoint best{x0, y0};
  double least = std::numeric_limits<double>::infinity();
  for (const ClipperLib::cInt dx : {0, 1}) {
    for (const ClipperLib::cInt dy : {0, 1}) {
      const ClipperLib::IntPoint c{x0 + dx, y0 + dy};
      const double d = (double(c.X) - x) * (double(c.X) - x) + (double(c.Y) - y) * (double(c.Y) - y);
      if (side(a, b, c) <= 0 && d < least) {
        least = d;
        best = c;
      }
    }
  }
  return best;
}

// The area of the points' convex hull, units^2 (Andrew's monotone chain).
double hull_area(Path points) {
  std::sort(points.begin(), points.end(), [](const ClipperLib::IntPoint& p, const ClipperLib::IntPoint& q) {
    return p.X != q.X ? p.X < q.X : p.Y < q.Y;
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return 0;
  Path hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {  // the lower chain
    while (k >= 2 && side(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // the upper chain
    while (k >= lower && side(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return std::abs(ClipperLib::Area(hull));
}

// A crossing of an edge of a loop of a with an edge of b (proven_specks): `t` along the edge
// of a, from 0 at its start to 1 at its end; `turn`, how b's winding number changes there
// along a's edge (+1 where it passes from the right of b's edge to its left, else -1).
struct Crossing {
  std::uint32_t loop, edge;
  double t;
  int turn;
};

// What proven_specks cuts off a's loops: the cap of a run of vertices outside b (the convex
// hull of the run and the chord's ends), its box and area.
struct Cap {
  ClipperLib::IntRect box;
  double area;
};

// Loop `l` of a with each run of its vertices outside b cut off: the run from the vertex after
// the edge that goes out to the vertex before the edge that comes back in, replaced by a chord
// from a point on the first edge kMargin units before its first crossing to a point on the
// second kMargin units past its last (each rounded to the lattice on the edge's right, a's
// outside, or on it). Appends each run's cap to `caps`; false where there is no such cut: a
// crossed edge with both ends inside b, every vertex outside, or a crossing within the margin
// of an end. `crossed` holds the loop's crossings; `made` gets the edges the cut adds (from the
// vertex before a run to the chord, the chord, and on to the vertex after it).
bool cut_loop(const Path& loop, std::span<const Crossing> crossed, const Paths& b,
              const std::vector<ClipperLib::IntRect>& b_boxes, Path& out, std::vector<Cap>& caps,
              std::vector<std::pair<ClipperLib::IntPoint, ClipperLib::IntPoint>>& made) {
  constexpr double kMargin = 1000;  // units: 1 um
  const std::size_t n = loop.size();
  // Per edge, where along it the first and last crossings lie, and how b's winding number
  // changes along it; per vertex, whether inside b: b's winding number round the first vertex
  // (on none of b's edges: no edge of b meets a's but by crossing), changed along each edge.
  std::vector<double> first(n, 2), last(n, -1);
  std::vector<int> turn(n, 0);
  for (const Crossing& c : crossed) {
    first[c.edge] = std::min(first[c.edge], c.t);
    last[c.edge] = std::max(last[c.edge], c.t);
    turn[c.edge] += c.turn;
  }
  std::vector<char> in(n);
  int winding = winding_of(b, b_boxes, loop[0]);
  for (std::size_t v = 0; v < n; ++v) {
    in[v] = winding != 0;
    winding += turn[v];
  }
  for (std::size_t e = 0; e < n; ++e) {
    if (last[e] >= 0 && in[e] && next_of(in, e)) return false;
  }
  std::size_t s = 0;
  while (s < n && !in[s]) ++s;
  if (s == n) return false;
  const auto along = [](const ClipperLib::IntPoint& p, const ClipperLib::IntPoint& q, double t) {
    return right_of(p, q, double(p.X) + t * double(q.X - p.X), double(p.Y) + t * double(q.Y - p.Y));
  };
  const auto push = [&](const ClipperLib::IntPoint& p) {
    if (out.empty() || out.back() != p) out.push_back(p);
  };
  out.clear();
  Path cap;  // the run's chord end on the edge out, then its vertices
  ClipperLib::IntPoint before;  // the vertex before the run
  for (std::size_t j = 1; j <= n; ++j) {
    const std::size_t v = (s + j) % n, u = (v + n - 1) % n;
    const auto& p = loop[u];
    const auto& q = loop[v];
    const auto length = [&] { return std::hypot(double(q.X - p.X), double(q.Y - p.Y)); };
    if (!in[v]) {
      if (in[u]) {
        const double t = first[u] - kMargin / length();
        if (!(t > 0)) return false;
        cap.assign(1, along(p, q, t));
        before = p;
      }
      cap.push_back(q);
      continue;
    }
    if (!in[u]) {
      const double t = last[u] + kMargin / length();
      if (!(t < 1)) return false;
      cap.push_back(along(p, q, t));
      push(cap.front());
      push(cap.back());
      caps.push_back({bounding_box(cap), hull_area(cap)});
      made.insert(made.end(), {{before, cap.front()}, {cap.front(), cap.back()}, {cap.back(), q}});
    }
    push(q);
  }
  if (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return true;
}

// Whether the segment [p, q] meets an edge of the loops (`boxes`: their bounding boxes).
bool meets_any(const ClipperLib::IntPoint& p, const ClipperLib::IntPoint& q, const Paths& loops,
               const std::vector<ClipperLib::IntRect>& boxes) {
  const ClipperLib::IntRect box{std::min(p.X, q.X), std::min(p.Y, q.Y), std::max(p.X, q.X),
                                std::max(p.Y, q.Y)};
  for (std::size_t l = 0; l < loops.size(); ++l) {
    if (!boxes_meet(boxes[l], box)) continue;
    const Path& loop = loops[l];
    for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
      const auto& c = loop[i];
      const auto& d = next_of(loop, i);
      if (std::max(c.X, d.X) < box.left || std::min(c.X, d.X) > box.right ||
          std::max(c.Y, d.Y) < box.top || std::min(c.Y, d.Y) > box.bottom) {
        continue;
      }
      if (meet_within_boxes(p, q, c, d)) return true;
    }
  }
  return false;
}

}  // namespace

bool proven_inside(const Paths& inner, const Paths& outer) {
  if (inner.empty()) return true;
  if (outer.empty()) return false;
  std::vector<ClipperLib::IntRect> inner_boxes, outer_boxes;
  ClipperLib::IntRect inner_box = bounding_box(Path{}), outer_box = bounding_box(Path{});
  for (const Path& loop : inner) add_to_box(inner_box, inner_boxes.emplace_back(bounding_box(loop)));
  for (const Path& loop : outer) add_to_box(outer_box, outer_boxes.emplace_back(bounding_box(loop)));
  if (!boxes_meet(inner_box, outer_box)) return false;
  // The windings first, as the cheaper; then whether edges meet, where the boxes overlap
  // (elsewhere no edge of one can meet an edge of the other).
  if (!first_points_inside(inner, inner_boxes, inner_box, outer, outer_boxes)) return false;
  const std::optional<bool> meet = sets_meet(inner, outer, box_overlap(inner_box, outer_box));
  return meet && !*meet;
}

bool proven_specks(const Paths& a, const Paths& b, double area) {
  if (a.empty()) return true;
  if (b.empty()) return false;
  // Each sliver is at most 2 units wide along an edge of a (where an edge of b passes within a
  // unit of it), so all of them enclose at most 2 units times a's length.
  double length = 0;
  for (const Path& loop : a) {
    for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
      const auto& p = loop[i];
      const auto& q = next_of(loop, i);
      length += std::abs(double(q.X - p.X)) + std::abs(double(q.Y - p.Y));
    }
  }
  const double slivers = 2 * length;
  if (!(slivers < area)) return false;
  std::vector<ClipperLib::IntRect> a_boxes, b_boxes;
  ClipperLib::IntRect a_box = bounding_box(Path{}), b_box = bounding_box(Path{});
  for (const Path& loop : a) add_to_box(a_box, a_boxes.emplace_back(bounding_box(loop)));
  for (const Path& loop : b) add_to_box(b_box, b_boxes.emplace_back(bounding_box(loop)));
  if (!boxes_meet(a_box, b_box)) return false;
  // Every crossing of an edge of a with one of b's; none where they meet otherwise (an end of
  // one on the other, or in line), nor too many: those are left to the difference.
  constexpr std::size_t kMostCrossings = 256;
  std::vector<Crossing> crossings;
  bool touch = false;
  const std::optional<bool> stopped = each_meeting(
      a, b, box_overlap(a_box, b_box),
      [&](std::uint32_t al, std::uint32_t ae, std::uint32_t bl, std::uint32_t be) {
        const Path& la = a[al];
        const Path& lb = b[bl];
        const auto& p = la[ae];
        const auto& q = next_of(la, ae);
        const auto& c = lb[be];
        const auto& d = next_of(lb, be);
        const int turn = side(c, d, q);
        if (!(side(p, q, c) * side(p, q, d) < 0 && side(c, d, p) * turn < 0)) {
          touch = true;
          return true;
        }
        // p + t (q - p) on the line through c and d.
        const double ex = double(q.X - p.X), ey = double(q.Y - p.Y);
        const double fx = double(d.X - c.X), fy = double(d.Y - c.Y);
        const double gx = double(c.X - p.X), gy = double(c.Y - p.Y);
        crossings.push_back({al, ae, (gx * fy - gy * fx) / (ex * fy - ey * fx), turn});
        return crossings.size() > kMostCrossings;
      });
  if (!stopped || touch || crossings.size() > kMostCrossings) return false;
  if (crossings.empty()) return first_points_inside(a, a_boxes, a_box, b, b_boxes);
  // Where edges cross, a with its runs of vertices outside b cut off (cut_loop): a', whose
  // windings differ from a's by those of the cycles each cut makes, new chain less old, v_i ->
  // p -> q -> v_j+1 -> v_j -> ... -> v_i+1 -> v_i (v_i and v_j+1 inside b, the run v_i+1 ..
  // v_j outside, p on the edge v_i -> v_i+1 and q on v_j -> v_j+1). Each cycle is the sum of
  // the triangles v_i -> p -> v_i+1 and q -> v_j+1 -> v_j, which wind 0 or 1 times round any
  // point (p and q lie on the right of their edges, or on them), and the cap's loop p -> q ->
  // v_j -> ... -> v_i+1, which winds round points of the cap's hull only. So a point of a (a
  // winds once round it: a is a Clipper result) that a' leaves out, where a' winds 0 times, is
  // one round which some cap's loop winds -1 times: in its hull. Where a' is proven inside b
  // (proven_inside), the difference of a and b is then in the caps' hulls, and with their
  // boxes apart by more than the rounding of Clipper's crossings (2 units), each path of it is
  // inside one hull, within a unit (its points are rounded to the lattice), with any slivers:
  // less than the hull's area, its box's half perimeter times 2 units (the unit round the
  // hull), and the slivers' bound.
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& x, const Crossing& y) {
    return x.loop != y.loop ? x.loop < y.loop : x.edge < y.edge;
  });
  Paths cut = a;
  std::vector<Cap> caps;
  std::vector<std::pair<ClipperLib::IntPoint, ClipperLib::IntPoint>> made;
  for (std::size_t k = 0; k < crossings.size();) {
    const std::uint32_t l = crossings[k].loop;
    std::size_t end = k;
    while (end < crossings.size() && crossings[end].loop == l) ++end;
    const std::span<const Crossing> crossed(crossings.data() + k, end - k);
    if (!cut_loop(a[l], crossed, b, b_boxes, cut[l], caps, made)) return false;
    a_boxes[l] = bounding_box(cut[l]);
    add_to_box(a_box, a_boxes[l]);
    k = end;
  }
  constexpr std::size_t kMostCaps = 64;
  if (caps.size() > kMostCaps) return false;
  for (std::size_t i = 0; i < caps.size(); ++i) {
    const ClipperLib::IntRect& box = caps[i].box;
    const double rim = 4 * (double(box.right - box.left) + double(box.bottom - box.top)) + 16;
    if (!(caps[i].area + rim + slivers < area)) return false;
    const ClipperLib::IntRect grown{box.left - 2, box.top - 2, box.right + 2, box.bottom + 2};
    for (std::size_t j = 0; j < i; ++j) {
      if (boxes_meet(grown, caps[j].box)) return false;
    }
  }
  // a' inside b (proven_inside's proof): the edges it keeps of a's meet none of b's (every
  // meeting was found above: a crossing, on an edge cut off or one of a run's), and those the
  // cuts made are tested against b's here.
  for (const auto& [p, q] : made) {
    if (meets_any(p, q, b, b_boxes)) return false;
  }
  return first_points_inside(cut, a_boxes, a_box, b, b_boxes);
}

bool proven_outside(const Paths& lines, const Paths& region) {
  if (lines.empty() || region.empty()) return true;
  std::vector<ClipperLib::IntRect> region_boxes;
  ClipperLib::IntRect lines_box = bounding_box(lines), region_box = bounding_box(Path{});
  for (const Path& loop : region) add_to_box(region_box, region_boxes.emplace_back(bounding_box(loop)));
  if (!boxes_meet(lines_box, region_box)) return true;
  // Where no edges meet, each line lies on one side of the region's boundary, the side its
  // first point is on. Tested first, as the cheaper: a point on an edge of the region may give
  // any winding, but then edges meet, which is tested after.
  for (const Path& line : lines) {
    if (!line.empty() && winding_of(region, region_boxes, line[0]) != 0) return false;
  }
  const ClipperLib::IntRect overlap = box_overlap(lines_box, region_box);
  const std::optional<bool> meet = sets_meet(lines, region, overlap);
  return meet && !*meet;
}

Paths opening(const Paths& region, double radius) {
  return offset(offset(region, -radius), radius);
}

}  // namespace geometry::clipper
