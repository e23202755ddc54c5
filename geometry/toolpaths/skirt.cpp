#include "geometry/toolpaths/skirt.h"

#include <algorithm>

#include "geometry/core/clipper.h"

namespace geometry {

std::vector<ExtrusionPath> skirt(const Region& first_layer, double width, int loops,
                                 double distance) {
  std::vector<ExtrusionPath> result;
  const clipper::Paths part = clipper::union_nonzero(to_clipper(first_layer));
  if (part.empty() || loops <= 0 || !(width > 0)) return result;
  distance = std::max(distance, 0.0);
  for (int k = loops - 1; k >= 0; --k) {
    const double grow = distance + width / 2 + k * width;
    for (const auto& path : clipper::offset(part, grow, ClipperLib::jtRound)) {
      if (!ClipperLib::Orientation(path)) continue;  // a hole of the grown outline: inside
      ExtrusionPath loop;
      loop.role = PathRole::skirt;
      loop.width = width;
      loop.points = from_clipper(path);
      loop.points.push_back(loop.points.front());
      result.push_back(std::move(loop));
    }
  }
  return result;
}

}  // namespace geometry
