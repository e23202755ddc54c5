#include "geometry/support/bridge_detector.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "geometry/core/clipper.h"
#include "geometry/core/point_in_region.h"

namespace geometry {

namespace {

// The trial lines run this far past the area's edge, and an end lands on an anchor if the
// anchors grown by twice this hold it (mm): the area's edge is the anchors' edge, up to the
// offsets' rounding.
constexpr double kReach = 0.02;
// Directions tried, degrees apart, then around the best of them.
constexpr double kStep = 10;
constexpr double kFineStep = 2.5;
// The first look: lines this many across the piece at most; below this share held at both
// ends in every direction it takes, a piece is no bridge.
constexpr double kCoarseLines = 8;
constexpr double kHopeless = 0.5;
// Shares within this of the best count as equal, and the shorter span wins.
constexpr double kShareTie = 0.005;
constexpr double kAnchoredShare = 0.98;

struct Trial {
  double share = 0, span = 0;
};

Trial try_direction(double angle, const clipper::Paths& area, const clipper::Paths& reached,
                    const clipper::Paths& anchors, double spacing) {
  const double a = angle * std::numbers::pi / 180;
  const Vec2 d{std::cos(a), std::sin(a)}, n{-d.y, d.x};
  double lo = 1e300, hi = -1e300, dlo = 1e300, dhi = -1e300;
  for (const auto& loop : area) {
    for (const auto& q : loop) {
      const Vec2 p = from_clipper(q);
      lo = std::min(lo, dot(p, n));
      hi = std::max(hi, dot(p, n));
      dlo = std::min(dlo, dot(p, d));
      dhi = std::max(dhi, dot(p, d));
    }
  }
  clipper::Paths lines;
  for (double o = lo + spacing / 2; o <= hi; o += spacing) {
    lines.push_back({to_clipper(o * n + (dlo - 1) * d), to_clipper(o * n + (dhi + 1) * d)});
  }
  if (lines.empty()) {
    const double o = (lo + hi) / 2;
    lines.push_back({to_clipper(o * n + (dlo - 1) * d), to_clipper(o * n + (dhi + 1) * d)});
  }
  Trial trial;
  double total = 0, held = 0;
  for (const auto& piece : clipper::clip_open(lines, reached)) {
    if (piece.size() < 2) continue;
    double length = 0;
    for (std::size_t i = 1; i < piece.size(); ++i) {
      const Vec2 step = from_clipper(piece[i]) - from_clipper(piece[i - 1]);
      length += std::hypot(step.x, step.y);
    }
    total += length;
    if (clipper::point_in_region(anchors, piece.front()) &&
        clipper::point_in_region(anchors, piece.back())) {
      held += length;
      trial.span = std::max(trial.span, length);
    }
  }
  trial.share = total > 0 ? held / total : 0;
  return trial;
}

// Direction from the centroid of the largest anchor to that of the second largest, degrees.
std::optional<double> between_largest(const clipper::Paths& anchors) {
  struct Piece {
    double area;
    Vec2 centroid;
  };
  std::vector<Piece> pieces;
  for (const clipper::Paths& island : clipper::islands(anchors)) {
    double twice = 0;
    Vec2 sum{};
    for (const auto& path : island) {
      for (std::size_t i = 0, m = path.size(); i < m; ++i) {
        const Vec2 p = from_clipper(path[i]), q = from_clipper(path[(i + 1) % m]);
        const double c = cross(p, q);
        twice += c;
        sum = sum + c * (p + q);
      }
    }
    if (twice > 0) pieces.push_back({twice / 2, (1.0 / (3 * twice)) * sum});
  }
  if (pieces.size() < 2) return std::nullopt;
  std::partial_sort(pieces.begin(), pieces.begin() + 2, pieces.end(),
                    [](const Piece& x, const Piece& y) { return x.area > y.area; });
  const Vec2 v = pieces[1].centroid - pieces[0].centroid;
  if (v.x == 0 && v.y == 0) return std::nullopt;
  double angle = std::atan2(v.y, v.x) * 180 / std::numbers::pi;
  angle = std::fmod(angle + 360, 180);
  return angle;
}

}  // namespace

BridgeDirection bridge_direction(const ClipperLib::Paths& area, const ClipperLib::Paths& anchors,
                                 double spacing) {
  BridgeDirection best;
  if (area.empty() || anchors.empty() || !(spacing > 0)) return best;
  const clipper::Paths reached = clipper::offset(area, kReach);
  const clipper::Paths held = clipper::offset(anchors, 2 * kReach);
  // Most unsupported pieces are bands along one wall, held on one side: a few directions
  // with lines far apart show it, before every direction is tried at the full spacing.
  double extent = 0;
  for (const auto& loop : area) {
    const ClipperLib::IntRect box = [&] {
      ClipperLib::Clipper c;
      c.AddPath(loop, ClipperLib::ptSubject, true);
      return c.GetBounds();
    }();
    extent = std::max(extent, std::max(double(box.right - box.left), double(box.bottom - box.top)) / kClipperScale);
  }
  const std::optional<double> centroids = between_largest(anchors);
  std::vector<double> coarse{0, 45, 90, 135};
  if (centroids) coarse.push_back(*centroids);
  double most = 0;
  for (double angle : coarse) {
    most = std::max(most, try_direction(angle, area, reached, held, std::max(spacing, extent / kCoarseLines)).share);
  }
  if (most < kHopeless) {
    best.anchored_share = most;
    return best;
  }
  std::vector<double> angles;
  for (double a = 0; a < 180; a += kStep) angles.push_back(a);
  if (centroids) angles.push_back(*centroids);
  std::vector<Trial> trials;
  for (double angle : angles) trials.push_back(try_direction(angle, area, reached, held, spacing));
  // Around the best so far, every kFineStep.
  std::size_t top = 0;
  for (std::size_t i = 1; i < trials.size(); ++i) {
    if (trials[i].share > trials[top].share + kShareTie ||
        (trials[i].share >= trials[top].share - kShareTie && trials[i].span < trials[top].span)) {
      top = i;
    }
  }
  const double around = angles[top];
  for (double d = -kStep + kFineStep; d < kStep - 1e-9; d += kFineStep) {
    if (std::abs(d) < 1e-9) continue;
    angles.push_back(std::fmod(around + d + 180, 180));
    trials.push_back(try_direction(angles.back(), area, reached, held, spacing));
  }
  for (const Trial& t : trials) most = std::max(most, t.share);
  bool found = false;
  for (std::size_t i = 0; i < trials.size(); ++i) {
    if (trials[i].share < most - kShareTie) continue;
    if (!found || trials[i].span < best.span) {
      best.angle = angles[i];
      best.span = trials[i].span;
      best.anchored_share = trials[i].share;
      found = true;
    }
  }
  best.anchored = best.anchored_share >= kAnchoredShare;
  return best;
}

BridgeDirection bridge_direction(const Region& area, const Region& anchors, double spacing) {
  return bridge_direction(to_clipper(area), to_clipper(anchors), spacing);
}

}  // namespace geometry
