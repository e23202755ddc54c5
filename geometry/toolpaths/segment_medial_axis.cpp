#include "geometry/toolpaths/segment_medial_axis.h"

#include <boost/polygon/polygon.hpp>
#include <boost/polygon/voronoi.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <unordered_map>

#include "geometry/core/clipper.h"

namespace geometry {
// Boost's coordinate types for the diagram, under a name of our own, so that its circle
// events can be formed as below (voronoi_predicates<CheckedTraits>).
struct CheckedTraits : boost::polygon::detail::voronoi_ctype_traits<std::int32_t> {};
}  // namespace geometry

namespace boost::polygon::detail {

// Circle events (the centre of a circle touching three sites, and its rightmost point, at
// which the sweep takes it): Boost forms them in floating point with an error bound, and
// where the bound is over 64 ulps recomputes them in multiprecision arithmetic.
// Near-parallel sites (the two sides of a thin strip, as the gap fill has) make that bound
// loose: 90% of the diagram's time went there (bunny, 0.2 mm layers), on circles already
// right to a small fraction of a nanometre. So the floating-point circle is kept where it is
// within kCircleSlack of each of its three sites (distances in double: good to 1e-6 nm on
// a 1 m frame), and its rightmost point is not within kCircleSlack of a whole nanometre,
// where a site (at whole nanometres) may tie with it: the exact arithmetic decides which
// the sweep meets first (a regular model, a box or a sphere, has such ties everywhere).
// Elsewhere it is recomputed exactly.
template <>
template <>
class voronoi_predicates<geometry::CheckedTraits>::mp_circle_formation_functor<site_event<int>,
                                                                               circle_event<double>> {
 public:
  using Site = site_event<int>;
  using Circle = circle_event<double>;
  using Exact = voronoi_predicates<voronoi_ctype_traits<int>>::mp_circle_formation_functor<Site,
                                                                                            Circle>;

  void ppp(const Site& a, const Site& b, const Site& c, Circle& circle, bool x = true,
           bool y = true, bool lower = true) {
    if (!fits(circle, a, b, c)) exact_.ppp(a, b, c, circle, x, y, lower);
  }
  void pps(const Site& a, const Site& b, const Site& c, int segment, Circle& circle,
           bool x = true, bool y = true, bool lower = true) {
    if (!fits(circle, a, b, c)) exact_.pps(a, b, c, segment, circle, x, y, lower);
  }
  void pss(const Site& a, const Site& b, const Site& c, int point, Circle& circle,
           bool x = true, bool y = true, bool lower = true) {
    if (!fits(circle, a, b, c)) exact_.pss(a, b, c, point, circle, x, y, lower);
  }
  void sss(const Site& a, const Site& b, const Site& c, Circle& circle, bool x = true,
           bool y = true, bool lower = true) {
    if (!fits(circle, a, b, c)) exact_.sss(a, b, c, circle, x, y, lower);
  }

 private:
  static constexpr double kCircleSlack = 0.01;  // nm

  // Distance from (x, y) to a site: a point, or a segment's line.
  static double distance(const Site& s, double x, double y) {
    const double x0 = s.x0(), y0 = s.y0();
    if (!s.is_segment()) return std::hypot(x - x0, y - y0);
    const double dx = double(s.x1()) - x0, dy = double(s.y1()) - y0;
    return std::abs((x - x0) * dy - (y - y0) * dx) / std::hypot(dx, dy);
  }
  static bool fits(const Circle& circle, const Site& a, const Site& b, const Site& c) {
    const double x = circle.x(), y = circle.y(), r = circle.lower_x() - circle.x();
    if (!std::isfinite(x) || !std::isfinite(y) || !(r >= 0)) return false;
    if (!(std::abs(circle.lower_x() - std::round(circle.lower_x())) > kCircleSlack)) return false;
    for (const Site* s : {&a, &b, &c}) {
      if (!(std::abs(distance(*s, x, y) - r) <= kCircleSlack)) return false;
    }
    return true;
  }

  Exact exact_;
};

}  // namespace boost::polygon::detail

namespace geometry {

namespace {

namespace bp = boost::polygon;
using VoronoiPoint = bp::point_data<std::int32_t>;
using VoronoiSegment = bp::segment_data<std::int32_t>;
using Diagram = bp::voronoi_diagram<double>;

// The region's edges in a local integer frame (nm from the bounding box's corner), with each
// edge's neighbours on its loop so a vertex's two edges are known.
struct Edges {
  std::vector<VoronoiSegment> segments;
  std::vector<std::size_t> previous;  // index of the edge ending where edge i starts
  std::vector<std::size_t> next;      // index of the edge starting where edge i ends
  ClipperLib::IntPoint origin;
};

Vec2 low(const VoronoiSegment& s) { return {double(bp::x(s.low())), double(bp::y(s.low()))}; }
Vec2 high(const VoronoiSegment& s) { return {double(bp::x(s.high())), double(bp::y(s.high()))}; }

// Distance from p to the site of a cell (an edge or one of its end points), nm.
double distance_to_site(const Edges& edges, const Diagram::cell_type& cell, Vec2 p) {
  const VoronoiSegment& s = edges.segments[cell.source_index()];
  if (cell.contains_segment()) return distance_to_segment(p, low(s), high(s));
  const Vec2 q = cell.source_category() == bp::SOURCE_CATEGORY_SEGMENT_START_POINT ? low(s)
                                                                                   : high(s);
  return length(p - q);
}

// Whether p, a point whose nearest boundary point is the cell's site, lies inside the region:
// inside is left of every edge (outer loops CCW, holes CW), and at a vertex inside the wedge
// its two edges make.
bool inside_by_site(const Edges& edges, const Diagram::cell_type& cell, Vec2 p) {
  const std::size_t i = cell.source_index();
  const VoronoiSegment& s = edges.segments[i];
  if (cell.contains_segment()) return cross(high(s) - low(s), p - low(s)) > 0;
  std::size_t in, out;
  if (cell.source_category() == bp::SOURCE_CATEGORY_SEGMENT_START_POINT) {
    in = edges.previous[i];
    out = i;
  } else {
    in = i;
    out = edges.next[i];
  }
  const VoronoiSegment& a = edges.segments[in];
  const VoronoiSegment& b = edges.segments[out];
  const Vec2 v = low(b), d_in = high(a) - low(a), d_out = high(b) - low(b);
  const bool left_of_in = cross(d_in, p - v) > 0, left_of_out = cross(d_out, p - v) > 0;
  // The inside at a vertex is the wedge between its edges: at a convex vertex (turning left)
  // left of both, at a reflex one left of either.
  return cross(d_in, d_out) > 0 ? left_of_in && left_of_out : left_of_in || left_of_out;
}

Edges region_edges(const Region& region) {
  ClipperLib::Paths paths = to_clipper(region);
  // Near-duplicate points make zero-length sites, which the Voronoi builder cannot take.
  ClipperLib::CleanPolygons(paths, 100.0);
  Edges edges;
  ClipperLib::IntRect box = clipper::bounding_box(ClipperLib::Path{});
  for (const auto& path : paths) {
    if (path.size() >= 3) clipper::add_to_box(box, clipper::bounding_box(path));
  }
  constexpr ClipperLib::cInt kMaxExtent = std::numeric_limits<std::int32_t>::max() / 2;
  if (box.left > box.right || box.right - box.left > kMaxExtent ||
      box.bottom - box.top > kMaxExtent) {
    return edges;
  }
  const ClipperLib::cInt min_x = box.left, min_y = box.top;
  edges.origin = {min_x, min_y};
  for (const auto& path : paths) {
    if (path.size() < 3) continue;
    const std::size_t first = edges.segments.size(), n = path.size();
    for (std::size_t i = 0; i < n; ++i) {
      const auto& a = path[i];
      const auto& b = path[(i + 1) % n];
      edges.segments.emplace_back(
          VoronoiPoint(std::int32_t(a.X - min_x), std::int32_t(a.Y - min_y)),
          VoronoiPoint(std::int32_t(b.X - min_x), std::int32_t(b.Y - min_y)));
      edges.previous.push_back(first + (i + n - 1) % n);
      edges.next.push_back(first + (i + 1) % n);
    }
  }
  return edges;
}

// The interior angle at the vertex two edges of the region share, radians; pi if they share
// none (then they are no corner).
double corner_angle(const Edges& edges, const Diagram::cell_type& c1,
                    const Diagram::cell_type& c2) {
  if (!c1.contains_segment() || !c2.contains_segment()) return std::numbers::pi;
  std::size_t in = c1.source_index(), out = c2.source_index();
  if (edges.next[in] != out) std::swap(in, out);
  if (edges.next[in] != out) return std::numbers::pi;
  const Vec2 a = high(edges.segments[in]) - low(edges.segments[in]);
  const Vec2 b = high(edges.segments[out]) - low(edges.segments[out]);
  return std::numbers::pi - std::atan2(cross(a, b), a.x * b.x + a.y * b.y);
}


// A corner sharper than this is a tapering wall, and its bisector is a centre line to print
// (down to the narrowest bead); a blunter corner's bisector only runs into the corner.
constexpr double kTaperAngle = std::numbers::pi / 4;

SegmentMedialAxis medial_axis_of(const Edges& edges, double min_radius, double max_radius) {
  SegmentMedialAxis axis;
  if (edges.segments.empty()) return axis;
  Diagram diagram;
  bp::voronoi_builder<std::int32_t, CheckedTraits> builder;
  for (const VoronoiSegment& s : edges.segments) {
    builder.insert_segment(bp::x(s.low()), bp::y(s.low()), bp::x(s.high()), bp::y(s.high()));
  }
  builder.construct(&diagram);
  std::unordered_map<const Diagram::vertex_type*, std::size_t> node_of;
  auto add_node = [&](Vec2 p, double r) {
    axis.points.push_back(p);
    axis.radius.push_back(r);
    return axis.points.size() - 1;
  };
  auto node = [&](const Diagram::vertex_type* v, double r) {
    auto [it, fresh] = node_of.try_emplace(v, axis.points.size());
    if (fresh) add_node({v->x(), v->y()}, r);
    return it->second;
  };
  // An axis point closer to the boundary than this touches it: the edge ends in a corner.
  const double touching = 0.1 * min_radius;
  for (const auto& edge : diagram.edges()) {
    // Each edge comes with its twin; take one of the pair.
    if (&edge > edge.twin() || !edge.is_primary() || !edge.is_finite()) continue;
    const Vec2 a{edge.vertex0()->x(), edge.vertex0()->y()};
    const Vec2 b{edge.vertex1()->x(), edge.vertex1()->y()};
    const Vec2 mid{(a.x + b.x) / 2, (a.y + b.y) / 2};
    const auto& cell = *edge.cell();
    if (!inside_by_site(edges, cell, mid)) continue;
    const double ra = distance_to_site(edges, cell, a), rb = distance_to_site(edges, cell, b);
    // Far wider than any bead: not a thin wall (and, from a region that breaks the
    // builder's rule of edges meeting only at their ends, not trusted either).
    if (ra > max_radius || rb > max_radius) continue;
    if (ra >= touching && rb >= touching) {
      axis.links.emplace_back(node(edge.vertex0(), ra), node(edge.vertex1(), rb));
      continue;
    }
    // An edge into a corner: keep it only in a sharp corner (a tapering wall), and only
    // where the wall is at least the narrowest bead wide. Between two lines the radius
    // grows linearly along the bisector.
    if (corner_angle(edges, cell, *edge.twin()->cell()) > kTaperAngle) continue;
    const bool a_in_corner = ra < rb;
    const double r_far = a_in_corner ? rb : ra, r_near = a_in_corner ? ra : rb;
    if (r_far <= min_radius) continue;
    const Vec2 far = a_in_corner ? b : a, near = a_in_corner ? a : b;
    const double t = (r_far - min_radius) / (r_far - r_near);
    const Vec2 cut{far.x + t * (near.x - far.x), far.y + t * (near.y - far.y)};
    const std::size_t far_node = node(a_in_corner ? edge.vertex1() : edge.vertex0(), r_far);
    axis.links.emplace_back(far_node, add_node(cut, min_radius));
  }
  return axis;
}

}  // namespace

SegmentMedialAxis segment_medial_axis(const Region& region, double min_radius,
                                      double max_radius) {
  const Edges edges = region_edges(region);
  SegmentMedialAxis axis =
      medial_axis_of(edges, min_radius * kClipperScale, max_radius * kClipperScale);
  axis.origin = from_clipper(edges.origin);
  return axis;
}

namespace {

// The links at each point, in the order of the links, in one array: a point's own vector each
// was an allocation per point, and prune_spurs builds this once a pass.
class Incidence {
 public:
  explicit Incidence(const SegmentMedialAxis& axis) : begin_(axis.points.size() + 1, 0) {
    for (const auto& [u, v] : axis.links) {
      ++begin_[u + 1];
      ++begin_[v + 1];
    }
    for (std::size_t p = 1; p < begin_.size(); ++p) begin_[p] += begin_[p - 1];
    links_.resize(begin_.back());
    std::vector<std::size_t> next(begin_.begin(), begin_.end() - 1);
    for (std::size_t l = 0; l < axis.links.size(); ++l) {
      links_[next[axis.links[l].first]++] = l;
      links_[next[axis.links[l].second]++] = l;
    }
  }
  std::size_t size(std::size_t point) const { return begin_[point + 1] - begin_[point]; }
  std::size_t operator()(std::size_t point, std::size_t k) const { return links_[begin_[point] + k]; }

 private:
  std::vector<std::size_t> begin_, links_;
};

}  // namespace

void prune_spurs(SegmentMedialAxis& axis) {
  const std::size_t n = axis.points.size();
  std::vector<std::size_t> chain;
  for (bool changed = true; changed;) {
    changed = false;
    const Incidence incident(axis);
    std::vector<bool> removed(axis.links.size(), false);
    for (std::size_t leaf = 0; leaf < n; ++leaf) {
      if (incident.size(leaf) != 1) continue;
      chain.clear();
      std::size_t at = leaf, via = incident(leaf, 0);
      double chain_length = 0;
      while (true) {
        if (removed[via]) break;
        chain.push_back(via);
        const auto [u, v] = axis.links[via];
        const std::size_t next = u == at ? v : u;
        chain_length += length(axis.points[next] - axis.points[at]);
        at = next;
        if (incident.size(at) != 2) break;
        via = incident(at, 0) == via ? incident(at, 1) : incident(at, 0);
      }
      if (incident.size(at) >= 3 && chain_length < axis.radius[at]) {
        for (std::size_t l : chain) removed[l] = true;
        changed = true;
      }
    }
    if (!changed) break;
    std::vector<std::pair<std::size_t, std::size_t>> kept;
    kept.reserve(axis.links.size());
    for (std::size_t l = 0; l < axis.links.size(); ++l) {
      if (!removed[l]) kept.push_back(axis.links[l]);
    }
    axis.links = std::move(kept);
  }
}

std::vector<std::vector<std::size_t>> axis_chains(const SegmentMedialAxis& axis) {
  const std::size_t n = axis.points.size();
  const Incidence incident(axis);
  std::vector<bool> used(axis.links.size(), false);
  std::vector<std::vector<std::size_t>> result;
  auto walk = [&](std::size_t start, std::size_t via) {
    std::vector<std::size_t> chain{start};
    std::size_t at = start;
    while (!used[via]) {
      used[via] = true;
      const auto [u, v] = axis.links[via];
      at = u == at ? v : u;
      chain.push_back(at);
      if (incident.size(at) != 2) break;
      via = incident(at, 0) == via ? incident(at, 1) : incident(at, 0);
    }
    result.push_back(std::move(chain));
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (incident.size(i) == 2) continue;
    for (std::size_t k = 0; k < incident.size(i); ++k) {
      const std::size_t l = incident(i, k);
      if (!used[l]) walk(i, l);
    }
  }
  for (std::size_t l = 0; l < axis.links.size(); ++l) {
    if (!used[l]) walk(axis.links[l].first, l);  // a cycle: ends where it began
  }
  return result;
}

}  // namespace geometry
