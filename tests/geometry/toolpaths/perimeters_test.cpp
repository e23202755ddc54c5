// perimeters: wall loops at w/2 + k w from the edge, thin walls where no loop fits.
#include "geometry/toolpaths/perimeters.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "geometry/toolpaths/bead_coverage.h"
#include "geometry/toolpaths/toolpath_shapes.h"

namespace perimeters_test {

using namespace geometry;
using namespace toolpath_shapes;

namespace {
constexpr double w = 0.45;
}

TEST_CASE("square_walls_are_nested_squares_one_width_apart") {
  const Region square{{rectangle(0, 0, 20, 20)}};
  const Perimeters p = perimeters(square, w, 3);
  REQUIRE(p.walls.size() == 3);
  for (int k = 0; k < 3; ++k) {
    CAPTURE(k);
    REQUIRE(p.walls[k].size() == 1);
    const ExtrusionPath& loop = p.walls[k][0];
    CHECK(loop.role == (k == 0 ? PathRole::outer_wall : PathRole::inner_wall));
    CHECK(loop.width == w);
    CHECK(is_closed(loop));
    const double inset = w / 2 + k * w, side = 20 - 2 * inset;
    CHECK(signed_area(loop_of(loop)) == doctest::Approx(side * side).epsilon(1e-9));
    CHECK(perimeter(loop_of(loop)) == doctest::Approx(4 * side).epsilon(1e-9));
    for (Vec2 v : loop.points) {
      CHECK(std::min({v.x, v.y, 20 - v.x, 20 - v.y}) == doctest::Approx(inset).epsilon(1e-6));
    }
  }
  CHECK(p.thin_walls.empty());
  const double inner = 20 - 6 * w;
  CHECK(area(p.infill_area) == doctest::Approx(inner * inner).epsilon(1e-9));
}

TEST_CASE("walls_and_infill_area_partition_the_square") {
  // Beads of width w centred on squares of side s_k cover 4 s_k w each; with the infill area
  // they tile the square exactly: no gap and no double coverage between walls and infill.
  const Region square{{rectangle(0, 0, 20, 20)}};
  for (int count : {1, 2, 4}) {
    CAPTURE(count);
    const Perimeters p = perimeters(square, w, count);
    double beads = 0;
    for (const auto& level : p.walls)
      for (const auto& loop : level) beads += perimeter(loop_of(loop)) * w;
    CHECK(beads + area(p.infill_area) == doctest::Approx(400).epsilon(1e-9));
  }
}

TEST_CASE("hole_walls_run_clockwise_outer_walls_counter_clockwise") {
  const Region holed{{rectangle(0, 0, 20, 20), reversed(rectangle(8, 8, 12, 12))}};
  const Perimeters p = perimeters(holed, w, 2);
  REQUIRE(p.walls.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    REQUIRE(p.walls[k].size() == 2);
    const double inset = w / 2 + k * w;
    int ccw = 0, cw = 0;
    for (const auto& loop : p.walls[k]) {
      const double a = signed_area(loop_of(loop));
      if (a > 0) {
        ++ccw;
        CHECK(a == doctest::Approx(std::pow(20 - 2 * inset, 2)).epsilon(1e-9));
      } else {
        ++cw;
        CHECK(-a == doctest::Approx(std::pow(4 + 2 * inset, 2)).epsilon(1e-9));
      }
    }
    CHECK(ccw == 1);
    CHECK(cw == 1);
  }
  CHECK(area(p.infill_area) == doctest::Approx(std::pow(20 - 4 * w, 2) - std::pow(4 + 4 * w, 2))
                                   .epsilon(1e-9));
}

TEST_CASE("disc_walls_are_regular_polygons_inset_by_their_apothem") {
  // Insetting a regular n-gon by d keeps it regular: apothem a - d, circumradius
  // (a - d) / cos(pi / n), with a = R cos(pi / n).
  const int n = 360;
  const double radius = 10, apothem = radius * std::cos(std::numbers::pi / n);
  const Region disc{{circle({3, -2}, radius, n)}};
  const Perimeters p = perimeters(disc, w, 2);
  REQUIRE(p.walls.size() == 2);
  for (std::size_t k = 0; k < 2; ++k) {
    REQUIRE(p.walls[k].size() == 1);
    const double expected = (apothem - w / 2 - k * w) / std::cos(std::numbers::pi / n);
    for (Vec2 v : p.walls[k][0].points) {
      CHECK(std::hypot(v.x - 3, v.y + 2) == doctest::Approx(expected).epsilon(1e-6));
    }
  }
}

TEST_CASE("strip_too_narrow_for_second_loop_gets_centre_line_between_walls") {
  // 1.2 mm strip: loop 0 fits (inset 0.225); the space left inside its bead is
  // 1.2 - 2 w = 0.3 wide, too narrow for loop 1: a 0.3 mm centre line at y = 0.6.
  const Region strip{{rectangle(0, 0, 15, 1.2)}};
  const Perimeters p = perimeters(strip, w, 2);
  REQUIRE(p.walls.size() == 1);
  REQUIRE(p.thin_walls.size() == 1);
  const ExtrusionPath& line = p.thin_walls[0];
  CHECK(line.role == PathRole::thin_wall);
  CHECK(line.width == doctest::Approx(0.3).epsilon(1e-6));
  for (Vec2 v : line.points) CHECK(v.y == doctest::Approx(0.6).epsilon(1e-6));
  // The centre line ends where its round ends would reach the inside of the outer wall's
  // bead (x = w and 15 - w), then runs on by half its width: laid against a wall, not the
  // air, the bead is full to the end of the strip.
  CHECK(length(line.points) == doctest::Approx(15 - 2 * w).epsilon(1e-6));
  CHECK(area(p.infill_area) == doctest::Approx(0));
}

TEST_CASE("region_thinner_than_width_gets_single_centre_line") {
  const Region strip{{rectangle(0, 0, 10, 0.3)}};
  const Perimeters p = perimeters(strip, w, 2);
  CHECK(p.walls.empty());
  REQUIRE(p.thin_walls.size() == 1);
  CHECK(p.thin_walls[0].width == doctest::Approx(0.3).epsilon(1e-6));
  CHECK(length(p.thin_walls[0].points) == doctest::Approx(10 - 0.3).epsilon(1e-6));
}

TEST_CASE("strip_under_one_and_a_half_widths_gets_one_line_not_a_collapsed_loop") {
  // A loop in a 0.6 mm strip would lay its two 0.45 mm sides 0.15 mm apart, one on the other.
  const Region strip{{rectangle(0, 0, 10, 0.6)}};
  const Perimeters p = perimeters(strip, w, 2);
  CHECK(p.walls.empty());
  REQUIRE(p.thin_walls.size() == 1);
  CHECK(p.thin_walls[0].width == doctest::Approx(0.6).epsilon(1e-6));
}

TEST_CASE("strip_between_one_and_a_half_and_two_widths_gets_two_beads_not_an_overlapping_loop") {
  // A loop in a 0.8 mm strip would lay its 0.45 mm sides 0.35 mm apart, 0.1 mm on top of
  // each other (12% of the strip laid twice). Instead: two beads side by side, each 0.4 mm
  // (and a dab in each of the strip's square corners).
  const Region strip{{rectangle(0, 0, 10, 0.8)}};
  const Perimeters p = perimeters(strip, w, 2);
  CHECK(p.walls.empty());
  REQUIRE(!p.thin_walls.empty());
  CHECK(is_closed(p.thin_walls[0]));
  CHECK(p.thin_walls[0].width == doctest::Approx(0.4).epsilon(1e-6));
  for (std::size_t i = 1; i < p.thin_walls.size(); ++i) CHECK(length(p.thin_walls[i].points) < 0.15);
  const auto c = bead_coverage::coverage(strip, p.thin_walls);
  INFO("inside " << c.inside << " outside " << c.outside << " double " << c.double_coverage);
  CHECK(c.inside >= 0.99);
  CHECK(c.outside <= 0.005);
  CHECK(c.double_coverage <= 0.005);
}

TEST_CASE("a_sharp_corner_the_bead_cannot_follow_gets_a_gap_fill") {
  // A 20 mm triangle with a 20 degree tip: the outer wall's bead rounds it off 1.3 mm short
  // of the tip (w/2 / sin 10 degrees, less w/2); the gap fill runs a tapering line into it.
  const double tip = 20 * std::numbers::pi / 180;
  const Region wedge{{Loop{{0, 0}, {20, 20 * std::tan(tip / 2)}, {0, 2 * 20 * std::tan(tip / 2)}}}};
  const Perimeters p = perimeters(wedge, w, 1);
  REQUIRE(p.walls.size() == 1);
  double reach = 0;
  for (const auto& line : p.thin_walls)
    for (Vec2 v : line.points) reach = std::max(reach, v.x);
  double wall_reach = 0;
  for (Vec2 v : p.walls[0][0].points) wall_reach = std::max(wall_reach, v.x);
  CHECK(reach > wall_reach + 0.5);
}

TEST_CASE("no_loops_gives_whole_island_as_infill_area") {
  const Region square{{rectangle(0, 0, 5, 5)}};
  const Perimeters p = perimeters(square, w, 0);
  CHECK(p.walls.empty());
  CHECK(area(p.infill_area) == doctest::Approx(25));
}

TEST_CASE("empty_island_gives_nothing") {
  const Perimeters p = perimeters(Region{}, w, 3);
  CHECK(p.walls.empty());
  CHECK(p.thin_walls.empty());
  CHECK(p.infill_area.loops.empty());
  CHECK(perimeters(Region{{rectangle(0, 0, 5, 5)}}, 0, 3).walls.empty());
}

}  // namespace perimeters_test
