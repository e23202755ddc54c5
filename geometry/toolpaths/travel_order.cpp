#include "geometry/toolpaths/travel_order.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>

#include "geometry/core/boundary_grid.h"

namespace geometry {

namespace {

double distance(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

bool closed(const ExtrusionPath& path) {
  return path.points.size() > 2 && path.points.front() == path.points.back();
}

// Turn at vertex i of a closed path, radians, positive to the left (convex for the part,
// which lies left of every loop: outer loops CCW, holes CW).
double turn(const std::vector<Vec2>& points, std::size_t i) {
  const std::size_t n = points.size() - 1;  // distinct vertices
  const Vec2 before = points[(i + n - 1) % n], at = points[i], after = points[(i + 1) % n];
  const Vec2 a = at - before, b = after - at;
  return std::atan2(cross(a, b), dot(a, b));
}

std::size_t nearest_vertex(const std::vector<Vec2>& points, Vec2 position) {
  std::size_t best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const double d = distance(points[i], position);
    if (d < best_distance) { best_distance = d; best = i; }
  }
  return best;
}

// Start vertex and whether the path runs backwards, for a path started from `position`.
struct Start {
  std::size_t vertex = 0;
  bool reversed = false;
};

Start start_of(const ExtrusionPath& path, SeamPosition seam, Vec2 position) {
  if (closed(path)) {
    return {seam == SeamPosition::aligned ? aligned_seam(path.points)
                                          : nearest_vertex(path.points, position),
            false};
  }
  const bool reversed = !path.points.empty() &&
                        distance(path.points.back(), position) <
                            distance(path.points.front(), position);
  return {reversed ? path.points.size() - 1 : 0, reversed};
}

void begin_at(ExtrusionPath& path, Start start) {
  if (closed(path)) {
    if (start.vertex == 0) return;
    path.points.pop_back();
    std::rotate(path.points.begin(), path.points.begin() + start.vertex, path.points.end());
    path.points.push_back(path.points.front());
  } else if (start.reversed) {
    std::reverse(path.points.begin(), path.points.end());
  }
}

bool segments_meet(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a);
  const double d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  auto on = [](Vec2 p, Vec2 q, Vec2 r, double o) {  // r on segment pq, given collinear
    return o == 0 && std::min(p.x, q.x) <= r.x && r.x <= std::max(p.x, q.x) &&
           std::min(p.y, q.y) <= r.y && r.y <= std::max(p.y, q.y);
  };
  return on(a, b, c, d1) || on(a, b, d, d2) || on(c, d, a, d3) || on(c, d, b, d4);
}

// Whether the travel a-b crosses an edge of the grid's region; only the edges near the
// travel's box are tested.
bool crosses(const BoundaryGrid& boundary, Vec2 a, Vec2 b) {
  bool met = false;
  boundary.for_each_near({std::min(a.x, b.x), std::min(a.y, b.y)},
                         {std::max(a.x, b.x), std::max(a.y, b.y)}, [&](std::uint32_t k) {
                           const Segment2& edge = boundary.segments()[k];
                           met = met || segments_meet(a, b, edge.a, edge.b);
                         });
  return met;
}

}  // namespace

std::string_view seam_position_name(SeamPosition seam) {
  return seam == SeamPosition::nearest ? "nearest" : "aligned";
}

std::optional<SeamPosition> parse_seam_position(std::string_view name) {
  if (name == "aligned") return SeamPosition::aligned;
  if (name == "nearest") return SeamPosition::nearest;
  return std::nullopt;
}

namespace {

// How well a seam hides at vertex i of a closed path: a corner is a turn of more than 30
// degrees; concave ones (turning right) rank first (2), then convex ones (1), then none
// (0); within a class, the sharper.
std::pair<int, double> corner_rank(const std::vector<Vec2>& points, std::size_t i) {
  constexpr double kCorner = 0.5236;
  const double t = turn(points, i);
  if (t < -kCorner) return std::pair{2, -t};
  if (t > kCorner) return std::pair{1, t};
  return std::pair{0, 0.0};
}

}  // namespace

std::size_t aligned_seam(const std::vector<Vec2>& points) {
  if (points.size() < 3) return 0;
  const std::size_t n = points.size() - 1;
  double y_min = points[0].y, y_max = points[0].y;
  for (std::size_t i = 0; i < n; ++i) {
    y_min = std::min(y_min, points[i].y);
    y_max = std::max(y_max, points[i].y);
  }
  const double band = std::max(0.5, 0.02 * (y_max - y_min));
  auto rank = [&](std::size_t i) { return corner_rank(points, i); };
  std::size_t best = n;
  std::pair<int, double> best_rank{-1, 0};
  for (std::size_t i = 0; i < n; ++i) {
    if (points[i].y < y_max - band) continue;
    const auto r = rank(i);
    bool better = best == n || r.first > best_rank.first;
    if (!better && r.first == best_rank.first) {
      if (r.first > 0 && r.second != best_rank.second) {
        better = r.second > best_rank.second;
      } else if (points[i].y != points[best].y) {
        better = points[i].y > points[best].y;
      } else {
        better = points[i].x < points[best].x;
      }
    }
    if (better) { best = i; best_rank = r; }
  }
  return best == n ? 0 : best;
}

std::optional<NearestStart> nearest_start(const std::vector<ExtrusionPath>& paths,
                                          SeamPosition seam, Vec2 position) {
  std::optional<NearestStart> best;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (paths[i].points.empty()) continue;
    const Start start = start_of(paths[i], seam, position);
    const Vec2 p = paths[i].points[start.vertex];
    const double d = distance(p, position);
    if (!best || d < best->distance) best = NearestStart{i, p, d};
  }
  return best;
}

std::size_t remembered_seam(const std::vector<Vec2>& points, PathRole role,
                            const std::vector<Seam>& below, double reach, double radius) {
  if (points.size() < 3) return 0;
  const std::size_t own = aligned_seam(points);
  const std::size_t n = points.size() - 1;
  const bool hole = signed_area(Loop(points.begin(), points.end() - 1)) < 0;
  // The seam below that belongs to this path: same role and direction, nearest to it.
  const Seam* mark = nullptr;
  double nearest = reach;
  for (const Seam& s : below) {
    if (s.role != role || s.hole != hole) continue;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = distance(points[i], s.at);
      if (d <= nearest) { nearest = d; mark = &s; }
    }
  }
  if (!mark) return own;
  // The best corner near it: the higher class, the sharper, the nearer.
  auto key = [&](std::size_t i) {
    const auto [kind, sharpness] = corner_rank(points, i);
    return std::tuple{kind, sharpness, -distance(points[i], mark->at)};
  };
  std::size_t best = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (distance(points[i], mark->at) > std::max(radius, nearest)) continue;
    if (best == n || key(i) > key(best)) best = i;
  }
  // The place below is kept unless it lies on a smooth stretch and the loop has a concave
  // corner to hide the seam in (measured on the bunny, keeping it whenever it is a corner or
  // there is no concave one moves outer seams more than 1 mm between layers 32 times, the
  // per-layer rule 47 times; most of the rest are loops that appear).
  if (best == n) return own;
  if (corner_rank(points, best).first == 0 && corner_rank(points, own).first == 2) return own;
  return best;
}

void append_nearest_first(std::vector<ExtrusionPath> paths, SeamPosition seam, Vec2& position,
                          std::vector<ExtrusionPath>& out, const std::vector<Seam>* below,
                          std::vector<Seam>* laid) {
  std::erase_if(paths, [](const ExtrusionPath& p) { return p.points.empty(); });
  // The aligned seam of a closed path does not depend on the nozzle: find it once.
  std::vector<Start> fixed(paths.size());
  std::vector<bool> is_closed(paths.size());
  for (std::size_t i = 0; i < paths.size(); ++i) {
    is_closed[i] = closed(paths[i]);
    if (!is_closed[i] || seam != SeamPosition::aligned) continue;
    const double w = paths[i].width > 0 ? paths[i].width : 0.45;
    fixed[i] = {below ? remembered_seam(paths[i].points, paths[i].role, *below, 3 * w, w)
                      : aligned_seam(paths[i].points)};
  }
  std::vector<bool> done(paths.size(), false);
  for (std::size_t left = paths.size(); left > 0; --left) {
    std::size_t best = paths.size();
    Start best_start;
    double best_distance = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < paths.size(); ++i) {
      if (done[i]) continue;
      const Start start = is_closed[i] && seam == SeamPosition::aligned
                              ? fixed[i]
                              : start_of(paths[i], seam, position);
      const double d = distance(paths[i].points[start.vertex], position);
      if (d < best_distance) { best_distance = d; best = i; best_start = start; }
    }
    if (best == paths.size()) best = static_cast<std::size_t>(
        std::find(done.begin(), done.end(), false) - done.begin());  // only NaN coordinates
    done[best] = true;
    ExtrusionPath& path = paths[best];
    begin_at(path, best_start);
    position = path.points.back();
    if (laid && is_closed[best]) {
      const bool hole = signed_area(Loop(path.points.begin(), path.points.end() - 1)) < 0;
      laid->push_back({path.role, hole, path.points.front()});
    }
    out.push_back(std::move(path));
  }
}

void mark_retractions(std::vector<ExtrusionPath>& paths, const Region& region,
                      double min_travel) {
  const BoundaryGrid boundary(region);
  for (std::size_t i = 0; i < paths.size(); ++i) {
    if (i == 0 || paths[i].points.empty() || paths[i - 1].points.empty()) {
      paths[i].retract_before = true;
      continue;
    }
    const Vec2 from = paths[i - 1].points.back(), to = paths[i].points.front();
    paths[i].retract_before = distance(from, to) > min_travel && crosses(boundary, from, to);
  }
}

bool crosses_boundary(const Region& region, Vec2 a, Vec2 b) {
  for (const Loop& loop : region.loops) {
    for (std::size_t i = 0, n = loop.size(); i < n && n > 1; ++i) {
      if (segments_meet(a, b, loop[i], loop[(i + 1) % n])) return true;
    }
  }
  return false;
}

}  // namespace geometry
