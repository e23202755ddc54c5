#include "geometry/toolpaths/brim.h"

#include <cmath>

#include "geometry/core/clipper.h"

namespace geometry {

namespace {

int loop_count(double width, double brim_width) {
  if (!(width > 0) || !(brim_width > 0)) return 0;
  // A brim a hair under a whole number of beads is that many beads, not one more.
  return static_cast<int>(std::ceil(brim_width / width - 1e-9));
}

}  // namespace

double brim_extent(double width, double brim_width) {
  return loop_count(width, brim_width) * width;
}

std::vector<ExtrusionPath> brim(const Region& footprint, double width, double brim_width) {
  std::vector<ExtrusionPath> result;
  const int loops = loop_count(width, brim_width);
  const clipper::Paths part = clipper::union_nonzero(to_clipper(footprint));
  if (part.empty() || loops <= 0) return result;
  for (int k = loops - 1; k >= 0; --k) {
    for (const auto& path : clipper::offset(part, width / 2 + k * width, ClipperLib::jtRound)) {
      if (!ClipperLib::Orientation(path)) continue;  // a hole of the grown outline
      ExtrusionPath loop;
      loop.role = PathRole::brim;
      loop.width = width;
      loop.points = from_clipper(path);
      loop.points.push_back(loop.points.front());
      result.push_back(std::move(loop));
    }
  }
  return result;
}

}  // namespace geometry
