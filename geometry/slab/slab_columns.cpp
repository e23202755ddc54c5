#include "geometry/slab/slab_columns.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "geometry/core/clipper.h"
#include "geometry/core/small_polygon.h"

namespace geometry {

namespace {

AreaMoments moments_of_paths(const ClipperLib::Paths& paths, Vec2 origin) {
  AreaMoments m;
  for (const auto& path : paths) {
    for (std::size_t i = 0, n = path.size(); i < n; ++i) {
      add_edge_moments(m, from_fine_clipper(path[i]) - origin, from_fine_clipper(path[(i + 1) % n]) - origin);
    }
  }
  return m;
}

// The robust slow path: Clipper's integer intersection of the polygon with the whole region.
AreaMoments moments_by_clipper(const std::vector<Vec2>& convex, Vec2 origin,
                               const Region& region) {
  return moments_of_paths(
      clipper::intersection({to_fine_clipper(convex)}, to_fine_clipper(region)), origin);
}

// How far outside a corner the no-crossing case judges the polygon (the infinitesimal margin of
// step 1), and how clear of the region's boundary that point must be, mm: both far below the
// 1e-10 mm of the generic move below, far above double rounding at bed coordinates (1e-13).
constexpr double kProbe = 1e-13;
constexpr double kClearance = 1e-12;

// Two corners of a facet's projection closer than this are one, mm: far below anything a
// volume feels (a facet of that width over a bed holds under 1e-10 mm³), far above the
// rounding of a clipped corner at bed coordinates (1e-14).
constexpr double kSameCorner = 1e-12;
bool same_corner(const Vec3& a, const Vec3& b) {
  return std::abs(a.x - b.x) <= kSameCorner && std::abs(a.y - b.y) <= kSameCorner;
}

// Corners a polygon's edges are kept on the stack for (a facet of a slab has at most 5).
constexpr std::size_t kStackCorners = 16;

struct Crossing {
  double position;  // edge index + parameter along the polygon's edge
  bool entry;       // the region's boundary enters the polygon here
  Vec2 point;
};

}  // namespace

double integrate_linear(const std::vector<Vec2>& loop, Vec2 origin, double w0, double wx,
                        double wy) {
  const AreaMoments m = moments_of_loop(loop, origin);
  return w0 * m.area + wx * m.mx + wy * m.my;
}

namespace {

// Step 1 of crossing_moments: the region's boundary inside the polygon (Cyrus-Beck against
// each edge's half-plane), its moments added to m, and where it crosses the polygon's
// boundary (`crossings`, unordered). A boundary point exactly on an edge's line counts as
// inside: the polygon is treated as grown by an infinitesimal margin, and step 2 judges its
// edges at that margin too, so both steps see the same configuration. Each vertex's side of
// each line is computed by the same expression wherever it appears, so neighbouring boundary
// segments agree on it.
void add_boundary_inside(const std::vector<Vec2>& convex, const Box2& box, Vec2 origin,
                         const BoundaryGrid& region_grid, AreaMoments& m,
                         std::vector<Crossing>& crossings) {
  const std::size_t n = convex.size();
  // Each edge's corner and direction, once per polygon rather than once per segment near it
  // (plain doubles: Vec2's zeroing of an array it never reads cost as much as it saves). With
  // the facets' boxes given (their ColumnFacet lo and hi), crossing_moments took 321 M instructions
  // of the bunny's best slice at 0.15 mm (callgrind) instead of 340 M; the same values.
  struct Edge {
    double px, py, dx, dy;
  };
  Edge stack_edges[kStackCorners];
  std::vector<Edge> heap_edges;
  Edge* edges = stack_edges;
  if (n > kStackCorners) {
    heap_edges.resize(n);
    edges = heap_edges.data();
  }
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 p = convex[k], d = convex[k + 1 == n ? 0 : k + 1] - p;
    edges[k] = {p.x, p.y, d.x, d.y};
  }
  const auto& segments = region_grid.segments();
  region_grid.for_each_near(box.lo, box.hi, [&](std::uint32_t id) {
    const Segment2& s = segments[id];
    double t0 = 0, t1 = 1;
    int k0 = -1, k1 = -1;
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2 p{edges[k].px, edges[k].py}, d{edges[k].dx, edges[k].dy};
      const double sa = cross(d, s.a - p), sb = cross(d, s.b - p);
      if (sa < 0 && sb < 0) return;
      if (sa >= 0 && sb >= 0) continue;
      const double t = sa / (sa - sb);
      // Entering crossings have t in (0, 1], leaving ones t in [0, 1).
      if (sa < 0) {
        if (t > t0) { t0 = t; k0 = static_cast<int>(k); }
      } else if (t < t1) {
        t1 = t;
        k1 = static_cast<int>(k);
      }
    }
    if (t0 > t1) return;
    const Vec2 ab = s.b - s.a;
    const Vec2 a = s.a + t0 * ab, b = s.a + t1 * ab;
    add_edge_moments(m, a - origin, b - origin);
    const auto position = [&](int k, Vec2 x) {
      const Vec2 p{edges[k].px, edges[k].py}, d{edges[k].dx, edges[k].dy};
      return k + std::clamp(dot(x - p, d) / dot(d, d), 0.0, 1.0);
    };
    if (k0 >= 0) crossings.push_back({position(k0, a), true, a});
    if (k1 >= 0) crossings.push_back({position(k1, b), false, b});
  });
}

// Step 2 with no crossing: the polygon's boundary is all in or all out. Judged at a point just
// outside a corner (the infinitesimal margin of step 1), unless the region's boundary passes
// too close to tell, which only a degenerate configuration does (false).
bool add_polygon_if_inside(const std::vector<Vec2>& convex, Vec2 origin,
                           const BoundaryGrid& region_grid, AreaMoments& m) {
  const std::size_t n = convex.size();
  Vec2 centre{0, 0};
  for (Vec2 p : convex) centre = centre + p;
  centre = (1.0 / n) * centre;
  const Vec2 out = convex[0] - centre;
  const double length = std::hypot(out.x, out.y);
  const Vec2 probe = length > 0 ? convex[0] + (kProbe / length) * out : convex[0];
  double clearance = 0;
  const int winding = region_grid.winding_number(probe, &clearance);
  if (clearance < kClearance) return false;
  if (winding != 0) {
    for (std::size_t k = 0; k < n; ++k) add_edge_moments(m, convex[k] - origin, convex[(k + 1) % n] - origin);
  }
  return true;
}

// Step 2 with crossings (sorted along the polygon's boundary): from every exit, the polygon's
// boundary runs inside the region up to the next entry. Walking it, the region's boundary
// alternately leaves and enters; anything else, or two crossings too close to order, is a
// degenerate configuration (false).
bool add_polygon_between_crossings(const std::vector<Vec2>& convex, Vec2 origin,
                                   const std::vector<Crossing>& crossings, AreaMoments& m) {
  const std::size_t n = convex.size(), count = crossings.size();
  for (std::size_t i = 0; i < count; ++i) {
    const Crossing& a = crossings[i];
    const Crossing& b = crossings[(i + 1) % count];
    const double gap = i + 1 < count ? b.position - a.position : b.position + n - a.position;
    if (a.entry == b.entry || gap < 1e-12) return false;
  }
  for (std::size_t i = 0; i < count; ++i) {
    const Crossing& exit = crossings[i];
    if (exit.entry) continue;
    const Crossing& entry = crossings[(i + 1) % count];
    Vec2 at = exit.point;
    std::size_t k = static_cast<std::size_t>(std::min(exit.position, n - 1e-9));
    const std::size_t last = static_cast<std::size_t>(std::min(entry.position, n - 1e-9));
    const bool wraps = entry.position < exit.position;
    if (!(k == last && !wraps)) {
      // Corners from the exit's edge round to the entry's edge.
      std::size_t steps = (last + n - k) % n;
      if (steps == 0) steps = n;  // entry behind the exit on the same edge: full turn
      for (std::size_t s = 0; s < steps; ++s) {
        const Vec2 corner = convex[(k + 1) % n];
        add_edge_moments(m, at - origin, corner - origin);
        at = corner;
        k = (k + 1) % n;
      }
    }
    add_edge_moments(m, at - origin, entry.point - origin);
  }
  return true;
}

// The moments of (convex ∩ region) by Green's theorem, or nothing where the configuration is
// degenerate (the region's boundary through a corner of the polygon or along its edge).
std::optional<AreaMoments> crossing_moments(const std::vector<Vec2>& convex, const Box2& box,
                                            Vec2 origin, const BoundaryGrid& region_grid) {
  AreaMoments m;
  // Reused: this runs for every facet and region, and a fresh vector each time was a malloc.
  thread_local std::vector<Crossing> crossings;
  crossings.clear();
  add_boundary_inside(convex, box, origin, region_grid, m, crossings);
  if (crossings.empty()) {
    if (!add_polygon_if_inside(convex, origin, region_grid, m)) return std::nullopt;
    return m;
  }
  std::sort(crossings.begin(), crossings.end(),
            [](const Crossing& a, const Crossing& b) { return a.position < b.position; });
  if (!add_polygon_between_crossings(convex, origin, crossings, m)) return std::nullopt;
  return m;
}

}  // namespace

AreaMoments moments_of_intersection(const std::vector<Vec2>& convex, const Box2& box, Vec2 origin,
                                    const BoundaryGrid& region_grid, const Region& region) {
  if (convex.size() < 3 || region_grid.empty()) return {};
  if (const auto m = crossing_moments(convex, box, origin, region_grid)) return *m;
  // Degenerate: a section through the polygon's corners, the lower contour along a facet's
  // bottom edge. Moved by 0.1 pm in a generic direction the polygon meets the region
  // generically, and its moments move by less than 1e-10 mm times its perimeter (times the
  // integrand): far below the 1 pm grid of the Clipper fallback, which runs over the whole
  // region (Clipper only if both moves still degenerate).
  for (const Vec2 shift : {Vec2{7.548776662e-11, 5.698402910e-11}, Vec2{-4.301597090e-11, 9.127451e-11}}) {
    std::vector<Vec2> moved = convex;
    for (Vec2& p : moved) p = p + shift;
    if (const auto m = crossing_moments(moved, bounding_box(moved), origin, region_grid)) return *m;
  }
  return moments_by_clipper(convex, origin, region);
}

AreaMoments moments_of_intersection(const std::vector<Vec2>& convex, Vec2 origin,
                                    const BoundaryGrid& region_grid, const Region& region) {
  if (convex.size() < 3 || region_grid.empty()) return {};
  return moments_of_intersection(convex, bounding_box(convex), origin, region_grid, region);
}

std::vector<Vec2> clip_to_half_plane(const std::vector<Vec2>& polygon, Vec2 o, double f0,
                                     double fx, double fy) {
  const auto at = [&](Vec2 p) { return f0 + fx * (p.x - o.x) + fy * (p.y - o.y); };
  std::vector<Vec2> out;
  for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
    const Vec2 a = polygon[i], b = polygon[(i + 1) % n];
    const double fa = at(a), fb = at(b);
    if (fa >= 0) out.push_back(a);
    if ((fa >= 0) != (fb >= 0)) out.push_back(a + (fa / (fa - fb)) * (b - a));
  }
  return out;
}

std::vector<Vec2> convex_intersection(std::vector<Vec2> polygon, const std::vector<Vec2>& by) {
  for (std::size_t k = 0, n = by.size(); k < n && polygon.size() >= 3; ++k) {
    const Vec2 p = by[k], d = by[(k + 1) % n] - p;
    // Left of p -> p + d: cross(d, x - p) >= 0.
    polygon = clip_to_half_plane(polygon, p, 0, -d.y, d.x);
  }
  return polygon;
}

std::vector<std::vector<int>> overlapping_facets(const SlabColumns& columns) {
  const std::size_t n = columns.facets.size();
  std::vector<std::vector<int>> overlapping(n);
  std::vector<Segment2> boxes;
  boxes.reserve(n);
  for (const ColumnFacet& facet : columns.facets) boxes.push_back({facet.lo, facet.hi});
  // A segment's box is the facet's box, so the grid finds facets whose boxes meet.
  const BoundaryGrid grid(std::move(boxes));
  // On the stack where the outlines fit (small_polygon.h: the same arithmetic, so the same
  // answer), else through convex_intersection.
  // Pushed, not sized and assigned: a sized vector zeroes every polygon's 16 corners first.
  std::vector<SmallPolygon> outline;
  outline.reserve(n);
  for (const ColumnFacet& facet : columns.facets) outline.push_back(small_polygon(facet.outline));
  const auto overlap = [&](std::size_t a, std::size_t b) {
    bool complete = columns.facets[a].outline.size() <= kSmallCorners &&
                    columns.facets[b].outline.size() <= kSmallCorners;
    if (complete) {
      const SmallPolygon common = intersect_small(outline[a], outline[b], &complete);
      if (complete) return common.size >= 3 && small_signed_area(common) > kFoldArea;
    }
    const std::vector<Vec2> common =
        convex_intersection(columns.facets[a].outline, columns.facets[b].outline);
    return common.size() >= 3 && signed_area(common) > kFoldArea;
  };
  // First the facets of folds (an up-facing facet over a down-facing one), then every pair
  // among them whatever its facing (an S-fold stacks two up-facing sheets round a
  // down-facing one).
  std::vector<char> folded(n, 0);
  bool any = false;
  for (std::size_t u = 0; u < n; ++u) {
    if (columns.facets[u].sign > 0) continue;
    grid.for_each_near(columns.facets[u].lo, columns.facets[u].hi, [&](std::uint32_t d) {
      if (columns.facets[d].sign < 0 || (folded[u] && folded[d]) || !overlap(u, d)) return;
      folded[u] = folded[d] = 1;
      any = true;
    });
  }
  if (!any) return overlapping;
  for (std::size_t a = 0; a < n; ++a) {
    if (!folded[a]) continue;
    grid.for_each_near(columns.facets[a].lo, columns.facets[a].hi, [&](std::uint32_t b) {
      if (b > a && folded[b] && overlap(a, b)) overlapping[a].push_back(static_cast<int>(b));
    });
    std::sort(overlapping[a].begin(), overlapping[a].end());
  }
  return overlapping;
}

void slab_columns(const Slab& slab, const Region& lower_section, SlabColumns& columns) {
  columns.z_lo = slab.z_lo;
  columns.z_hi = slab.z_hi;
  columns.lower = lower_section;
  columns.lower_area = area(lower_section);
  const double t = slab.z_hi - slab.z_lo;
  double volume = t * columns.lower_area;
  std::vector<Vec3> corners;
  std::size_t used = 0;
  for (const auto& facet : slab.facets) {
    if (facet.size() < 3) continue;
    // Newell's normal: exact for planar polygons, robust to the clip's near-repeated points.
    Vec3 normal{};
    for (std::size_t i = 0, n = facet.size(); i < n; ++i) {
      const Vec3 a = facet[i], b = facet[(i + 1) % n];
      normal.x += (a.y - b.y) * (a.z + b.z);
      normal.y += (a.z - b.z) * (a.x + b.x);
      normal.z += (a.x - b.x) * (a.y + b.y);
    }
    const double length = std::sqrt(dot(normal, normal));
    // A (nearly) vertical facet covers no area seen from above; dropping one whose normal is
    // within 1e-9 of horizontal changes a column integral by under 1e-9 of its area times t.
    if (!(length > 0) || std::abs(normal.z) <= 1e-9 * length) continue;
    // Corners that meet in projection (within kSameCorner) are one: an edge of a few ulps,
    // left by clipping a face at a plane its corner lies a rounding error off (a sphere's
    // equator at a layer's bottom), has no direction to speak of, which the exact integrals
    // over the facet's intersection with a region (moments_of_intersection) need.
    corners.clear();
    for (const Vec3& v : facet) {
      if (corners.empty() || !same_corner(corners.back(), v)) corners.push_back(v);
    }
    while (corners.size() > 1 && same_corner(corners.front(), corners.back())) corners.pop_back();
    if (corners.size() < 3) continue;
    // The facets already there are overwritten, their outlines' storage reused.
    if (used == columns.facets.size()) columns.facets.emplace_back();
    ColumnFacet& column = columns.facets[used++];
    column.sign = normal.z > 0 ? -1 : 1;
    column.outline.clear();
    column.outline.reserve(corners.size());
    for (const Vec3& v : corners) column.outline.push_back({v.x, v.y});
    if (column.sign > 0) std::reverse(column.outline.begin(), column.outline.end());
    const Vec3 first = corners[column.sign > 0 ? corners.size() - 1 : 0];
    // z_f(x, y) = first.z - (n.x (x - x0) + n.y (y - y0)) / n.z, so w = z_hi - z_f has:
    column.w0 = slab.z_hi - first.z;
    column.wx = normal.x / normal.z;
    column.wy = normal.y / normal.z;
    const Box2 box = bounding_box(column.outline);
    column.lo = box.lo;
    column.hi = box.hi;
    volume += column.sign * integrate_linear(column.outline, column.outline[0], column.w0,
                                             column.wx, column.wy);
  }
  columns.facets.resize(used);
  columns.volume = volume;
  columns.overlapping = overlapping_facets(columns);
}

SlabColumns slab_columns(const Slab& slab, const Region& lower_section) {
  SlabColumns columns;
  slab_columns(slab, lower_section, columns);
  return columns;
}

double intersection_area(const Region& a, const Region& b) {
  if (a.loops.empty() || b.loops.empty()) return 0;
  const ClipperLib::Paths result = clipper::intersection(to_fine_clipper(a), to_fine_clipper(b));
  // Summed in the plane's own units: a loop's area in pm^2 can exceed a double's exact range
  // but not its relative precision, which is all an area needs.
  double total = 0;
  for (const auto& path : result) total += moments_of_paths({path}, {0, 0}).area;
  return total;
}

double occupied_volume_inside(const SlabColumns& columns, const Region& region,
                              const BoundaryGrid& region_grid) {
  if (region.loops.empty()) return 0;
  double volume = columns.thickness() * intersection_area(columns.lower, region);
  for (const ColumnFacet& facet : columns.facets) {
    const Vec2 origin = facet.outline[0];
    const AreaMoments m =
        moments_of_intersection(facet.outline, {facet.lo, facet.hi}, origin, region_grid, region);
    volume += facet.sign * (facet.w0 * m.area + facet.wx * m.mx + facet.wy * m.my);
  }
  return volume;
}

double occupied_volume_inside(const SlabColumns& columns, const Region& region) {
  return occupied_volume_inside(columns, region, BoundaryGrid(region));
}

}  // namespace geometry
