#include "geometry/core/clipper_bridge.h"

namespace geometry {

ClipperLib::IntPoint to_clipper(Vec2 p) {
  return {rounded_units(p.x * kClipperScale), rounded_units(p.y * kClipperScale)};
}

Vec2 from_clipper(const ClipperLib::IntPoint& p) {
  return {static_cast<double>(p.X) / kClipperScale, static_cast<double>(p.Y) / kClipperScale};
}

ClipperLib::Path to_clipper(const Loop& loop) {
  ClipperLib::Path path;
  path.reserve(loop.size());
  for (Vec2 p : loop) path.push_back(to_clipper(p));
  return path;
}

ClipperLib::Paths to_clipper(const Region& region) {
  ClipperLib::Paths paths;
  paths.reserve(region.loops.size());
  for (const Loop& loop : region.loops) paths.push_back(to_clipper(loop));
  return paths;
}

Loop from_clipper(const ClipperLib::Path& path) {
  Loop loop;
  loop.reserve(path.size());
  for (const auto& p : path) loop.push_back(from_clipper(p));
  return loop;
}

Region from_clipper(const ClipperLib::Paths& paths) {
  Region region;
  region.loops.reserve(paths.size());
  for (const auto& path : paths) region.loops.push_back(from_clipper(path));
  return region;
}

Region from_clipper(const ClipperLib::PolyTree& tree) {
  Region region;
  for (const ClipperLib::PolyNode* node = tree.GetFirst(); node; node = node->GetNext()) {
    if (node->IsOpen()) continue;
    ClipperLib::Path path = node->Contour;
    // Outer boundaries and islands CCW, holes CW, whatever orientation Clipper returned.
    if (ClipperLib::Orientation(path) == node->IsHole()) ClipperLib::ReversePath(path);
    region.loops.push_back(from_clipper(path));
  }
  return region;
}

}  // namespace geometry
