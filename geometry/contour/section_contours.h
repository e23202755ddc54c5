// The two cross-section strategies (contour_strategy.h): the model's section at one plane.
//   lower: at the layer's bottom z_lo, the paper's "traditional" contour, its baseline;
//   mid:   at the layer's middle, what PrusaSlicer, Slic3r and CuraEngine print.
// Both from LayerStack (its lower section is the limit from above at z_lo, layer_stack.h).
// Output: the section, mm, and the height it was cut at.
#pragma once

#include "geometry/contour/contour_input.h"

namespace geometry {

ContourResult lower_strategy(const ContourInput& input);
ContourResult mid_strategy(const ContourInput& input);

}  // namespace geometry
