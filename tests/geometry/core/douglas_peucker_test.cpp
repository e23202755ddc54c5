// Douglas-Peucker on a closed loop (douglas_peucker.h), worked by hand.
#include <doctest/doctest.h>

#include <algorithm>
#include <vector>

#include "geometry/core/douglas_peucker.h"
#include "geometry/core/polygon.h"

namespace douglas_peucker_test {

using geometry::Vec2;

namespace {

double squared_distance(Vec2 p, Vec2 a, Vec2 b) {
  const double abx = b.x - a.x, aby = b.y - a.y, length2 = abx * abx + aby * aby;
  const double t = length2 > 0 ? std::clamp(((p.x - a.x) * abx + (p.y - a.y) * aby) / length2, 0.0, 1.0) : 0.0;
  const double dx = p.x - a.x - t * abx, dy = p.y - a.y - t * aby;
  return dx * dx + dy * dy;
}

std::vector<char> keep(const std::vector<Vec2>& loop, double tolerance) {
  return geometry::douglas_peucker_keep(loop.size(), tolerance * tolerance,
                                        [&](std::size_t i, std::size_t a, std::size_t b) {
                                          return squared_distance(loop[i], loop[a], loop[b]);
                                        });
}

}  // namespace

// A 10 mm square with a vertex in the middle of each side, the top one raised 0.1 mm: the
// side midpoints go, the raised one stays while the tolerance is under 0.1 mm.
TEST_CASE("douglas_peucker_drops_what_lies_within_the_tolerance_and_keeps_the_rest") {
  const std::vector<Vec2> loop{{0, 0}, {5, 0}, {10, 0}, {10, 5}, {10, 10},
                               {5, 10.1}, {0, 10}, {0, 5}};
  CHECK(keep(loop, 0.05) == std::vector<char>{1, 0, 1, 0, 1, 1, 1, 0});
  CHECK(keep(loop, 0.2) == std::vector<char>{1, 0, 1, 0, 1, 0, 1, 0});
  // Vertex 0 and the farthest from it (10, 10) are always kept.
  CHECK(keep(loop, 100) == std::vector<char>{1, 0, 0, 0, 1, 0, 0, 0});
}

TEST_CASE("douglas_peucker_is_total") {
  CHECK(keep({}, 1).empty());
  CHECK(keep({{1, 2}}, 1) == std::vector<char>{1});
}

}  // namespace douglas_peucker_test
