#include "geometry/toolpath_clipper.h"

#include "geometry/clipper_bridge.h"
#include "geometry/douglas_peucker.h"

#include <cmath>

namespace geometry::toolpath_clipper {

namespace {

// Round joins within this distance of the true arc: finer than any printer resolves, coarse
// enough that a 0.2 mm arc has a dozen points rather than thousands of nanometre steps.
constexpr double kArcTolerance = 0.005;  // mm

// A loop with less area than a micrometre square is a sliver of rounding, in nm^2.
constexpr double kNoArea = 1e6;

Paths boolean(const Paths& a, const Paths& b, ClipperLib::ClipType type) {
  ClipperLib::Clipper clipper;
  clipper.AddPaths(a, ClipperLib::ptSubject, true);
  clipper.AddPaths(b, ClipperLib::ptClip, true);
  Paths result;
  clipper.Execute(type, result, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return result;
}

}  // namespace

Paths offset(const Paths& region, double delta, ClipperLib::JoinType join, double miter_limit) {
  if (region.empty()) return {};
  ClipperLib::ClipperOffset offsetter(miter_limit, kArcTolerance * kClipperScale);
  // ClipperOffset takes the orientation of the loop with the lowest vertex for that of every
  // outer loop: a loop of next to no area there (a union leaves such slivers where two
  // pieces touch at the edge), if it runs the other way, turns the whole region inside out.
  // Such loops are nothing to offset.
  for (const Path& path : region) {
    if (std::abs(ClipperLib::Area(path)) >= kNoArea) {
      offsetter.AddPath(path, join, ClipperLib::etClosedPolygon);
    }
  }
  Paths result;
  offsetter.Execute(result, delta * kClipperScale);
  return result;
}

Paths opening(const Paths& region, double radius) {
  return offset(offset(region, -radius), radius);
}

Paths intersection(const Paths& a, const Paths& b) {
  if (a.empty() || b.empty()) return {};
  return boolean(a, b, ClipperLib::ctIntersection);
}

Paths difference(const Paths& a, const Paths& b) {
  if (a.empty()) return {};
  if (b.empty()) return a;
  return boolean(a, b, ClipperLib::ctDifference);
}

Paths union_of(const Paths& a, const Paths& b) { return boolean(a, b, ClipperLib::ctUnion); }

Paths clip_open(const Paths& lines, const Paths& region) {
  if (lines.empty() || region.empty()) return {};
  ClipperLib::Clipper clipper;
  clipper.AddPaths(lines, ClipperLib::ptSubject, false);
  clipper.AddPaths(region, ClipperLib::ptClip, true);
  ClipperLib::PolyTree tree;
  clipper.Execute(ClipperLib::ctIntersection, tree, ClipperLib::pftNonZero,
                  ClipperLib::pftNonZero);
  Paths result;
  ClipperLib::OpenPathsFromPolyTree(tree, result);
  return result;
}

std::vector<Paths> islands(const Paths& region) {
  std::vector<Paths> result;
  if (region.empty()) return result;
  ClipperLib::Clipper clipper;
  clipper.AddPaths(region, ClipperLib::ptSubject, true);
  ClipperLib::PolyTree tree;
  clipper.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  for (const ClipperLib::PolyNode* node = tree.GetFirst(); node; node = node->GetNext()) {
    if (node->IsHole() || node->IsOpen()) continue;
    Paths island{node->Contour};
    if (!ClipperLib::Orientation(island.front())) ClipperLib::ReversePath(island.front());
    for (const ClipperLib::PolyNode* hole : node->Childs) {
      island.push_back(hole->Contour);
      if (ClipperLib::Orientation(island.back())) ClipperLib::ReversePath(island.back());
    }
    result.push_back(std::move(island));
  }
  return result;
}

namespace {

// Squared distance from p to the segment [a, b], in units^2 (doubles: nm^2 overflows int64).
double distance2(const ClipperLib::IntPoint& p, const ClipperLib::IntPoint& a,
                 const ClipperLib::IntPoint& b) {
  const double abx = double(b.X - a.X), aby = double(b.Y - a.Y);
  const double apx = double(p.X - a.X), apy = double(p.Y - a.Y);
  const double length2 = abx * abx + aby * aby;
  double t = length2 > 0 ? (apx * abx + apy * aby) / length2 : 0;
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  const double dx = apx - t * abx, dy = apy - t * aby;
  return dx * dx + dy * dy;
}

}  // namespace

Paths simplified(const Paths& region, double tolerance) {
  const double limit2 = tolerance * kClipperScale * tolerance * kClipperScale;
  Paths result;
  result.reserve(region.size());
  for (const Path& path : region) {
    const std::size_t n = path.size();
    if (n < 3) continue;
    const std::vector<char> keep =
        douglas_peucker_keep(n, limit2, [&](std::size_t i, std::size_t a, std::size_t b) {
          return distance2(path[i], path[a], path[b]);
        });
    Path kept;
    for (std::size_t i = 0; i < n; ++i) {
      if (keep[i]) kept.push_back(path[i]);
    }
    if (kept.size() >= 3) result.push_back(std::move(kept));
  }
  return result;
}

double area_mm2(const Paths& region) {
  double total = 0;
  for (const Path& path : region) total += ClipperLib::Area(path);
  return total / (kClipperScale * kClipperScale);
}

}  // namespace geometry::toolpath_clipper
