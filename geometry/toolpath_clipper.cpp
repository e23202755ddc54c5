#include "geometry/toolpath_clipper.h"

#include "geometry/clipper_bridge.h"

namespace geometry::toolpath_clipper {

namespace {

// Round joins within this distance of the true arc: finer than any printer resolves, coarse
// enough that a 0.2 mm arc has a dozen points rather than thousands of nanometre steps.
constexpr double kArcTolerance = 0.005;  // mm

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
  offsetter.AddPaths(region, join, ClipperLib::etClosedPolygon);
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

double area_mm2(const Paths& region) {
  double total = 0;
  for (const Path& path : region) total += ClipperLib::Area(path);
  return total / (kClipperScale * kClipperScale);
}

}  // namespace geometry::toolpath_clipper
