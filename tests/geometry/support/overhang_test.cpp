// overhang: the part of a layer the layer below does not carry, against closed forms.
#include "geometry/support/overhang.h"

#include <doctest/doctest.h>

#include <cmath>

namespace overhang_test {

using namespace geometry;

namespace {

Region rectangle(double x0, double y0, double x1, double y1) {
  return Region{{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}};
}

Region square(double side) { return rectangle(-side / 2, -side / 2, side / 2, side / 2); }

}  // namespace

TEST_CASE("reach_is_the_angle_over_a_layer_at_most_half_a_bead") {
  CHECK(overhang_reach(0.2, 45, 0.45) == doctest::Approx(0.2));
  CHECK(overhang_reach(0.1, 60, 0.45) == doctest::Approx(0.1 * std::sqrt(3.0)));
  CHECK(overhang_reach(0.2, 60, 0.45) == doctest::Approx(0.225));  // 0.346 capped
  CHECK(overhang_reach(0.2, 0, 0.45) == 0);
  CHECK(overhang_reach(0, 45, 0.45) == 0);
}

TEST_CASE("wings_of_a_t_overhang_whole_beyond_the_stem") {
  // A 50 x 10 bar over a 10 x 10 stem: two 20 x 10 wings.
  const Region bar = rectangle(-25, -5, 25, 5), stem = square(10);
  const Region wings = overhang(bar, stem, 0.2, 0.2);
  CHECK(area(wings) == doctest::Approx(400).epsilon(1e-6));
  CHECK(wings.loops.size() == 2);
}

TEST_CASE("a_wall_leaning_within_the_reach_needs_nothing") {
  // 0.15 mm out on every side, the reach 0.2 mm.
  CHECK(overhang(square(10.3), square(10), 0.2, 0.2).loops.empty());
}

TEST_CASE("a_steep_wall_overhangs_from_the_edge_of_the_layer_below") {
  // 1 mm out on every side: the whole band, not only what lies beyond the reach.
  const Region band = overhang(square(12), square(10), 0.2, 0.2);
  CHECK(area(band) == doctest::Approx(144 - 100).epsilon(1e-6));
}

TEST_CASE("specks_smaller_than_the_least_area_are_left_alone") {
  Region region = square(10);
  region.loops.push_back(rectangle(20, 0, 20.3, 0.3).loops.front());  // 0.09 mm^2
  region.loops.push_back(rectangle(30, 0, 31, 1).loops.front());      // 1 mm^2
  const Region pieces = overhang(region, square(10), 0.2, 0.2);
  CHECK(area(pieces) == doctest::Approx(1).epsilon(1e-6));
}

TEST_CASE("an_island_over_nothing_overhangs_whole") {
  CHECK(area(overhang(square(4), Region{}, 0.2, 0.2)) == doctest::Approx(16));
}

TEST_CASE("an_empty_layer_has_no_overhang") {
  CHECK(overhang(Region{}, square(10), 0.2, 0.2).loops.empty());
}

}  // namespace overhang_test
