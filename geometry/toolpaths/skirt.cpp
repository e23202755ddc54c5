#include "geometry/toolpaths/skirt.h"

#include <algorithm>

#include "geometry/core/clipper_bridge.h"
#include "geometry/core/toolpath_clipper.h"

namespace geometry {

std::vector<ExtrusionPath> skirt(const Region& first_layer, double width, int loops,
                                 double distance) {
  namespace tc = toolpath_clipper;
  std::vector<ExtrusionPath> result;
  const tc::Paths part = tc::union_of(to_clipper(first_layer));
  if (part.empty() || loops <= 0 || !(width > 0)) return result;
  distance = std::max(distance, 0.0);
  for (int k = loops - 1; k >= 0; --k) {
    const double grow = distance + width / 2 + k * width;
    for (const auto& path : tc::offset(part, grow, ClipperLib::jtRound)) {
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
