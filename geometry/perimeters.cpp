#include "geometry/perimeters.h"

#include <cmath>

#include "geometry/clipper_bridge.h"
#include "geometry/thin_walls.h"
#include "geometry/toolpath_clipper.h"

namespace geometry {

namespace {

namespace tc = toolpath_clipper;

// A loop with less length than this is a speck left by the offset, not a printable wall;
// dropping it leaves its area to the thin-wall pass, which covers it if it is wide enough.
constexpr double kMinLoopLength = 0.5;  // in bead widths
// A gap with less area than this is a speck of the offsets, not a wall to print.
constexpr double kMinGapArea = 1.0 / 16;  // in bead widths squared

ExtrusionPath closed_path(const ClipperLib::Path& path, PathRole role, double width) {
  ExtrusionPath result;
  result.role = role;
  result.width = width;
  result.points = from_clipper(path);
  result.points.push_back(result.points.front());
  return result;
}

}  // namespace

Perimeters perimeters(const Region& island, double width, int count) {
  Perimeters result;
  if (!(width > 0) || count <= 0) {
    if (count <= 0) result.infill_area = island;
    return result;
  }
  // inside: the part of the island not yet covered by the loops made so far.
  tc::Paths inside = tc::union_of(to_clipper(island));
  tc::Paths gaps;
  for (int k = 0; k < count && !inside.empty(); ++k) {
    // The loop's centre line, w/2 inside. Where its two sides would come closer than half a
    // bead the loop would lay its beads on top of each other: that part (under 1.5 beads
    // wide) is cut away (an opening by w/4) and left to a thin wall.
    tc::Paths centre = tc::offset(tc::offset(inside, -0.75 * width), width / 4);
    std::erase_if(centre, [&](const ClipperLib::Path& path) {
      double length = 0;
      for (std::size_t i = 0; i < path.size(); ++i) {
        const Vec2 d = from_clipper(path[(i + 1) % path.size()]) - from_clipper(path[i]);
        length += std::hypot(d.x, d.y);
      }
      return length < kMinLoopLength * width;
    });
    // What the loop's bead covers, corners taken as sharp: a bead rounds them, but the sliver
    // it misses at a corner is not a wall to print.
    const tc::Paths covered = tc::offset(centre, width / 2, ClipperLib::jtMiter, 10.0);
    tc::Paths gap = tc::difference(inside, covered);
    // The difference is mostly specks along the edge where the offsets round off short
    // edges; a piece of wall to print has at least a quarter bead square of area.
    const double min_gap = kMinGapArea * width * width * kClipperScale * kClipperScale;
    std::erase_if(gap, [&](const auto& path) { return std::abs(ClipperLib::Area(path)) < min_gap; });
    if (!gap.empty()) {
      // Slivers narrower than a quarter bead are offset noise, not walls.
      gap = tc::opening(gap, width / 8);
      gaps.insert(gaps.end(), gap.begin(), gap.end());
    }
    if (!centre.empty()) {
      std::vector<ExtrusionPath> loops;
      const PathRole role = k == 0 ? PathRole::outer_wall : PathRole::inner_wall;
      for (const auto& path : centre) loops.push_back(closed_path(path, role, width));
      result.walls.push_back(std::move(loops));
    }
    inside = tc::offset(centre, -width / 2);
  }
  if (!gaps.empty()) {
    result.thin_walls = thin_walls(from_clipper(tc::union_of(gaps)), width / 4, 1.5 * width);
  }
  result.infill_area = from_clipper(inside);
  return result;
}

}  // namespace geometry
