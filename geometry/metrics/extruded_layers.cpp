#include "geometry/metrics/extruded_layers.h"

#include "geometry/core/clipper.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>

namespace geometry {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, Kernel>;
// Face info: nesting depth (how many loops enclose the face); odd = inside the region.
using FaceBase = CGAL::Constrained_triangulation_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<int, Kernel>>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// Exact_predicates_tag: constraints that cross (which a valid region never has, but touching
// loops come close) are split rather than refused.
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::Exact_predicates_tag>;

// CGAL's polygon-with-holes example: flood the faces from the infinite one, the depth growing
// by one across every constrained edge.
void mark_depths(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::list<Cdt::Edge> border;
  const auto flood = [&](Cdt::Face_handle start, int depth) {
    if (start->info() != -1) return;
    std::list<Cdt::Face_handle> queue{start};
    while (!queue.empty()) {
      const Cdt::Face_handle f = queue.front();
      queue.pop_front();
      if (f->info() != -1) continue;
      f->info() = depth;
      for (int i = 0; i < 3; ++i) {
        const Cdt::Edge e(f, i);
        const Cdt::Face_handle n = f->neighbor(i);
        if (n->info() != -1) continue;
        if (cdt.is_constrained(e)) border.push_back(e);
        else queue.push_back(n);
      }
    }
  };
  flood(cdt.infinite_face(), 0);
  while (!border.empty()) {
    const Cdt::Edge e = border.front();
    border.pop_front();
    const Cdt::Face_handle n = e.first->neighbor(e.second);
    if (n->info() == -1) flood(n, e.first->info() + 1);
  }
}

}  // namespace

RegionTriangulation triangulate_region(const Region& region) {
  RegionTriangulation result;
  Cdt cdt;
  std::map<std::pair<double, double>, std::uint32_t> index;
  const auto vertex = [&](Vec2 p) {
    const auto [it, fresh] = index.emplace(std::pair{p.x, p.y}, 0);
    if (fresh) {
      it->second = static_cast<std::uint32_t>(result.points.size());
      result.points.push_back(p);
    }
    return it->second;
  };
  for (const Loop& loop : region.loops) {
    if (loop.size() < 3) continue;
    std::vector<Cdt::Vertex_handle> handles;
    for (Vec2 p : loop) {
      const Cdt::Vertex_handle v = cdt.insert(Kernel::Point_2(p.x, p.y));
      v->info() = vertex(p);
      handles.push_back(v);
    }
    for (std::size_t i = 0; i < handles.size(); ++i) {
      const auto a = handles[i], b = handles[(i + 1) % handles.size()];
      if (a != b) cdt.insert_constraint(a, b);
    }
  }
  // Where constraints crossed, CGAL made new vertices: give them indices.
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v) {
    const Vec2 p{v->point().x(), v->point().y()};
    if (index.find({p.x, p.y}) == index.end()) v->info() = vertex(p);
  }
  mark_depths(cdt);
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (f->info() % 2 != 1) continue;
    result.triangles.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return result;
}

// ---------------------------------------------------------------------------------------
// The layered part as one manifold (see extruded_layers.h). Everything below works in whole
// grid units, so that every predicate is exact and every coordinate a float32.

namespace {

using GridPoint = std::array<std::int64_t, 2>;

// A plane's triangulation: each face knows how many loops of the region below and above wind
// around it.
struct Winding {
  int below = 0, above = 0;
  bool known = false;
};
using PlaneFaceBase = CGAL::Constrained_triangulation_face_base_2<
    Kernel, CGAL::Triangulation_face_base_with_info_2<Winding, Kernel>>;
using PlaneTds = CGAL::Triangulation_data_structure_2<CGAL::Triangulation_vertex_base_2<Kernel>, PlaneFaceBase>;
using PlaneCdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, PlaneTds, CGAL::Exact_predicates_tag>;

struct WideHash {
  std::size_t operator()(__int128 k) const {
    const auto lo = static_cast<std::uint64_t>(k), hi = static_cast<std::uint64_t>(k >> 64);
    return std::hash<std::uint64_t>{}(lo ^ (hi * 0x9E3779B97F4A7C15ull));
  }
};
using GridLoop = std::vector<GridPoint>;
using GridRegion = std::vector<GridLoop>;
using Wide = __int128;

std::int64_t cross(GridPoint o, GridPoint a, GridPoint b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}
std::int64_t dot(GridPoint o, GridPoint a, GridPoint b) {
  return (a[0] - o[0]) * (b[0] - o[0]) + (a[1] - o[1]) * (b[1] - o[1]);
}
std::uint64_t key_of(GridPoint p) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(p[0])) << 32) |
         static_cast<std::uint32_t>(p[1]);
}

// n / d rounded to the nearest whole number (halves away from zero), d != 0.
std::int64_t round_div(Wide n, Wide d) {
  if (d < 0) n = -n, d = -d;
  const Wide q = n >= 0 ? (2 * n + d) / (2 * d) : -((-2 * n + d) / (2 * d));
  return static_cast<std::int64_t>(q);
}

// A region's loops that touch in a point or along an edge (Clipper's unions leave such
// touches: a hole touching the outline, two islands sharing a corner), or a spike of it
// thinner than the grid, make a prism that touches itself, which no manifold surface can
// bound. So gaps and parts thinner than a micrometre go first: the region is closed by half a
// micrometre (grown, then shrunk), then opened (shrunk, then grown). Mitred corners come back
// where they were, so a region that still touches itself on the grid is cleaned again with
// the corners rounded (bevelled), which parts touching wedges; not every region, since that
// doubles the vertices. Far below a printer's step; the area changes by nothing measurable.
constexpr double kCleanBy = 0.5e-3;  // mm
Region cleaned(const Region& region, bool round) {
  const auto second = round ? ClipperLib::jtRound : ClipperLib::jtMiter;
  const clipper::Paths closed = clipper::offset(clipper::offset(to_clipper(region), kCleanBy), -kCleanBy, second);
  return from_clipper(clipper::offset(clipper::offset(closed, -kCleanBy), kCleanBy, second));
}

// Twice the loop's signed area on the grid, exact (CCW positive).
Wide twice_area(const GridLoop& loop) {
  Wide twice = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) twice += cross({0, 0}, loop[i], loop[(i + 1) % loop.size()]);
  return twice;
}

// The region on the grid: vertices rounded, repeats dropped, loops of no area dropped.
GridRegion snap_region(const Region& region, double scale) {
  GridRegion loops;
  for (const Loop& loop : region.loops) {
    GridLoop snapped;
    for (Vec2 p : loop) {
      const GridPoint g{std::llround(p.x * scale), std::llround(p.y * scale)};
      if (snapped.empty() || snapped.back() != g) snapped.push_back(g);
    }
    while (snapped.size() > 1 && snapped.back() == snapped.front()) snapped.pop_back();
    if (snapped.size() < 3) continue;
    if (twice_area(snapped) != 0) loops.push_back(std::move(snapped));
  }
  return loops;
}

// Does a loop vertex of the region lie within `reach` grid units of another part of its
// outline (a segment not ending at it)? Then the region touches itself on the grid.
bool touches_itself(const GridRegion& region, std::int64_t reach) {
  struct Piece { GridPoint a, b; std::size_t loop, index; };
  std::vector<Piece> pieces;
  double total = 0;
  for (std::size_t l = 0; l < region.size(); ++l) {
    const GridLoop& loop = region[l];
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const GridPoint a = loop[i], b = loop[(i + 1) % loop.size()];
      pieces.push_back({a, b, l, i});
      total += std::hypot(double(b[0] - a[0]), double(b[1] - a[1]));
    }
  }
  if (pieces.empty()) return false;
  // Cells of twice the mean piece; each piece is listed in the cells around samples every half
  // cell along it, so a vertex within `reach` of it finds it in the vertex's own cell.
  const std::int64_t cell = std::max<std::int64_t>(
      64 + 2 * reach, static_cast<std::int64_t>(2 * total / double(pieces.size())));
  const auto floor_div = [](std::int64_t v, std::int64_t d) { return v >= 0 ? v / d : -((-v + d - 1) / d); };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> by_cell;
  std::vector<std::uint64_t> cells;
  for (std::uint32_t k = 0; k < pieces.size(); ++k) {
    const Piece& p = pieces[k];
    const double dx = double(p.b[0] - p.a[0]), dy = double(p.b[1] - p.a[1]);
    const auto steps = static_cast<std::int64_t>(std::ceil(2 * std::hypot(dx, dy) / double(cell))) + 1;
    cells.clear();
    for (std::int64_t s = 0; s <= steps; ++s) {
      const double t = double(s) / double(steps);
      const std::int64_t cx = floor_div(std::llround(double(p.a[0]) + t * dx), cell);
      const std::int64_t cy = floor_div(std::llround(double(p.a[1]) + t * dy), cell);
      for (std::int64_t i = -1; i <= 1; ++i)
        for (std::int64_t j = -1; j <= 1; ++j) cells.push_back(key_of({cx + i, cy + j}));
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    for (std::uint64_t c : cells) by_cell[c].push_back(k);
  }
  for (std::size_t l = 0; l < region.size(); ++l) {
    const GridLoop& loop = region[l];
    for (std::size_t vi = 0; vi < loop.size(); ++vi) {
      const GridPoint v = loop[vi];
      const std::size_t before = (vi + loop.size() - 1) % loop.size();
      const auto it = by_cell.find(key_of({floor_div(v[0], cell), floor_div(v[1], cell)}));
      if (it == by_cell.end()) continue;
      for (std::uint32_t k : it->second) {
        const Piece& p = pieces[k];
        // Not the two pieces the vertex joins; any other that comes this near touches.
        if (p.loop == l && (p.index == vi || p.index == before)) continue;
        // Squared distance from v to the piece, exactly (in wide integers).
        const Wide dx = p.b[0] - p.a[0], dy = p.b[1] - p.a[1];
        const Wide wx = v[0] - p.a[0], wy = v[1] - p.a[1];
        const Wide along = dx * wx + dy * wy, length2 = dx * dx + dy * dy;
        const Wide limit = Wide(reach) * reach;
        if (along <= 0) {
          if (wx * wx + wy * wy <= limit) return true;
        } else if (along >= length2) {
          const Wide ex = v[0] - p.b[0], ey = v[1] - p.b[1];
          if (ex * ex + ey * ey <= limit) return true;
        } else {
          const Wide c = dx * wy - dy * wx;  // distance c / |piece|
          if (c * c <= limit * length2) return true;
        }
      }
    }
  }
  return false;
}

// A segment's route on the grid: its start, the centres of the hot cells it goes through in
// order, not its end (the next segment's start).
using Route = std::vector<GridPoint>;
// routes[loop][segment]
using LoopRoutes = std::vector<std::vector<Route>>;

struct Segment {
  GridPoint a, b;
  int owner;  // 0: the region below the plane, 1: above
  std::size_t loop, index;
};

// Cells of a coarse hash grid the segment passes near: sampled every half cell, with the
// cells around each sample, so that any point within a cell of the segment is in one of them.
void cells_near(const Segment& s, std::int64_t cell, std::vector<std::uint64_t>& out) {
  out.clear();
  const double dx = double(s.b[0] - s.a[0]), dy = double(s.b[1] - s.a[1]);
  const double length = std::hypot(dx, dy);
  const auto steps = static_cast<std::int64_t>(std::ceil(2 * length / double(cell))) + 1;
  const auto floor_div = [](std::int64_t v, std::int64_t d) { return v >= 0 ? v / d : -((-v + d - 1) / d); };
  for (std::int64_t k = 0; k <= steps; ++k) {
    const double t = double(k) / double(steps);
    const auto x = static_cast<std::int64_t>(std::llround(double(s.a[0]) + t * dx));
    const auto y = static_cast<std::int64_t>(std::llround(double(s.a[1]) + t * dy));
    const std::int64_t cx = floor_div(x, cell), cy = floor_div(y, cell);
    for (std::int64_t i = -1; i <= 1; ++i)
      for (std::int64_t j = -1; j <= 1; ++j) out.push_back(key_of({cx + i, cy + j}));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

// Does the segment meet the closed cell of half-width 1/2 around h? (In doubled coordinates,
// so that the cell's corners are whole numbers.)
bool meets_cell(GridPoint a, GridPoint b, GridPoint h) {
  const GridPoint a2{2 * a[0], 2 * a[1]}, b2{2 * b[0], 2 * b[1]};
  const std::int64_t lo_x = 2 * h[0] - 1, hi_x = 2 * h[0] + 1, lo_y = 2 * h[1] - 1, hi_y = 2 * h[1] + 1;
  if (std::max(a2[0], b2[0]) < lo_x || std::min(a2[0], b2[0]) > hi_x ||
      std::max(a2[1], b2[1]) < lo_y || std::min(a2[1], b2[1]) > hi_y) {
    return false;
  }
  int positive = 0, negative = 0;
  for (const GridPoint c : {GridPoint{lo_x, lo_y}, GridPoint{hi_x, lo_y}, GridPoint{hi_x, hi_y},
                            GridPoint{lo_x, hi_y}}) {
    const std::int64_t side = cross(a2, b2, c);
    positive += side > 0;
    negative += side < 0;
  }
  return positive < 4 && negative < 4;
}

// The crossing of two segments that cross properly (inside both), rounded to the grid.
std::optional<GridPoint> crossing(const Segment& s, const Segment& t) {
  const std::int64_t d1 = cross(s.a, s.b, t.a), d2 = cross(s.a, s.b, t.b);
  const std::int64_t d3 = cross(t.a, t.b, s.a), d4 = cross(t.a, t.b, s.b);
  if (!(((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))) {
    return std::nullopt;
  }
  // s.a + (s.b - s.a) * d3 / (d3 - d4)
  const Wide den = Wide(d3) - Wide(d4);
  return GridPoint{round_div(Wide(s.a[0]) * den + Wide(s.b[0] - s.a[0]) * d3, den),
                   round_div(Wide(s.a[1]) * den + Wide(s.b[1] - s.a[1]) * d3, den)};
}

// One plane: the arrangement of the region below (owner 0) and above (owner 1) on the grid,
// its horizontal faces into the mesh, and every segment's route for the walls.
class Plane {
 public:
  Plane(const GridRegion* below, const GridRegion* above, double z, double scale, Mesh& mesh)
      : z_(z), scale_(scale), mesh_(mesh) {
    const GridRegion* owners[2] = {below, above};
    for (int owner = 0; owner < 2; ++owner) {
      if (!owners[owner]) continue;
      routes_[owner].resize(owners[owner]->size());
      for (std::size_t l = 0; l < owners[owner]->size(); ++l) {
        const GridLoop& loop = (*owners[owner])[l];
        routes_[owner][l].resize(loop.size());
        for (std::size_t i = 0; i < loop.size(); ++i) {
          segments_.push_back({loop[i], loop[(i + 1) % loop.size()], owner, l, i});
        }
      }
    }
    if (segments_.empty()) return;
    find_hot_cells();
    route_segments();
    faces();
  }

  LoopRoutes& routes(int owner) { return routes_[owner]; }
  std::uint32_t vertex(GridPoint p) {
    const auto [it, fresh] = vertices_.emplace(key_of(p), 0);
    if (fresh) {
      it->second = static_cast<std::uint32_t>(mesh_.vertices.size());
      mesh_.vertices.push_back({double(p[0]) / scale_, double(p[1]) / scale_, z_});
    }
    return it->second;
  }

 private:
  void find_hot_cells() {
    double total = 0;
    for (const Segment& s : segments_) total += std::hypot(double(s.b[0] - s.a[0]), double(s.b[1] - s.a[1]));
    cell_ = std::max<std::int64_t>(64, static_cast<std::int64_t>(2 * total / double(segments_.size())));
    segment_cells_.resize(segments_.size());
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> by_cell;
    for (std::size_t i = 0; i < segments_.size(); ++i) {
      cells_near(segments_[i], cell_, segment_cells_[i]);
      for (std::uint64_t c : segment_cells_[i]) by_cell[c].push_back(static_cast<std::uint32_t>(i));
    }
    const auto add_hot = [&](GridPoint p) {
      if (hot_index_.emplace(key_of(p), static_cast<std::uint32_t>(hot_.size())).second) hot_.push_back(p);
    };
    for (const Segment& s : segments_) add_hot(s.a);
    for (auto& [cell, list] : by_cell) {
      for (std::size_t i = 0; i < list.size(); ++i)
        for (std::size_t j = i + 1; j < list.size(); ++j)
          if (auto p = crossing(segments_[list[i]], segments_[list[j]])) add_hot(*p);
    }
    const auto floor_div = [](std::int64_t v, std::int64_t d) { return v >= 0 ? v / d : -((-v + d - 1) / d); };
    for (std::uint32_t h = 0; h < hot_.size(); ++h) {
      hot_by_cell_[key_of({floor_div(hot_[h][0], cell_), floor_div(hot_[h][1], cell_)})].push_back(h);
    }
  }

  // Hot cells near segment i (from its cells), each once.
  void hot_near(std::size_t i, std::vector<std::uint32_t>& out) const {
    out.clear();
    for (std::uint64_t c : segment_cells_[i]) {
      const auto it = hot_by_cell_.find(c);
      if (it != hot_by_cell_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  }

  void route_segments() {
    std::vector<std::uint32_t> near;
    std::vector<std::pair<std::int64_t, GridPoint>> on;
    for (std::size_t i = 0; i < segments_.size(); ++i) {
      const Segment& s = segments_[i];
      hot_near(i, near);
      on.clear();
      for (std::uint32_t h : near) {
        const GridPoint p = hot_[h];
        if (p == s.a || p == s.b || !meets_cell(s.a, s.b, p)) continue;
        on.push_back({dot(s.a, s.b, p), p});
      }
      std::sort(on.begin(), on.end());
      Route route{s.a};
      for (const auto& [along, p] : on) route.push_back(p);
      route.push_back(s.b);
      // A piece between two hot centres may still pass exactly through a third: split there,
      // so that the triangulation's edges are exactly the routes' pieces.
      Route split{route.front()};
      for (std::size_t k = 0; k + 1 < route.size(); ++k) {
        const GridPoint u = route[k], v = route[k + 1];
        on.clear();
        for (std::uint32_t h : near) {
          const GridPoint p = hot_[h];
          if (p == u || p == v || cross(u, v, p) != 0) continue;
          const std::int64_t along = dot(u, v, p);
          if (along > 0 && along < dot(u, v, v)) on.push_back({along, p});
        }
        std::sort(on.begin(), on.end());
        for (const auto& [along, p] : on) split.push_back(p);
        split.push_back(v);
      }
      split.pop_back();  // the end is the next segment's start
      Route clean;
      for (GridPoint p : split)
        if (clean.empty() || clean.back() != p) clean.push_back(p);
      routes_[s.owner][s.loop][s.index] = std::move(clean);
    }
  }

  // Net traversals of each grid edge by each owner's loops, in the direction of smaller to
  // larger point key; then the triangles inside one owner's region and outside the other's.
  void faces() {
    struct Count { int below = 0, above = 0; };
    std::unordered_map<Wide, Count, WideHash> counts;  // key: (key_of(u) << 64 | key_of(v)), u < v
    const auto edge_key = [](std::uint64_t u, std::uint64_t v) { return (Wide(u) << 64) | Wide(v); };
    for (int owner = 0; owner < 2; ++owner) {
      for (const auto& loop : routes_[owner]) {
        Route ring;
        for (const Route& r : loop) ring.insert(ring.end(), r.begin(), r.end());
        for (std::size_t k = 0; k < ring.size(); ++k) {
          const std::uint64_t u = key_of(ring[k]), v = key_of(ring[(k + 1) % ring.size()]);
          if (u == v) continue;
          Count& c = counts[u < v ? edge_key(u, v) : edge_key(v, u)];
          (owner == 0 ? c.below : c.above) += u < v ? 1 : -1;
        }
      }
    }
    using Cdt = PlaneCdt;
    Cdt cdt;
    std::unordered_map<std::uint64_t, Cdt::Vertex_handle> handles;
    const auto handle = [&](std::uint64_t key) {
      auto it = handles.find(key);
      if (it != handles.end()) return it->second;
      const GridPoint p{static_cast<std::int32_t>(key >> 32), static_cast<std::int32_t>(key & 0xffffffffu)};
      const Cdt::Vertex_handle h = cdt.insert(Kernel::Point_2(double(p[0]), double(p[1])));
      handles.emplace(key, h);
      return h;
    };
    for (const auto& [edge, c] : counts) {
      if (c.below == 0 && c.above == 0) continue;
      const auto u = static_cast<std::uint64_t>(edge >> 64), v = static_cast<std::uint64_t>(edge);
      cdt.insert_constraint(handle(u), handle(v));
    }
    if (cdt.number_of_faces() == 0) return;
    const auto key_at = [](Cdt::Vertex_handle h) {
      return key_of({std::llround(h->point().x()), std::llround(h->point().y())});
    };
    // Windings by flooding from the infinite face; f lies left of the edge ccw(i) -> cw(i).
    std::vector<Cdt::Face_handle> queue{cdt.infinite_face()};
    cdt.infinite_face()->info() = {0, 0, true};
    while (!queue.empty()) {
      const Cdt::Face_handle f = queue.back();
      queue.pop_back();
      const Winding w = f->info();
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle n = f->neighbor(i);
        if (n->info().known) continue;
        Winding next = w;
        const Cdt::Vertex_handle a = f->vertex(f->ccw(i)), b = f->vertex(f->cw(i));
        if (!cdt.is_infinite(a) && !cdt.is_infinite(b)) {
          const std::uint64_t u = key_at(a), v = key_at(b);
          const auto it = counts.find(u < v ? edge_key(u, v) : edge_key(v, u));
          if (it != counts.end()) {
            const int sign = u < v ? 1 : -1;
            next.below -= sign * it->second.below;
            next.above -= sign * it->second.above;
          }
        }
        n->info() = next;
        queue.push_back(n);
      }
    }
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      const int below = f->info().below, above = f->info().above;
      if ((below > 0) == (above > 0)) continue;
      std::array<std::uint32_t, 3> t;
      for (int k = 0; k < 3; ++k) {
        t[k] = vertex({std::llround(f->vertex(k)->point().x()), std::llround(f->vertex(k)->point().y())});
      }
      if (below > 0) mesh_.faces.push_back(t);                  // the top of the layer below
      else mesh_.faces.push_back({t[0], t[2], t[1]});          // the bottom of the layer above
    }
  }

  double z_, scale_;
  Mesh& mesh_;
  std::vector<Segment> segments_;
  LoopRoutes routes_[2];
  std::int64_t cell_ = 64;
  std::vector<std::vector<std::uint64_t>> segment_cells_;
  std::vector<GridPoint> hot_;
  std::unordered_map<std::uint64_t, std::uint32_t> hot_index_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> hot_by_cell_;
  std::unordered_map<std::uint64_t, std::uint32_t> vertices_;
};

// A point of a loop's route on a plane: where it is, on which segment of the loop, how far
// along it (in dot-product units).
struct ChainPoint { GridPoint p; std::size_t segment; std::int64_t along; };

// Drops the tips of the spikes in a closed chain of points: where it turns straight back
// (its neighbours on the same ray from it), as often as dropping one makes another, round the
// chain's start too. Snap rounding makes them where a loop's vertex lies within a cell of a
// hot centre that both its segments pass through (a rounded corner's arc of nanometre steps,
// on a grid of 2 nm): the route goes out to the vertex and back, so a wall along it would lie
// against its own back. On a plane the two traversals cancel.
void drop_spikes(std::vector<ChainPoint>& chain) {
  const auto tip = [](const ChainPoint& a, const ChainPoint& b, const ChainPoint& c) {
    return cross(b.p, a.p, c.p) == 0 && dot(b.p, a.p, c.p) > 0;
  };
  std::vector<ChainPoint> kept;
  kept.reserve(chain.size());
  for (const ChainPoint& q : chain) {
    if (!kept.empty() && kept.back().p == q.p) continue;
    kept.push_back(q);
    while (kept.size() >= 3 && tip(kept.end()[-3], kept.end()[-2], kept.back())) {
      kept.erase(kept.end() - 2);
      if (kept.end()[-2].p == kept.back().p) kept.pop_back();
    }
  }
  for (bool dropped = true; dropped && kept.size() >= 3;) {
    const std::size_t n = kept.size();
    dropped = true;
    if (kept.back().p == kept.front().p || tip(kept[n - 2], kept[n - 1], kept[0])) {
      kept.pop_back();
    } else if (tip(kept[n - 1], kept[0], kept[1])) {
      kept.erase(kept.begin());
    } else {
      dropped = false;
    }
  }
  chain = std::move(kept);
}

// A layer's walls: per loop, a strip between its route at the bottom plane and at the top
// plane, each a refinement of the same loop (less its spikes), merged in order along the loop.
void walls(const GridRegion& region, const LoopRoutes& bottom, const LoopRoutes& top,
           Plane& bottom_plane, Plane& top_plane, Mesh& mesh) {
  for (std::size_t l = 0; l < region.size(); ++l) {
    const GridLoop& loop = region[l];
    const auto chain = [&](const LoopRoutes& routes) {
      std::vector<ChainPoint> points;
      for (std::size_t s = 0; s < loop.size(); ++s) {
        const GridPoint a = loop[s], b = loop[(s + 1) % loop.size()];
        for (GridPoint p : routes[l][s]) points.push_back({p, s, dot(a, b, p)});
      }
      drop_spikes(points);
      return points;
    };
    const std::vector<ChainPoint> lo = chain(bottom), hi = chain(top);
    if (lo.empty() || hi.empty()) continue;
    const auto order = [&](const std::vector<ChainPoint>& c, std::size_t i) {
      return i < c.size() ? std::pair{c[i].segment, c[i].along}
                          : std::pair{loop.size(), std::int64_t{0}};  // back at the start
    };
    std::size_t i = 0, j = 0;
    const auto lo_at = [&](std::size_t k) { return bottom_plane.vertex(lo[k % lo.size()].p); };
    const auto hi_at = [&](std::size_t k) { return top_plane.vertex(hi[k % hi.size()].p); };
    // Loops run with the region on their left: outward is to the right, so a wall triangle
    // runs bottom forward, then up (a_lo, b_lo, a_hi), or (a_lo, b_hi, a_hi).
    while (i < lo.size() || j < hi.size()) {
      if (i < lo.size() && (j == hi.size() || order(lo, i + 1) <= order(hi, j + 1))) {
        mesh.faces.push_back({lo_at(i), lo_at(i + 1), hi_at(j)});
        ++i;
      } else {
        mesh.faces.push_back({lo_at(i), hi_at(j + 1), hi_at(j)});
        ++j;
      }
    }
  }
}

}  // namespace

Mesh extruded_layers(std::span<const Layer> layers, std::span<const Region> regions) {
  Mesh mesh;
  const std::size_t count = std::min(layers.size(), regions.size());
  // The grid: the finest power of two (2^-30 mm at most) that keeps every coordinate of the
  // part below 2^23 units, so that a float32 holds it exactly (2^-18 mm, 3.8 nm, for the
  // bunny's 25 mm).
  double largest = 0;
  for (std::size_t i = 0; i < count; ++i)
    for (const Loop& loop : regions[i].loops)
      for (Vec2 p : loop) largest = std::max({largest, std::abs(p.x), std::abs(p.y)});
  if (!std::isfinite(largest)) return mesh;
  int bits = 30;
  while (bits > -30 && largest * std::ldexp(1.0, bits) >= std::ldexp(1.0, 23)) --bits;
  const double scale = std::ldexp(1.0, bits);

  struct Solid { Layer layer; GridRegion region; };
  std::vector<Solid> solids;
  for (std::size_t i = 0; i < count; ++i) {
    if (!(layers[i].z_hi > layers[i].z_lo)) continue;
    GridRegion region = snap_region(cleaned(regions[i], false), scale);
    if (touches_itself(region, 4)) region = snap_region(cleaned(regions[i], true), scale);
    if (!region.empty()) solids.push_back({layers[i], std::move(region)});
  }
  // Plane by plane, bottom up: under the first solid, between solids that touch, over and
  // under the ones with a gap between them, over the last. Each solid's walls are laid when its
  // top plane is done, between the routes of its two planes.
  const auto height = [](double z) { return static_cast<double>(static_cast<float>(z)); };
  std::unique_ptr<Plane> bottom;  // the current solid's bottom plane
  for (std::size_t k = 0; k < solids.size(); ++k) {
    if (!bottom) bottom = std::make_unique<Plane>(nullptr, &solids[k].region, height(solids[k].layer.z_lo), scale, mesh);
    const bool touching = k + 1 < solids.size() && solids[k + 1].layer.z_lo == solids[k].layer.z_hi;
    auto top = std::make_unique<Plane>(&solids[k].region, touching ? &solids[k + 1].region : nullptr,
                                       height(solids[k].layer.z_hi), scale, mesh);
    walls(solids[k].region, bottom->routes(1), top->routes(0), *bottom, *top, mesh);
    bottom = touching ? std::move(top) : nullptr;
  }
  return mesh;
}

}  // namespace geometry
