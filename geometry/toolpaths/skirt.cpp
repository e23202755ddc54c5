#include "geometry/toolpaths/skirt.h"

#include <algorithm>

#include "geometry/core/clipper.h"

namespace geometry {

std::vector<ExtrusionPath> loops_around(const Region& part, double first, double width,
                                        int loops, PathRole role) {
  std::vector<ExtrusionPath> result;
  const clipper::Paths outline = clipper::union_nonzero(to_clipper(part));
  if (outline.empty() || loops <= 0 || !(width > 0)) return result;
  for (int k = loops - 1; k >= 0; --k) {
    for (const auto& path : clipper::offset(outline, first + k * width, ClipperLib::jtRound)) {
      if (!ClipperLib::Orientation(path)) continue;  // a hole of the grown outline: inside
      ExtrusionPath loop;
      loop.role = role;
      loop.width = width;
      loop.points = from_clipper(path);
      loop.points.push_back(loop.points.front());
      result.push_back(std::move(loop));
    }
  }
  return result;
}

std::vector<ExtrusionPath> skirt(const Region& first_layer, double width, int loops,
                                 double distance) {
  return loops_around(first_layer, std::max(distance, 0.0) + width / 2, width, loops,
                      PathRole::skirt);
}

}  // namespace geometry
