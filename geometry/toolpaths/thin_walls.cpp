#include "geometry/toolpaths/thin_walls.h"

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
#include "geometry/toolpaths/segment_medial_axis.h"

namespace geometry {

namespace {

// A run of a centre line is printed at one width while the strip's width stays within this
// fraction of the run's mean: a bead wider than the strip lays its excess outside it.
constexpr double kRunTolerance = 0.1;

// Round bead ends and joins within this of the arc, mm.
constexpr double kBeadArcTolerance = 0.005;

std::vector<ExtrusionPath> centre_lines(const Region& region, double min_width,
                                        double max_width) {
  std::vector<ExtrusionPath> paths;
  if (!(min_width > 0) || !(max_width >= min_width)) return paths;
  // The narrowest bead is printed along the axis wherever the region is at least that wide.
  SegmentMedialAxis axis = segment_medial_axis(region, min_width / 2, max_width);
  prune_spurs(axis);
  const Vec2 origin = axis.origin;
  for (const auto& chain : axis_chains(axis)) {
    const bool cycle = chain.size() > 2 && chain.front() == chain.back();
    // The chain's points, with steps inserted where the width changes along one edge (a
    // tapering wall is a single Voronoi edge), the radius interpolated linearly.
    std::vector<Vec2> at;
    std::vector<double> radius;
    for (std::size_t k = 0; k + 1 < chain.size(); ++k) {
      const Vec2 p = axis.points[chain[k]], q = axis.points[chain[k + 1]];
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
      const double segment = length(at[k + 1] - at[k]);
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
  const auto at = [&](const ClipperLib::IntPoint& p) {
    return Vec2{double(p.X - o.X) / kClipperScale, double(p.Y - o.Y) / kClipperScale};
  };
  SecondMoments m;
  for (const auto& path : piece) {
    for (std::size_t i = 0, n = path.size(); i < n; ++i) {
      add_edge_moments(m, at(path[i]), at(path[(i + 1) % n]));
    }
  }
  const double a = m.area;
  if (!(a > 0)) return std::nullopt;
  const double cx = m.mx / a, cy = m.my / a;
  const double ixx = m.mxx - a * cx * cx, iyy = m.myy - a * cy * cy, ixy = m.mxy - a * cx * cy;
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

}  // namespace

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
    const ClipperLib::IntRect outline = clipper::bounding_box(piece[0]);
    const double box = max_width * kClipperScale;
    if (static_cast<double>(outline.right - outline.left) <= box &&
        static_cast<double>(outline.bottom - outline.top) <= box) {
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
