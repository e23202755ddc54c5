#include "geometry/contour/section_contours.h"

namespace geometry {

ContourResult lower_strategy(const ContourInput& input) {
  return {input.stack.lower(input.layer), input.stack.layers()[input.layer].z_lo};
}

ContourResult mid_strategy(const ContourInput& input) {
  return {input.stack.mid(input.layer), input.stack.layers()[input.layer].z_mid()};
}

}  // namespace geometry
