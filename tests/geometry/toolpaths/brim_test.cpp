// brim: loops out from the first layer's edge, innermost against it.
#include "geometry/toolpaths/brim.h"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/toolpaths/toolpath_shapes.h"

namespace brim_test {

using namespace geometry;
using namespace toolpath_shapes;

namespace {

constexpr double w = 0.5;

double distance_to_square(Vec2 p, double s) {
  const double dx = std::max({0.0, -p.x, p.x - s}), dy = std::max({0.0, -p.y, p.y - s});
  return std::hypot(dx, dy);
}

}  // namespace

TEST_CASE("brim_lays_whole_beads_from_the_edge_out_to_its_width") {
  const Region square{{rectangle(0, 0, 10, 10)}};
  const auto loops = brim(square, w, 2.0);
  REQUIRE(loops.size() == 4);  // 2 mm of 0.5 mm beads
  CHECK(brim_extent(w, 2.0) == doctest::Approx(2.0));
  CHECK(brim_extent(w, 1.8) == doctest::Approx(2.0));  // a part bead is a whole bead
  CHECK(brim_extent(w, 1.5 + 1e-12) == doctest::Approx(1.5));
  for (std::size_t k = 0; k < loops.size(); ++k) {
    CAPTURE(k);
    CHECK(loops[k].role == PathRole::brim);
    CHECK(is_closed(loops[k]));
    CHECK(signed_area(loop_of(loops[k])) > 0);
    // Outermost first: loop k lies (3 - k + 1/2) beads out.
    const double r = w / 2 + double(loops.size() - 1 - k) * w;
    for (Vec2 p : loops[k].points) CHECK(distance_to_square(p, 10) == doctest::Approx(r).epsilon(0.01));
  }
}

TEST_CASE("brim_goes_round_the_outside_never_into_a_hole") {
  const Region ring{{rectangle(0, 0, 20, 20), reversed(rectangle(5, 5, 15, 15))}};
  const auto loops = brim(ring, w, 1.0);
  REQUIRE(loops.size() == 2);
  for (const auto& loop : loops) CHECK(signed_area(loop_of(loop)) > 400);
}

TEST_CASE("no_width_or_nothing_to_hold_gives_no_brim") {
  const Region square{{rectangle(0, 0, 10, 10)}};
  CHECK(brim(square, w, 0).empty());
  CHECK(brim(Region{}, w, 3).empty());
  CHECK(brim(square, 0, 3).empty());
  CHECK(brim_extent(w, 0) == 0);
}

}  // namespace brim_test
