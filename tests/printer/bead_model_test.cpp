// The bead model against its closed forms.
#include <initializer_list>
#include <numbers>

#include <doctest/doctest.h>

#include "geometry/toolpaths/bead_spacing.h"
#include "printer/bead_model.h"

namespace bead_model_test {

using namespace printer;
constexpr double pi = std::numbers::pi;

TEST_CASE("bead_is_a_rounded_rectangle") {
  // 0.45 wide, 0.2 tall: a 0.25 x 0.2 rectangle plus a 0.2 mm disc.
  CHECK(bead_area(0.45, 0.2) == doctest::Approx(0.25 * 0.2 + pi * 0.01).epsilon(1e-15));
  // As wide as tall: exactly the disc.
  CHECK(bead_area(0.3, 0.3) == doctest::Approx(pi * 0.09 / 4).epsilon(1e-15));
}

TEST_CASE("narrow_bead_is_a_round_strand") {
  CHECK(bead_area(0.2, 0.4) == doctest::Approx(pi * 0.04 / 4).epsilon(1e-15));
}

TEST_CASE("degenerate_bead_takes_no_filament") {
  CHECK(bead_area(0, 0.2) == 0);
  CHECK(bead_area(0.4, -1) == 0);
  CHECK(filament_for_bead(0.45, 0.2, 0, 1.75) == 0);
  CHECK(filament_for_bead(0.45, 0.2, 10, 0) == 0);
  CHECK(bead_width(0, 10, 0.2, 1.75) == 0);
}

TEST_CASE("filament_length_is_bead_volume_over_filament_section") {
  // 100 mm of a 0.45 x 0.2 bead from 1.75 mm filament at flow 0.9.
  const double expected = (0.25 * 0.2 + pi * 0.01) * 100 / (pi * 1.75 * 1.75 / 4) * 0.9;
  CHECK(filament_for_bead(0.45, 0.2, 100, 1.75, 0.9) == doctest::Approx(expected).epsilon(1e-15));
  CHECK(filament_area(1.75) == doctest::Approx(pi * 1.75 * 1.75 / 4).epsilon(1e-15));
}

TEST_CASE("bead_width_inverts_filament_for_bead") {
  for (double w : {0.15, 0.3, 0.45, 0.8}) {
    const double e = filament_for_bead(w, 0.3, 12.5, 1.75, 1.05);
    CHECK(bead_width(e, 12.5, 0.3, 1.75, 1.05) == doctest::Approx(w).epsilon(1e-12));
  }
}

TEST_CASE("filament_weight_from_density") {
  // 1000 mm of 1.75 mm filament is 2.405 cm^3; ABS at 1.04 g/cm^3.
  CHECK(filament_weight(1000, 1.75, 1.04) ==
        doctest::Approx(pi * 1.75 * 1.75 / 4 * 1000 / 1000 * 1.04).epsilon(1e-15));
  CHECK(filament_weight(1000, 1.75, 1.04) == doctest::Approx(2.5015).epsilon(1e-4));
}

// geometry lays beads out by shares (geometry/toolpaths/bead_spacing.h) without depending on printer/;
// the share times the height must be the cross-section the G-code writer extrudes.
TEST_CASE("geometry_bead_spacing_fills_the_writers_bead_cross_section") {
  for (double h : {0.1, 0.2, 0.35}) {
    for (double w : {0.15, 0.4, 0.45, 0.6}) {
      CAPTURE(h);
      CAPTURE(w);
      CHECK(geometry::bead_spacing(w, h) * h == doctest::Approx(bead_area(w, h)).epsilon(1e-12));
    }
  }
}

}  // namespace bead_model_test
