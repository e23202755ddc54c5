#include "geometry/toolpaths/thin_walls.h"

#include <boost/polygon/polygon.hpp>
#include <boost/polygon/voronoi.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <map>
#include <unordered_map>

#include "geometry/core/boundary_grid.h"
#include "geometry/core/clipper.h"

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

struct Vec2d {
  double x, y;
};

double cross2(Vec2d a, Vec2d b) { return a.x * b.y - a.y * b.x; }

Vec2d low(const VoronoiSegment& s) { return {double(bp::x(s.low())), double(bp::y(s.low()))}; }
Vec2d high(const VoronoiSegment& s) { return {double(bp::x(s.high())), double(bp::y(s.high()))}; }
Vec2d sub(Vec2d a, Vec2d b) { return {a.x - b.x, a.y - b.y}; }

double distance_to_segment(Vec2d p, Vec2d a, Vec2d b) {
  const Vec2d ab = sub(b, a), ap = sub(p, a);
  const double length2 = ab.x * ab.x + ab.y * ab.y;
  const double t = length2 > 0 ? std::clamp((ap.x * ab.x + ap.y * ab.y) / length2, 0.0, 1.0) : 0;
  return std::hypot(ap.x - t * ab.x, ap.y - t * ab.y);
}

// Distance from p to the site of a cell (an edge or one of its end points), nm.
double distance_to_site(const Edges& edges, const Diagram::cell_type& cell, Vec2d p) {
  const VoronoiSegment& s = edges.segments[cell.source_index()];
  if (cell.contains_segment()) return distance_to_segment(p, low(s), high(s));
  const Vec2d q = cell.source_category() == bp::SOURCE_CATEGORY_SEGMENT_START_POINT ? low(s)
                                                                                    : high(s);
  return std::hypot(p.x - q.x, p.y - q.y);
}

// Whether p, a point whose nearest boundary point is the cell's site, lies inside the region:
// inside is left of every edge (outer loops CCW, holes CW), and at a vertex inside the wedge
// its two edges make.
bool inside_by_site(const Edges& edges, const Diagram::cell_type& cell, Vec2d p) {
  const std::size_t i = cell.source_index();
  const VoronoiSegment& s = edges.segments[i];
  if (cell.contains_segment()) return cross2(sub(high(s), low(s)), sub(p, low(s))) > 0;
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
  const Vec2d v = low(b), d_in = sub(high(a), low(a)), d_out = sub(high(b), low(b));
  const bool left_of_in = cross2(d_in, sub(p, v)) > 0, left_of_out = cross2(d_out, sub(p, v)) > 0;
  // The inside at a vertex is the wedge between its edges: at a convex vertex (turning left)
  // left of both, at a reflex one left of either.
  return cross2(d_in, d_out) > 0 ? left_of_in && left_of_out : left_of_in || left_of_out;
}

Edges region_edges(const Region& region) {
  ClipperLib::Paths paths = to_clipper(region);
  // Near-duplicate points make zero-length sites, which the Voronoi builder cannot take.
  ClipperLib::CleanPolygons(paths, 100.0);
  Edges edges;
  bool any = false;
  ClipperLib::cInt min_x = 0, min_y = 0, max_x = 0, max_y = 0;
  for (const auto& path : paths) {
    if (path.size() < 3) continue;
    for (const auto& p : path) {
      if (!any) { min_x = max_x = p.X; min_y = max_y = p.Y; any = true; }
      min_x = std::min(min_x, p.X); max_x = std::max(max_x, p.X);
      min_y = std::min(min_y, p.Y); max_y = std::max(max_y, p.Y);
    }
  }
  constexpr ClipperLib::cInt kMaxExtent = std::numeric_limits<std::int32_t>::max() / 2;
  if (!any || max_x - min_x > kMaxExtent || max_y - min_y > kMaxExtent) return edges;
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

// The pruned medial axis as a graph: nodes are Voronoi vertices with their inscribed radius.
struct Axis {
  std::vector<Vec2d> points;
  std::vector<double> radius;
  std::vector<std::pair<std::size_t, std::size_t>> links;
};

// The interior angle at the vertex two edges of the region share, radians; pi if they share
// none (then they are no corner).
double corner_angle(const Edges& edges, const Diagram::cell_type& c1,
                    const Diagram::cell_type& c2) {
  if (!c1.contains_segment() || !c2.contains_segment()) return std::numbers::pi;
  std::size_t in = c1.source_index(), out = c2.source_index();
  if (edges.next[in] != out) std::swap(in, out);
  if (edges.next[in] != out) return std::numbers::pi;
  const Vec2d a = sub(high(edges.segments[in]), low(edges.segments[in]));
  const Vec2d b = sub(high(edges.segments[out]), low(edges.segments[out]));
  return std::numbers::pi - std::atan2(cross2(a, b), a.x * b.x + a.y * b.y);
}

double length(Vec2d a, Vec2d b) { return std::hypot(a.x - b.x, a.y - b.y); }

// A run of a centre line is printed at one width while the strip's width stays within this
// fraction of the run's mean: a bead wider than the strip lays its excess outside it.
constexpr double kRunTolerance = 0.1;

// Round bead ends and joins within this of the arc, mm.
constexpr double kBeadArcTolerance = 0.005;

// A corner sharper than this is a tapering wall, and its bisector is a centre line to print
// (down to the narrowest bead); a blunter corner's bisector only runs into the corner.
constexpr double kTaperAngle = std::numbers::pi / 4;

Axis medial_axis(const Edges& edges, double min_radius, double max_radius) {
  Axis axis;
  if (edges.segments.empty()) return axis;
  Diagram diagram;
  bp::construct_voronoi(edges.segments.begin(), edges.segments.end(), &diagram);
  std::unordered_map<const Diagram::vertex_type*, std::size_t> node_of;
  auto add_node = [&](Vec2d p, double r) {
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
    const Vec2d a{edge.vertex0()->x(), edge.vertex0()->y()};
    const Vec2d b{edge.vertex1()->x(), edge.vertex1()->y()};
    const Vec2d mid{(a.x + b.x) / 2, (a.y + b.y) / 2};
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
    const Vec2d far = a_in_corner ? b : a, near = a_in_corner ? a : b;
    const double t = (r_far - min_radius) / (r_far - r_near);
    const Vec2d cut{far.x + t * (near.x - far.x), far.y + t * (near.y - far.y)};
    const std::size_t far_node = node(a_in_corner ? edge.vertex1() : edge.vertex0(), r_far);
    axis.links.emplace_back(far_node, add_node(cut, min_radius));
  }
  return axis;
}

// Removes short leaf branches that stay inside the disc of the junction they hang from: they
// come from bumps of the boundary and add nothing a bead along the main line does not cover.
void prune_spurs(Axis& axis) {
  const std::size_t n = axis.points.size();
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<std::vector<std::size_t>> incident(n);
    for (std::size_t l = 0; l < axis.links.size(); ++l) {
      incident[axis.links[l].first].push_back(l);
      incident[axis.links[l].second].push_back(l);
    }
    std::vector<bool> removed(axis.links.size(), false);
    for (std::size_t leaf = 0; leaf < n; ++leaf) {
      if (incident[leaf].size() != 1) continue;
      std::vector<std::size_t> chain;
      std::size_t at = leaf, via = incident[leaf][0];
      double chain_length = 0;
      while (true) {
        if (removed[via]) break;
        chain.push_back(via);
        const auto [u, v] = axis.links[via];
        const std::size_t next = u == at ? v : u;
        chain_length += length(axis.points[at], axis.points[next]);
        at = next;
        if (incident[at].size() != 2) break;
        via = incident[at][0] == via ? incident[at][1] : incident[at][0];
      }
      if (incident[at].size() >= 3 && chain_length < axis.radius[at]) {
        for (std::size_t l : chain) removed[l] = true;
        changed = true;
      }
    }
    std::vector<std::pair<std::size_t, std::size_t>> kept;
    for (std::size_t l = 0; l < axis.links.size(); ++l) {
      if (!removed[l]) kept.push_back(axis.links[l]);
    }
    axis.links = std::move(kept);
  }
}

// Chains of the graph between nodes that are not simple pass-throughs, then the cycles left.
std::vector<std::vector<std::size_t>> chains(const Axis& axis) {
  const std::size_t n = axis.points.size();
  std::vector<std::vector<std::size_t>> incident(n);
  for (std::size_t l = 0; l < axis.links.size(); ++l) {
    incident[axis.links[l].first].push_back(l);
    incident[axis.links[l].second].push_back(l);
  }
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
      if (incident[at].size() != 2) break;
      via = incident[at][0] == via ? incident[at][1] : incident[at][0];
    }
    result.push_back(std::move(chain));
  };
  for (std::size_t i = 0; i < n; ++i) {
    if (incident[i].size() == 2) continue;
    for (std::size_t l : incident[i]) {
      if (!used[l]) walk(i, l);
    }
  }
  for (std::size_t l = 0; l < axis.links.size(); ++l) {
    if (!used[l]) walk(axis.links[l].first, l);  // a cycle: ends where it began
  }
  return result;
}

std::vector<ExtrusionPath> centre_lines(const Region& region, double min_width,
                                        double max_width) {
  std::vector<ExtrusionPath> paths;
  if (!(min_width > 0) || !(max_width >= min_width)) return paths;
  const Edges edges = region_edges(region);
  // The narrowest bead is printed along the axis wherever the region is at least that wide.
  const double min_radius = min_width / 2 * kClipperScale;
  Axis axis = medial_axis(edges, min_radius, max_width * kClipperScale);
  prune_spurs(axis);
  const Vec2 origin = from_clipper(edges.origin);
  for (const auto& chain : chains(axis)) {
    const bool cycle = chain.size() > 2 && chain.front() == chain.back();
    // The chain's points, with steps inserted where the width changes along one edge (a
    // tapering wall is a single Voronoi edge), the radius interpolated linearly.
    std::vector<Vec2d> at;
    std::vector<double> radius;
    for (std::size_t k = 0; k + 1 < chain.size(); ++k) {
      const Vec2d p = axis.points[chain[k]], q = axis.points[chain[k + 1]];
      const double rp = axis.radius[chain[k]], rq = axis.radius[chain[k + 1]];
      const double change = std::abs(rq - rp) / std::max({rp, rq, 1e-9});
      const int steps = std::clamp(static_cast<int>(std::ceil(change / 0.05)), 1, 64);
      for (int j = 0; j < steps; ++j) {
        const double t = static_cast<double>(j) / steps;
        at.push_back({p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)});
        radius.push_back(rp + t * (rq - rp));
      }
    }
    if (chain.empty()) continue;
    at.push_back(axis.points[chain.back()]);
    radius.push_back(axis.radius[chain.back()]);

    // Runs of nearly constant width, each printed at its mean width.
    std::size_t run_start = 0;
    double run_length = 0, run_weighted = 0;
    auto emit = [&](std::size_t end) {
      if (end <= run_start || run_length <= 0) return;
      ExtrusionPath path;
      path.role = PathRole::thin_wall;
      path.width = std::clamp(run_weighted / run_length / kClipperScale, min_width, max_width);
      for (std::size_t k = run_start; k <= end; ++k) {
        path.points.push_back(origin + Vec2{at[k].x / kClipperScale, at[k].y / kClipperScale});
      }
      const bool closed = cycle && run_start == 0 && end + 1 == at.size();
      if (closed) path.points.back() = path.points.front();
      if (closed || run_length / kClipperScale >= min_width) paths.push_back(std::move(path));
    };
    for (std::size_t k = 0; k + 1 < at.size(); ++k) {
      const double segment = length(at[k], at[k + 1]);
      const double width = radius[k] + radius[k + 1];
      if (run_length > 0) {
        const double mean = run_weighted / run_length;
        if (std::abs(width - mean) > kRunTolerance * mean) {
          emit(k);
          run_start = k;
          run_length = run_weighted = 0;
        }
      }
      run_length += segment;
      run_weighted += segment * width;
    }
    emit(at.size() - 1);
  }
  return paths;
}

// One line through a compact piece along its long axis (the principal axis of its area),
// as long as the piece less a bead's round ends, as wide as the piece's area over its chord.
std::optional<ExtrusionPath> long_axis_line(const clipper::Paths& piece, double min_width,
                                            double max_width) {
  // Area moments about the first vertex (keeps the sums small), then about the centroid.
  const ClipperLib::IntPoint o = piece.front().front();
  double a = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (const auto& path : piece) {
    for (std::size_t i = 0, n = path.size(); i < n; ++i) {
      const double x0 = double(path[i].X - o.X) / kClipperScale;
      const double y0 = double(path[i].Y - o.Y) / kClipperScale;
      const double x1 = double(path[(i + 1) % n].X - o.X) / kClipperScale;
      const double y1 = double(path[(i + 1) % n].Y - o.Y) / kClipperScale;
      const double c = x0 * y1 - x1 * y0;
      a += c / 2;
      sx += (x0 + x1) * c / 6;
      sy += (y0 + y1) * c / 6;
      sxx += (x0 * x0 + x0 * x1 + x1 * x1) * c / 12;
      syy += (y0 * y0 + y0 * y1 + y1 * y1) * c / 12;
      sxy += (x0 * y1 + 2 * x0 * y0 + 2 * x1 * y1 + x1 * y0) * c / 24;
    }
  }
  if (!(a > 0)) return std::nullopt;
  const double cx = sx / a, cy = sy / a;
  const double ixx = sxx - a * cx * cx, iyy = syy - a * cy * cy, ixy = sxy - a * cx * cy;
  const double angle = 0.5 * std::atan2(2 * ixy, ixx - iyy);  // the axis of largest spread
  const Vec2 centre = from_clipper(o) + Vec2{cx, cy};
  const Vec2 along{std::cos(angle), std::sin(angle)};
  double reach = 0;
  for (const auto& path : piece) {
    for (const auto& p : path) reach = std::max(reach, std::abs(dot(from_clipper(p) - centre, along)));
  }
  const clipper::Paths chord_line{{to_clipper(centre + (-reach - 1) * along),
                              to_clipper(centre + (reach + 1) * along)}};
  double chord = 0;
  Vec2 from = centre, to = centre;
  for (const auto& part : clipper::clip_open(chord_line, piece)) {
    const Vec2 p = from_clipper(part.front()), q = from_clipper(part.back());
    const double length = std::hypot(q.x - p.x, q.y - p.y);
    if (length > chord) { chord = length; from = p; to = q; }
  }
  if (!(chord > 0)) return std::nullopt;
  const double width = std::clamp(a / chord, min_width, max_width);
  const double keep = std::max(chord - width, 0.25 * width);  // a blob gets at least a dab
  const Vec2 mid = 0.5 * (from + to), direction = (1 / chord) * (to - from);
  ExtrusionPath line;
  line.role = PathRole::thin_wall;
  line.width = width;
  line.points = {mid + (-keep / 2) * direction, mid + (keep / 2) * direction};
  return line;
}

}  // namespace

// A run too wide for one bead as two beads side by side: the outline of its centre line
// widened by a quarter of its width (round ends, so that the pair ends where one bead as
// wide would), as closed paths half its width wide. The outline is kept a quarter width
// inside the region (the pair's beads stay in it where the run's mean width is more than
// the strip's there, or the centre line runs off-centre past a corner of the edge).
std::vector<ExtrusionPath> side_by_side(const ExtrusionPath& run, const clipper::Paths& region) {
  const bool closed = run.points.size() > 2 && run.points.front() == run.points.back();
  ClipperLib::Path line = to_clipper(run.points);
  if (closed) line.pop_back();
  clipper::Paths outline = clipper::library_offset(
      {line}, run.width / 4, ClipperLib::jtRound,
      closed ? ClipperLib::etClosedLine : ClipperLib::etOpenRound, kBeadArcTolerance);
  outline = clipper::intersection(outline, clipper::offset(region, -run.width / 4));
  std::vector<ExtrusionPath> pair;
  for (const auto& path : outline) {
    if (path.size() < 3) continue;
    ExtrusionPath loop;
    loop.role = PathRole::thin_wall;
    loop.width = run.width / 2;
    loop.points = from_clipper(path);
    loop.points.push_back(loop.points.front());
    pair.push_back(std::move(loop));
  }
  return pair;
}

// Free ends (an end no other path shares) carried on by half their width along their last
// piece, where the bead then still lies inside `within`: the centre line stops where its
// bead's round end meets the edge, but a bead laid against another bead or a wall, not the
// air, may as well be full to the end.
void reach_on(std::vector<ExtrusionPath>& paths, const Region& within) {
  auto key = [](Vec2 p) { return std::pair{std::llround(p.x * 1e6), std::llround(p.y * 1e6)}; };
  std::map<std::pair<long long, long long>, int> ends;
  for (const ExtrusionPath& path : paths) {
    if (path.points.size() < 2 || path.points.front() == path.points.back()) continue;
    ++ends[key(path.points.front())];
    ++ends[key(path.points.back())];
  }
  bool any_free = false;
  for (const auto& [end, count] : ends) any_free = any_free || count == 1;
  if (!any_free) return;
  // The grid answers both from the few edges around q (an island has thousands of edges).
  const BoundaryGrid edges(within);
  auto room = [&](Vec2 q, double radius) {
    // Clear of every edge by the bead's half width, then inside: q is off the boundary, so
    // its winding number is defined.
    return !(edges.nearest_distance(q) < radius) && edges.winding_number(q) > 0;
  };
  for (ExtrusionPath& path : paths) {
    auto& p = path.points;
    if (p.size() < 2 || p.front() == p.back()) continue;
    for (bool front : {true, false}) {
      const Vec2 end = front ? p.front() : p.back();
      const Vec2 before = front ? p[1] : p[p.size() - 2];
      const Vec2 d = end - before;
      const double length = std::hypot(d.x, d.y);
      if (ends[key(end)] > 1 || !(length > 0)) continue;
      const Vec2 q = end + (path.width / 2 / length) * d;
      if (room(q, path.width / 2 * (1 - 1e-6))) (front ? p.front() : p.back()) = q;
    }
  }
}

std::vector<ExtrusionPath> thin_walls(const Region& region, double min_width, double max_width,
                                      double pair_width, const Region* reach_within) {
  if (region.loops.empty() || !(min_width > 0) || !(max_width >= min_width)) return {};
  // A piece that fits in a box the widest bead across is a blob (a gap fill's
  // piece mostly is one): its medial axis, pruned of the branches into its corners, is
  // little or nothing, and it gets the one line along its long axis below without
  // building the Voronoi diagram.
  std::vector<ExtrusionPath> paths;
  clipper::Paths long_pieces;
  for (const clipper::Paths& piece : clipper::islands(to_clipper(region))) {
    ClipperLib::cInt x0 = piece[0][0].X, x1 = x0, y0 = piece[0][0].Y, y1 = y0;
    for (const auto& p : piece[0]) {
      x0 = std::min(x0, p.X); x1 = std::max(x1, p.X);
      y0 = std::min(y0, p.Y); y1 = std::max(y1, p.Y);
    }
    const double box = max_width * kClipperScale;
    if (static_cast<double>(x1 - x0) <= box && static_cast<double>(y1 - y0) <= box) {
      for (const clipper::Paths& core : clipper::islands(clipper::opening(piece, min_width / 2))) {
        if (auto line = long_axis_line(core, min_width, max_width)) paths.push_back(*line);
      }
    } else {
      long_pieces.insert(long_pieces.end(), piece.begin(), piece.end());
    }
  }
  if (long_pieces.empty()) {
    if (reach_within) reach_on(paths, *reach_within);
    return paths;
  }
  std::vector<ExtrusionPath> lines =
      centre_lines(from_clipper(long_pieces), min_width, max_width);
  const std::size_t blobs = paths.size();
  paths.insert(paths.end(), lines.begin(), lines.end());
  // A compact piece (an end of a thin feature, about as wide as it is long) has no centre
  // line once the medial axis' branches into its corners are gone: what the lines leave
  // bare, if a bead of the smallest width fits in it, gets one line along its long axis.
  clipper::Paths covered;  // each line's bead, at its own width
  for (std::size_t i = blobs; i < paths.size(); ++i) {
    const ExtrusionPath& path = paths[i];
    const clipper::Paths bead =
        clipper::library_offset({to_clipper(path.points)}, path.width / 2, ClipperLib::jtRound,
                                ClipperLib::etOpenRound, kBeadArcTolerance);
    covered.insert(covered.end(), bead.begin(), bead.end());
  }
  const clipper::Paths bare =
      clipper::opening(clipper::difference(long_pieces, clipper::union_nonzero(covered)), min_width / 2);
  for (const clipper::Paths& piece : clipper::islands(bare)) {
    if (auto line = long_axis_line(piece, min_width, max_width)) paths.push_back(*line);
  }
  if (reach_within) reach_on(paths, *reach_within);
  if (!(pair_width < max_width)) return paths;
  std::vector<ExtrusionPath> laid;
  for (ExtrusionPath& path : paths) {
    if (path.width > pair_width) {
      for (ExtrusionPath& side : side_by_side(path, long_pieces)) laid.push_back(std::move(side));
    } else {
      laid.push_back(std::move(path));
    }
  }
  return laid;
}

}  // namespace geometry
