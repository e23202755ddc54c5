// bridge_direction: lines across an unsupported area, held at both ends, against closed forms.
#include "geometry/support/bridge_detector.h"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

namespace bridge_detector_test {

using namespace geometry;

namespace {

Loop rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

Loop turned(Loop loop, double degrees) {
  const double a = degrees * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
  for (Vec2& p : loop) p = {c * p.x - s * p.y, s * p.x + c * p.y};
  return loop;
}

Loop circle(double r, int n, bool clockwise = false) {
  Loop loop;
  for (int i = 0; i < n; ++i) {
    const double a = (clockwise ? -1 : 1) * 2 * std::numbers::pi * i / n;
    loop.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return loop;
}

// The direction's distance from `expected` degrees, lines having no sense (mod 180).
double off_by(double angle, double expected) {
  const double d = std::fmod(std::abs(angle - expected), 180.0);
  return std::min(d, 180 - d);
}

}  // namespace

TEST_CASE("a_gap_between_two_blocks_is_bridged_across_it") {
  // 8 mm between the blocks, 20 mm along them: lines across (at 0 degrees) span 8 mm.
  const Region gap{{rectangle(0, 0, 8, 20)}};
  const Region blocks{{rectangle(-5, 0, 0, 20), rectangle(8, 0, 13, 20)}};
  const BridgeDirection d = bridge_direction(gap, blocks, 0.45);
  CHECK(d.anchored);
  CHECK(off_by(d.angle, 0) < 1e-6);
  CHECK(d.span == doctest::Approx(8).epsilon(0.01));
  CHECK(d.anchored_share == doctest::Approx(1));
}

TEST_CASE("a_turned_gap_is_bridged_across_it_at_its_angle") {
  const Region gap{{turned(rectangle(0, 0, 8, 20), 30)}};
  const Region blocks{{turned(rectangle(-5, 0, 0, 20), 30), turned(rectangle(8, 0, 13, 20), 30)}};
  const BridgeDirection d = bridge_direction(gap, blocks, 0.45);
  CHECK(d.anchored);
  CHECK(off_by(d.angle, 30) < 1e-6);
  CHECK(d.span == doctest::Approx(8).epsilon(0.01));
}

TEST_CASE("a_ledge_held_on_one_side_is_no_bridge") {
  const Region ledge{{rectangle(0, 0, 8, 20)}};
  const Region wall{{rectangle(-5, 0, 0, 20)}};
  const BridgeDirection d = bridge_direction(ledge, wall, 0.45);
  CHECK_FALSE(d.anchored);
  CHECK(d.anchored_share < 0.5);
}

TEST_CASE("a_hole_covered_over_is_held_all_round") {
  // A 6 mm hole in a 20 mm plate: every line across rests on the plate, none longer than 6.
  const Region hole{{circle(3, 64)}};
  const Region plate{{rectangle(-10, -10, 10, 10), circle(3, 64, true)}};
  const BridgeDirection d = bridge_direction(hole, plate, 0.45);
  CHECK(d.anchored);
  CHECK(d.span <= 6.05);
  CHECK(d.span >= 5.9);
}

TEST_CASE("nothing_to_bridge_or_nothing_to_hold_it_is_no_bridge") {
  const Region gap{{rectangle(0, 0, 8, 20)}};
  CHECK_FALSE(bridge_direction(Region{}, gap, 0.45).anchored);
  CHECK_FALSE(bridge_direction(gap, Region{}, 0.45).anchored);
  CHECK_FALSE(bridge_direction(gap, gap, 0).anchored);
}

}  // namespace bridge_detector_test
