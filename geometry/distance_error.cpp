#include "geometry/distance_error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace geometry {

namespace {

constexpr double kInvSqrt3 = 0.57735026918962576;

double distance_to(Vec2 p, const Segment2& s) { return distance_to_segment(p, s.a, s.b); }

double length(Vec2 a, Vec2 b) { return std::hypot(b.x - a.x, b.y - a.y); }

// The nearby walls of one piece of surface: every segment whose box meets [lo, hi].
std::vector<const Segment2*> walls_near(const BoundaryGrid& grid, Vec2 lo, Vec2 hi) {
  std::vector<const Segment2*> near;
  grid.for_each_near(lo, hi, [&](std::uint32_t id) { near.push_back(&grid.segments()[id]); });
  return near;
}

double nearest_of(Vec2 p, const std::vector<const Segment2*>& candidates) {
  double best = std::numeric_limits<double>::infinity();
  for (const Segment2* s : candidates) best = std::min(best, distance_to(p, *s));
  return best;
}

// max over the triangle of the distance to the nearest wall, raising `best` (see the header).
void search_triangle(const std::array<Vec2, 3>& corners, const std::array<double, 3>& corner_d,
                     const BoundaryGrid& grid, double tolerance, double& best) {
  struct Piece {
    std::array<Vec2, 3> p;
    std::array<double, 3> d;
  };
  const auto longest = [](const std::array<Vec2, 3>& p) {
    return std::max({length(p[0], p[1]), length(p[1], p[2]), length(p[2], p[0])});
  };
  const double top = std::max({corner_d[0], corner_d[1], corner_d[2]});
  const double reach = top + longest(corners) * kInvSqrt3;
  if (reach <= best + tolerance) return;
  // Every point's nearest wall lies within `reach` of it, hence in this box.
  Vec2 lo = corners[0], hi = corners[0];
  for (Vec2 p : corners) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
  }
  const std::vector<const Segment2*> near =
      walls_near(grid, {lo.x - reach, lo.y - reach}, {hi.x + reach, hi.y + reach});
  if (near.empty()) return;
  std::vector<Piece> stack{{corners, corner_d}};
  while (!stack.empty()) {
    const Piece piece = stack.back();
    stack.pop_back();
    const double size = longest(piece.p);
    const double low = std::max({piece.d[0], piece.d[1], piece.d[2]});
    best = std::max(best, low);
    if (low + size * kInvSqrt3 <= best + tolerance) continue;
    double upper = std::numeric_limits<double>::infinity();
    for (const Segment2* s : near) {
      upper = std::min(upper, std::max({distance_to(piece.p[0], *s), distance_to(piece.p[1], *s),
                                        distance_to(piece.p[2], *s)}));
      if (upper <= best + tolerance) break;
    }
    if (upper <= best + tolerance) continue;
    const Vec2 m01 = 0.5 * (piece.p[0] + piece.p[1]), m12 = 0.5 * (piece.p[1] + piece.p[2]),
               m20 = 0.5 * (piece.p[2] + piece.p[0]);
    const double d01 = nearest_of(m01, near), d12 = nearest_of(m12, near),
                 d20 = nearest_of(m20, near);
    best = std::max({best, d01, d12, d20});
    stack.push_back({{piece.p[0], m01, m20}, {piece.d[0], d01, d20}});
    stack.push_back({{m01, piece.p[1], m12}, {d01, piece.d[1], d12}});
    stack.push_back({{m20, m12, piece.p[2]}, {d20, d12, piece.d[2]}});
    stack.push_back({{m01, m12, m20}, {d01, d12, d20}});
  }
}

// max over the segment [a, b] of the distance to the nearest segment of `grid`, raising `best`.
void search_segment(Vec2 a, Vec2 b, double da, double db, const BoundaryGrid& grid,
                    double tolerance, double& best) {
  const double reach = std::max(da, db) + length(a, b) / 2;
  if (reach <= best + tolerance) return;
  const Vec2 lo{std::min(a.x, b.x) - reach, std::min(a.y, b.y) - reach};
  const Vec2 hi{std::max(a.x, b.x) + reach, std::max(a.y, b.y) + reach};
  const std::vector<const Segment2*> near = walls_near(grid, lo, hi);
  if (near.empty()) return;
  struct Piece {
    Vec2 a, b;
    double da, db;
  };
  std::vector<Piece> stack{{a, b, da, db}};
  while (!stack.empty()) {
    const Piece piece = stack.back();
    stack.pop_back();
    const double low = std::max(piece.da, piece.db);
    best = std::max(best, low);
    if (low + length(piece.a, piece.b) / 2 <= best + tolerance) continue;
    double upper = std::numeric_limits<double>::infinity();
    for (const Segment2* s : near) {
      upper = std::min(upper, std::max(distance_to(piece.a, *s), distance_to(piece.b, *s)));
      if (upper <= best + tolerance) break;
    }
    if (upper <= best + tolerance) continue;
    const Vec2 m = 0.5 * (piece.a + piece.b);
    const double dm = nearest_of(m, near);
    best = std::max(best, dm);
    stack.push_back({piece.a, m, piece.da, dm});
    stack.push_back({m, piece.b, dm, piece.db});
  }
}

double forward_distance(const SlabSurface& surface, const BoundaryGrid& walls, double tolerance) {
  const BoundaryGrid& grid = walls.empty() ? surface.footprint_boundary : walls;
  if (surface.triangles.empty() || grid.empty()) return 0;
  std::vector<std::array<double, 3>> corner_d(surface.triangles.size());
  double best = 0;
  for (std::size_t i = 0; i < surface.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      corner_d[i][k] = grid.nearest_distance(surface.triangles[i][k]);
      best = std::max(best, corner_d[i][k]);
    }
  }
  // Most promising first, so the bound prunes the rest.
  std::vector<std::uint32_t> order(surface.triangles.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::max({corner_d[a][0], corner_d[a][1], corner_d[a][2]}) >
           std::max({corner_d[b][0], corner_d[b][1], corner_d[b][2]});
  });
  for (std::uint32_t i : order) search_triangle(surface.triangles[i], corner_d[i], grid, tolerance, best);
  return best;
}

double reverse_distance(const SlabSurface& surface, const BoundaryGrid& walls, double tolerance) {
  double best = 0;
  for (const BoundaryGrid& level : surface.levels) {
    const auto& segments = walls.segments();
    std::vector<std::array<double, 2>> ends(segments.size());
    for (std::size_t i = 0; i < segments.size(); ++i) {
      ends[i] = {level.nearest_distance(segments[i].a), level.nearest_distance(segments[i].b)};
      best = std::max({best, ends[i][0], ends[i][1]});
    }
    for (std::size_t i = 0; i < segments.size(); ++i) {
      search_segment(segments[i].a, segments[i].b, ends[i][0], ends[i][1], level, tolerance, best);
    }
  }
  return best;
}

}  // namespace

std::vector<Segment2> surface_at(const Slab& slab, double z, bool from_above) {
  std::vector<Segment2> segments;
  for (const auto& facet : slab.facets) {
    Vec2 found[2];
    int count = 0;
    for (std::size_t i = 0, n = facet.size(); i < n && count < 2; ++i) {
      const Vec3 a = facet[i], b = facet[(i + 1) % n];
      const bool a_below = from_above ? a.z <= z : a.z < z;
      const bool b_below = from_above ? b.z <= z : b.z < z;
      if (a_below == b_below) continue;
      const double t = (z - a.z) / (b.z - a.z);
      found[count++] = {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    }
    if (count == 2 && !(found[0] == found[1])) segments.push_back({found[0], found[1]});
  }
  return segments;
}

SlabSurface slab_surface(const Slab& slab, const Region& footprint,
                         const DistanceOptions& options) {
  SlabSurface surface;
  surface.z_lo = slab.z_lo;
  surface.z_hi = slab.z_hi;
  struct FlatEdge {
    double z;
    Vec2 a, b;
  };
  std::vector<FlatEdge> flat_edges;
  for (const auto& facet : slab.facets) {
    if (facet.size() < 3) continue;
    const bool horizontal = std::all_of(facet.begin(), facet.end(),
                                        [&](const Vec3& v) { return v.z == facet[0].z; });
    const auto flat = [](const Vec3& v) { return Vec2{v.x, v.y}; };
    if (horizontal) {
      for (std::size_t i = 0, n = facet.size(); i < n; ++i) {
        flat_edges.push_back({facet[i].z, flat(facet[i]), flat(facet[(i + 1) % n])});
      }
      continue;
    }
    for (std::size_t i = 1; i + 1 < facet.size(); ++i) {
      surface.triangles.push_back({flat(facet[0]), flat(facet[i]), flat(facet[i + 1])});
    }
  }
  // A flat face is usually several facets: only the edges of the flat region count, not the
  // diagonals between its facets (an edge met in both directions at the same height).
  const auto key = [](const FlatEdge& e) {
    const bool swap = e.b.x < e.a.x || (e.b.x == e.a.x && e.b.y < e.a.y);
    const Vec2 lo = swap ? e.b : e.a, hi = swap ? e.a : e.b;
    return std::array<double, 5>{e.z, lo.x, lo.y, hi.x, hi.y};
  };
  std::sort(flat_edges.begin(), flat_edges.end(),
            [&](const FlatEdge& x, const FlatEdge& y) { return key(x) < key(y); });
  for (std::size_t i = 0; i < flat_edges.size();) {
    std::size_t j = i + 1;
    while (j < flat_edges.size() && key(flat_edges[j]) == key(flat_edges[i])) ++j;
    if (j - i == 1) surface.triangles.push_back({flat_edges[i].a, flat_edges[i].b, flat_edges[i].b});
    i = j;
  }
  const int levels = std::max(options.reverse_levels, 2);
  const double t = slab.z_hi - slab.z_lo;
  for (int j = 0; j < levels && t > 0; ++j) {
    const double z = j + 1 == levels ? slab.z_hi : slab.z_lo + t * j / (levels - 1);
    std::vector<Segment2> segments = surface_at(slab, z, j + 1 < levels);
    if (!segments.empty()) surface.levels.emplace_back(std::move(segments));
  }
  // Holes filled: an empty layer's walls are taken to have shrunk onto the outer outline.
  Region outline;
  for (const Loop& loop : footprint.loops)
    if (signed_area(loop) > 0) outline.loops.push_back(loop);
  surface.footprint_boundary = BoundaryGrid(outline);
  return surface;
}

DistanceError distance_error(const SlabSurface& surface, const BoundaryGrid& walls,
                             const DistanceOptions& options) {
  DistanceError error;
  const double tolerance = std::max(options.tolerance, 1e-9);
  error.forward = forward_distance(surface, walls, tolerance);
  error.reverse = walls.empty() ? 0 : reverse_distance(surface, walls, tolerance);
  error.hausdorff = std::max(error.forward, error.reverse);
  return error;
}

}  // namespace geometry
