#include "geometry/infill.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/clipper_bridge.h"
#include "geometry/thin_walls.h"
#include "geometry/toolpath_clipper.h"

namespace geometry {

namespace {

namespace tc = toolpath_clipper;

// Rotation by -angle takes the area into a frame where the lines run along +X.
struct Frame {
  double c, s;
  explicit Frame(double angle_degrees)
      : c(std::cos(angle_degrees * std::numbers::pi / 180)),
        s(std::sin(angle_degrees * std::numbers::pi / 180)) {}
  Vec2 into(Vec2 p) const { return {p.x * c + p.y * s, -p.x * s + p.y * c}; }
  Vec2 out(Vec2 p) const { return {p.x * c - p.y * s, p.x * s + p.y * c}; }
};

// Lines at heights first + k * spacing (k = 0, 1, ...) in the rotated frame, clipped to area.
std::vector<ExtrusionPath> lines(const Frame& frame, double first, double spacing,
                                 double y_max, double x_min, double x_max,
                                 const tc::Paths& rotated, PathRole role, double width) {
  // More lines than this means a spacing no printer can lay down (nanometres over a bed).
  constexpr double kMaxLines = 1e6;
  if ((y_max - first) / spacing > kMaxLines) return {};
  tc::Paths scan;
  for (std::size_t k = 0;; ++k) {
    const double y = first + static_cast<double>(k) * spacing;
    if (y > y_max) break;
    scan.push_back({to_clipper(Vec2{x_min - 1, y}), to_clipper(Vec2{x_max + 1, y})});
  }
  std::vector<ExtrusionPath> result;
  for (const auto& piece : tc::clip_open(scan, rotated)) {
    if (piece.size() < 2) continue;
    ExtrusionPath path;
    path.role = role;
    path.width = width;
    for (const auto& p : piece) path.points.push_back(frame.out(from_clipper(p)));
    result.push_back(std::move(path));
  }
  // Clipper returns pieces in no promised order; sort so the output never depends on it.
  std::sort(result.begin(), result.end(), [&](const ExtrusionPath& a, const ExtrusionPath& b) {
    const Vec2 pa = frame.into(a.points.front()), pb = frame.into(b.points.front());
    return pa.y != pb.y ? pa.y < pb.y : pa.x < pb.x;
  });
  return result;
}

struct Rotated {
  tc::Paths paths;
  double x_min = 0, x_max = 0, y_min = 0, y_max = 0;
  bool empty() const { return paths.empty(); }
};

Rotated rotate(const Region& area, const Frame& frame) {
  Rotated r;
  bool any = false;
  for (const Loop& loop : area.loops) {
    if (loop.size() < 3) continue;
    ClipperLib::Path path;
    for (Vec2 p : loop) {
      const Vec2 q = frame.into(p);
      if (!any) { r.x_min = r.x_max = q.x; r.y_min = r.y_max = q.y; any = true; }
      r.x_min = std::min(r.x_min, q.x); r.x_max = std::max(r.x_max, q.x);
      r.y_min = std::min(r.y_min, q.y); r.y_max = std::max(r.y_max, q.y);
      path.push_back(to_clipper(q));
    }
    r.paths.push_back(std::move(path));
  }
  return r;
}

}  // namespace

std::string_view infill_pattern_name(InfillPattern pattern) {
  switch (pattern) {
    case InfillPattern::rectilinear: return "rectilinear";
    case InfillPattern::grid: return "grid";
  }
  return "grid";
}

std::optional<InfillPattern> parse_infill_pattern(std::string_view name) {
  if (name == "rectilinear") return InfillPattern::rectilinear;
  if (name == "grid") return InfillPattern::grid;
  return std::nullopt;
}

std::vector<ExtrusionPath> hatch(const Region& area, double spacing, double angle,
                                 PathRole role, double width) {
  if (!(spacing > 0) || !(width > 0)) return {};
  const Frame frame(angle);
  const Rotated r = rotate(area, frame);
  if (r.empty()) return {};
  const double first = std::ceil(r.y_min / spacing) * spacing;
  return lines(frame, first, spacing, r.y_max, r.x_min, r.x_max, r.paths, role, width);
}

std::vector<ExtrusionPath> sparse_infill(const Region& area, double width, double density,
                                         InfillPattern pattern, double angle,
                                         std::size_t layer_index) {
  density = std::min(density, 100.0);
  if (!(density > 0) || !(width > 0)) return {};
  const double spacing = width * 100 / density;
  if (pattern == InfillPattern::rectilinear) {
    const double layer_angle = angle + (layer_index % 2 ? 90 : 0);
    return hatch(area, spacing, layer_angle, PathRole::sparse_infill, width);
  }
  std::vector<ExtrusionPath> result = hatch(area, 2 * spacing, angle, PathRole::sparse_infill,
                                            width);
  std::vector<ExtrusionPath> across = hatch(area, 2 * spacing, angle + 90,
                                            PathRole::sparse_infill, width);
  result.insert(result.end(), across.begin(), across.end());
  return result;
}

std::vector<ExtrusionPath> solid_infill(const Region& area, double width, double angle,
                                        std::size_t layer_index, PathRole role) {
  if (!(width > 0)) return {};
  const Frame frame(angle + (layer_index % 2 ? 90 : 0));
  const Rotated r = rotate(area, frame);
  if (r.empty()) return {};
  const double extent = r.y_max - r.y_min;
  const double count = std::max(1.0, std::round(extent / width));
  const double spacing = extent > 0 ? extent / count : width;
  std::vector<ExtrusionPath> result =
      lines(frame, r.y_min + spacing / 2, spacing, r.y_max, r.x_min, r.x_max, r.paths, role,
            width);

  // Where an edge of the area runs along the lines between two of them, a strip up to half a
  // bead wide stays bare: fill it with a centre line, as the walls' thin walls do.
  ClipperLib::ClipperOffset beads(2.0, 0.005 * kClipperScale);
  for (const ExtrusionPath& line : result) {
    ClipperLib::Path path;
    for (Vec2 p : line.points) path.push_back(to_clipper(p));
    beads.AddPath(path, ClipperLib::jtRound, ClipperLib::etOpenRound);
  }
  tc::Paths covered;
  beads.Execute(covered, width / 2 * kClipperScale);
  tc::Paths bare = tc::difference(tc::union_of(to_clipper(area)), covered);
  const double speck = width * width / 16 * kClipperScale * kClipperScale;
  std::erase_if(bare, [&](const auto& path) { return std::abs(ClipperLib::Area(path)) < speck; });
  bare = tc::opening(bare, width / 8);
  for (ExtrusionPath& gap : thin_walls(from_clipper(bare), width / 4, width)) {
    gap.role = role;
    result.push_back(std::move(gap));
  }
  return result;
}

}  // namespace geometry
