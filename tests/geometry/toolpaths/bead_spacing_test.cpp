// Bead spacing against its closed form: share x height = the rounded-rectangle cross-section.
#include <initializer_list>
#include "geometry/toolpaths/bead_spacing.h"

#include <numbers>

#include <doctest/doctest.h>

namespace bead_spacing_test {

using geometry::bead_spacing;
using geometry::bead_width_for_spacing;

namespace {
constexpr double pi = std::numbers::pi;
}

// s h = (w - h) h + pi h^2 / 4, worked by hand: 0.45 wide, 0.2 tall -> 0.45 - 0.2 (1 - pi/4).
TEST_CASE("side_by_side_beads_lie_their_cross_section_over_height_apart") {
  CHECK(bead_spacing(0.45, 0.2) == doctest::Approx(0.45 - 0.2 + pi * 0.2 / 4).epsilon(1e-15));
  CHECK(bead_spacing(0.45, 0.2) == doctest::Approx(0.40708).epsilon(1e-5));
  // Taller layers lose more to the rounded sides.
  CHECK(bead_spacing(0.5, 0.3) < bead_spacing(0.5, 0.2));
  // A round strand (w <= h) of area pi w^2 / 4 over height h.
  CHECK(bead_spacing(0.2, 0.4) == doctest::Approx(pi * 0.04 / 4 / 0.4).epsilon(1e-15));
}

TEST_CASE("bead_width_for_spacing_inverts_bead_spacing") {
  for (double h : {0.1, 0.2, 0.3}) {
    for (double w : {0.05, 0.1, 0.3, 0.45, 0.8}) {
      CAPTURE(h);
      CAPTURE(w);
      CHECK(bead_width_for_spacing(bead_spacing(w, h), h) == doctest::Approx(w).epsilon(1e-12));
    }
  }
}

TEST_CASE("bead_spacing_is_total") {
  CHECK(bead_spacing(0, 0.2) == 0);
  CHECK(bead_spacing(-1, 0.2) == 0);
  CHECK(bead_spacing(0.45, 0) == 0.45);  // no height: flat sides, no overlap needed
  CHECK(bead_width_for_spacing(0, 0.2) == 0);
  CHECK(bead_width_for_spacing(0.4, 0) == 0.4);
}

}  // namespace bead_spacing_test
