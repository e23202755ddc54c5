// PointsInRegion against point_in_region, point by point: on a grid through the loops' vertices,
// edges (horizontal, vertical, slanted) and insides, so that every rule of
// ClipperLib::PointInPolygon is met (on a vertex, on an edge, a crossing on either side).
#include <cmath>
#include <numbers>

#include <doctest/doctest.h>

#include "geometry/core/point_in_region.h"

namespace point_in_region_test {

using geometry::clipper::IntPoint;
using geometry::clipper::Path;
using geometry::clipper::Paths;
using geometry::clipper::point_in_region;
using geometry::clipper::PointsInRegion;

namespace {

// Every point of the grid from (lo, lo) to (hi, hi), `step` apart, answered alike.
void check_alike(const Paths& region, long lo, long hi, long step) {
  const PointsInRegion inside(region);
  int agree = 0, in = 0, total = 0;
  for (long y = lo; y <= hi; y += step) {
    for (long x = lo; x <= hi; x += step) {
      const IntPoint p{x, y};
      const bool expected = point_in_region(region, p);
      agree += inside.contains(p) == expected;
      in += expected;
      ++total;
    }
  }
  CHECK(agree == total);
  CHECK(in > 0);
  CHECK(in < total);
}

}  // namespace

TEST_CASE("points_in_region_answer_as_point_in_region_does") {
  SUBCASE("a square with a square hole, and an island in the hole") {
    const Paths region{{{0, 0}, {100, 0}, {100, 100}, {0, 100}},
                       {{20, 20}, {20, 80}, {80, 80}, {80, 20}},
                       {{40, 40}, {60, 40}, {60, 60}, {40, 60}}};
    check_alike(region, -10, 110, 1);
  }
  SUBCASE("a star of slanted edges, and a loop crossing it (non-zero windings of 2)") {
    Path star, crossing;
    for (int k = 0; k < 14; ++k) {
      const double a = k * std::numbers::pi / 7, r = k % 2 ? 300 : 1000;
      star.push_back({std::lround(r * std::cos(a)), std::lround(r * std::sin(a))});
      crossing.push_back({std::lround(500 + 600 * std::cos(a)), std::lround(200 + 600 * std::sin(a))});
    }
    check_alike({star, crossing}, -1200, 1200, 7);
    check_alike({star, crossing}, -1200, 1200, 50);
  }
  SUBCASE("loops of fewer than three points are no region") {
    const Paths region{{{0, 0}, {100, 100}}, {{0, 0}, {100, 0}, {0, 100}}};
    check_alike(region, -5, 105, 1);
  }
}

TEST_CASE("an_empty_region_contains_no_point") {
  CHECK_FALSE(PointsInRegion(Paths{}).contains({0, 0}));
  CHECK_FALSE(PointsInRegion(Paths{{{0, 0}, {1, 1}}}).contains({0, 0}));
}

}  // namespace point_in_region_test
