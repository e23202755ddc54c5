#include "geometry/toolpaths/bead_spacing.h"

#include <cmath>
#include <numbers>

namespace geometry {

// The same cross-section as printer::bead_area (geometry does not depend on printer/;
// tests/printer/bead_model_test.cpp holds the two together).
double bead_spacing(double width, double height) {
  if (!(width > 0)) return 0;
  if (!(height > 0)) return width;
  if (width <= height) return std::numbers::pi * width * width / 4 / height;
  return width - height * (1 - std::numbers::pi / 4);
}

double bead_width_for_spacing(double spacing, double height) {
  if (!(spacing > 0)) return 0;
  if (!(height > 0)) return spacing;
  // A share of at most pi h / 4 is filled by a round strand no wider than it is tall.
  if (spacing <= std::numbers::pi * height / 4) return std::sqrt(4 * spacing * height / std::numbers::pi);
  return spacing + height * (1 - std::numbers::pi / 4);
}

}  // namespace geometry
