// BoundaryGrid's distance queries (boundary_grid.h) against closed forms: a square's edges cut
// into many short segments (so that a query crosses cells) and a 360-gon.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "geometry/core/boundary_grid.h"
#include "geometry/core/polygon.h"

namespace boundary_grid_test {

using geometry::BoundaryGrid;
using geometry::Loop;
using geometry::Region;
using geometry::Vec2;

namespace {

// The square [0, 10]^2, each side cut into 40 segments.
Region square() {
  Loop loop;
  const Vec2 corners[] = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  for (int side = 0; side < 4; ++side) {
    const Vec2 a = corners[side], b = corners[(side + 1) % 4];
    for (int k = 0; k < 40; ++k) loop.push_back(a + (k / 40.0) * (b - a));
  }
  return Region{{loop}};
}

// Distance from p to the square's boundary, by hand.
double to_square(Vec2 p) {
  const double dx = std::max({0.0 - p.x, 0.0, p.x - 10}), dy = std::max({0.0 - p.y, 0.0, p.y - 10});
  if (dx > 0 || dy > 0) return std::hypot(dx, dy);
  return std::min({p.x, 10 - p.x, p.y, 10 - p.y});
}

}  // namespace

TEST_CASE("any_within_tells_a_square_s_edges_nearer_than_r_as_the_closed_form_does") {
  const BoundaryGrid grid(square());
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-30, 40), radius(0.01, 25);
  int near = 0, far = 0;
  for (int i = 0; i < 20000; ++i) {
    const Vec2 p{coordinate(random), coordinate(random)};
    const double r = radius(random);
    const double d = to_square(p);
    if (std::abs(d - r) < 1e-9) continue;  // the documented band either way
    CHECK(grid.any_within(p, r) == (d < r));
    CHECK(std::abs(grid.nearest_distance(p) - d) < 1e-9);
    (d < r ? near : far) += 1;
  }
  // Both answers were asked for, inside the square and far outside the grid's cells.
  CHECK(near > 1000);
  CHECK(far > 1000);
}

TEST_CASE("a_loop_s_edges_that_run_straight_on_are_one_segment") {
  // The square's 160 edges are its 4 sides; a point's distance and side are the same.
  const BoundaryGrid grid(square());
  CHECK(grid.segments().size() == 4);
  CHECK(grid.nearest_distance({5, 4}) == doctest::Approx(4));
  CHECK(grid.nearest({3.3, -2}).foot.x == doctest::Approx(3.3));
  CHECK(grid.winding_number({5, 5}) == 1);
  CHECK(grid.winding_number({5, 11}) == 0);
  // A spike (the loop running back on itself) and a bend of a thousandth of a degree are
  // corners.
  const BoundaryGrid spike(Region{{{{0, 0}, {4, 0}, {2, 0}, {2, 3}}}});
  CHECK(spike.segments().size() == 4);
  const double bend = 1e-3 * std::numbers::pi / 180;
  const Vec2 turned{5 + 5 * std::cos(bend), 5 * std::sin(bend)};
  const BoundaryGrid bent(Region{{{{0, 0}, {5, 0}, turned, {5, 5}}}});
  CHECK(bent.segments().size() == 4);
}

TEST_CASE("any_within_on_a_360_gon_and_at_its_edges") {
  Loop loop;
  for (int k = 0; k < 360; ++k) {
    const double a = k * std::numbers::pi / 180;
    loop.push_back({10 * std::cos(a), 10 * std::sin(a)});
  }
  const BoundaryGrid grid(Region{{loop}});
  // The chords sag 10 (1 - cos 0.5 deg) = 0.38 um inside the circle at most.
  const double sag = 10 * (1 - std::cos(std::numbers::pi / 360));
  for (double rho : {0.0, 3.0, 9.5, 9.99, 10.01, 10.5, 14.0, 60.0}) {
    for (double angle : {0.1, 1.3, 2.9, 4.4, 6.0}) {
      const Vec2 p{rho * std::cos(angle), rho * std::sin(angle)};
      const double d = std::abs(rho - 10);
      CHECK(grid.any_within(p, d + sag + 1e-3));
      CHECK_FALSE(grid.any_within(p, d - sag - 1e-3));
    }
  }
  // A vertex is at distance 0: nothing is nearer than 0, and everything nearer than a micron.
  CHECK_FALSE(grid.any_within(loop[17], 0));
  CHECK(grid.any_within(loop[17], 1e-6));
  CHECK_FALSE(BoundaryGrid().any_within({0, 0}, 1e9));
}

TEST_CASE("winding_number_of_many_points_is_one_between_a_ring_s_circles_and_zero_elsewhere") {
  // A disc of radius 10 with a hole of radius 4, as 360-gons: the grid's cells off the
  // circles list no segment, and past its first queries the grid answers from them.
  Loop outer, hole;
  for (int k = 0; k < 360; ++k) {
    const double a = k * std::numbers::pi / 180;
    outer.push_back({10 * std::cos(a), 10 * std::sin(a)});
    hole.push_back({4 * std::cos(-a), 4 * std::sin(-a)});
  }
  const BoundaryGrid grid(Region{{outer, hole}});
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-15, 15);
  int inside = 0, outside = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec2 p{coordinate(random), coordinate(random)};
    const double rho = std::hypot(p.x, p.y);
    // Off the circles by more than the chords' sag (0.38 um on the outer one).
    if (std::abs(rho - 10) < 1e-3 || std::abs(rho - 4) < 1e-3) continue;
    double clearance = -1;
    const int winding = grid.winding_number(p, &clearance);
    const bool between = rho > 4 && rho < 10;
    CHECK(winding == (between ? 1 : 0));
    // A lower bound on the distance to the walls, and more than nothing off them.
    CHECK(clearance <= std::min(std::abs(rho - 10), std::abs(rho - 4)) + 1e-3);
    CHECK(clearance > 0);
    (between ? inside : outside) += 1;
  }
  CHECK(inside > 1000);
  CHECK(outside > 1000);
}

}  // namespace boundary_grid_test
