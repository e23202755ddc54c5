#include "geometry/toolpaths/brim.h"

#include <cmath>

#include "geometry/toolpaths/skirt.h"

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
  return loops_around(footprint, width / 2, width, loop_count(width, brim_width), PathRole::brim);
}

}  // namespace geometry
