// skirt: loops around the first layer at a distance.
#include "geometry/toolpaths/skirt.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "geometry/toolpaths/toolpath_shapes.h"

namespace skirt_test {

using namespace geometry;
using namespace toolpath_shapes;

namespace {

constexpr double w = 0.5;

// Distance from p to the axis-aligned square [0, s]^2 (p outside it).
double distance_to_square(Vec2 p, double s) {
  const double dx = std::max({0.0, -p.x, p.x - s}), dy = std::max({0.0, -p.y, p.y - s});
  return std::hypot(dx, dy);
}

}  // namespace

TEST_CASE("skirt_loop_keeps_its_distance_from_the_part") {
  // The loop's centre line runs distance + w/2 from the square: a rounded square of area
  // (s + 2r)^2 - (4 - pi) r^2 with r = 3.25 (round corners within 5 um).
  const Region square{{rectangle(0, 0, 10, 10)}};
  const auto loops = skirt(square, w, 1, 3);
  REQUIRE(loops.size() == 1);
  const auto& loop = loops[0];
  CHECK(loop.role == PathRole::skirt);
  CHECK(loop.width == w);
  CHECK(is_closed(loop));
  const double r = 3 + w / 2;
  for (Vec2 p : loop.points) CHECK(distance_to_square(p, 10) == doctest::Approx(r).epsilon(0.002));
  CHECK(signed_area(loop_of(loop)) ==
        doctest::Approx(std::pow(10 + 2 * r, 2) - (4 - std::numbers::pi) * r * r).epsilon(1e-3));
}

TEST_CASE("skirt_loops_are_one_width_apart_outermost_first") {
  const Region square{{rectangle(0, 0, 10, 10)}};
  const auto loops = skirt(square, w, 3, 2);
  REQUIRE(loops.size() == 3);
  for (int k = 0; k < 3; ++k) {
    const double r = 2 + w / 2 + (2 - k) * w;
    for (Vec2 p : loops[k].points) {
      CHECK(distance_to_square(p, 10) == doctest::Approx(r).epsilon(0.002));
    }
  }
}

TEST_CASE("skirt_goes_around_holes_and_close_islands") {
  const Region holed{{rectangle(0, 0, 30, 30), reversed(rectangle(5, 5, 25, 25))}};
  const auto around = skirt(holed, w, 1, 3);
  REQUIRE(around.size() == 1);
  CHECK(signed_area(loop_of(around[0])) > 900);
  // Two islands 4 mm apart, skirt 3 mm out: one loop round both; 40 mm apart: one each.
  const Region near{{rectangle(0, 0, 10, 10), rectangle(14, 0, 24, 10)}};
  CHECK(skirt(near, w, 1, 3).size() == 1);
  const Region far{{rectangle(0, 0, 10, 10), rectangle(50, 0, 60, 10)}};
  CHECK(skirt(far, w, 1, 3).size() == 2);
}

TEST_CASE("no_part_or_no_loops_gives_no_skirt") {
  CHECK(skirt(Region{}, w, 2, 3).empty());
  CHECK(skirt(Region{{rectangle(0, 0, 1, 1)}}, w, 0, 3).empty());
  CHECK(skirt(Region{{rectangle(0, 0, 1, 1)}}, 0, 1, 3).empty());
}

}  // namespace skirt_test
