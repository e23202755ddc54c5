// Steps 3-5 of the medial-axis contour: labels, the exit edge of Observation 3.3.1, and the
// faired loop of a ring, which runs where the two loops are equally far.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/contour/ma/axis.h"

namespace axis_test {

using geometry::Loop;
using geometry::Vec2;
using geometry::ma::SampleTriangulation;

namespace {

double distance_to_loop(Vec2 p, const Loop& loop) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < loop.size(); ++i) {
    best = std::min(best, geometry::distance_to_segment(p, loop[i], loop[(i + 1) % loop.size()]));
  }
  return best;
}

}  // namespace

TEST_CASE("exit_edge_keeps_the_solid_on_the_left") {
  SampleTriangulation::Face face;
  face.vertex = {0, 1, 2};
  // Corner 0 the odd one out: solid, the contour leaves by edge 1 (from v2 to v0); empty, by
  // edge 2 (from v0 to v1). Equal labels: not crossed.
  CHECK(geometry::ma::exit_edge(face, {1, 0, 0}) == 1);
  CHECK(geometry::ma::exit_edge(face, {0, 1, 1}) == 2);
  CHECK(geometry::ma::exit_edge(face, {0, 1, 0}) == 2);  // corner 1 solid: edge 2
  CHECK(geometry::ma::exit_edge(face, {1, 1, 1}) == -1);
  CHECK(geometry::ma::is_mixed(face, {1, 0, 0}));
  CHECK_FALSE(geometry::ma::is_mixed(face, {0, 0, 0}));
}

TEST_CASE("axis_of_a_ring_is_one_loop_equidistant_from_both_loops") {
  const Loop outer{{-5, -5}, {5, -5}, {5, 5}, {-5, 5}}, hole{{-2, -2}, {-2, 2}, {2, 2}, {2, -2}};
  const std::vector<const Loop*> loops{&outer, &hole};
  geometry::MaOptions options;
  const auto samples = geometry::ma::sample_boundary_pair(loops, options);
  const SampleTriangulation t = geometry::ma::triangulate_samples(samples);
  for (const std::vector<char>& solid : {std::vector<char>{0, 1}, std::vector<char>{1, 0}}) {
    CAPTURE(int(solid[0]));
    const std::vector<char> labels = geometry::ma::vertex_labels(t, samples, solid);
    const auto axis = geometry::ma::axis_loops(t, labels, samples, loops, true);
    REQUIRE(axis.size() == 1);
    // Solid on the left: round the hole counter-clockwise when the hole is the solid side.
    CHECK((geometry::signed_area(axis[0]) > 0) == (solid[1] == 1));
    for (Vec2 p : axis[0]) {
      CHECK(std::abs(distance_to_loop(p, outer) - distance_to_loop(p, hole)) <= 1e-4);
    }
    // Between the squares of half-size 3.5 (the sides' axis) and 5 - 3.243 from the corner
    // (the diagonal's: 5 - t = sqrt(2) (t - 2), t = 3.243).
    for (Vec2 p : axis[0]) {
      const double r = std::max(std::abs(p.x), std::abs(p.y));
      CHECK(r <= 3.5 + 1e-4);
      CHECK(r >= 3.2426 - 1e-4);
    }
  }
}

}  // namespace axis_test
