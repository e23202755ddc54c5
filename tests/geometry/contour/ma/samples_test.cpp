// Step 1 of the medial-axis contour: the samples of a boundary pair, counted and placed by
// hand.
#include <doctest/doctest.h>

#include <cmath>

#include "geometry/contour/ma/samples.h"

namespace samples_test {

using geometry::Loop;
using geometry::Vec2;
using geometry::ma::Sample;

namespace {

Loop square(double half) {
  return {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
}

}  // namespace

TEST_CASE("samples_split_each_edge_at_the_spacing_and_keep_every_vertex") {
  const Loop outer = square(0.5);  // edges 1 mm long
  geometry::MaOptions options;
  options.spacing = 0.25;
  const std::vector<Sample> samples = geometry::ma::sample_boundary_pair({&outer}, options);
  REQUIRE(samples.size() == 16);  // per edge: its first vertex and 3 points between
  for (std::size_t i = 0; i < samples.size(); ++i) {
    CAPTURE(i);
    const std::size_t edge = i / 4, k = i % 4;
    const Vec2 a = outer[edge], b = outer[(edge + 1) % 4];
    CHECK(samples[i].loop == 0);
    CHECK(samples[i].segment == edge);
    CHECK(samples[i].at.x == doctest::Approx(a.x + 0.25 * k * (b.x - a.x)));
    CHECK(samples[i].at.y == doctest::Approx(a.y + 0.25 * k * (b.y - a.y)));
  }
}

TEST_CASE("samples_over_the_cap_widen_the_spacing_then_thin_the_vertices") {
  const Loop outer = square(5), hole{{-1, -1}, {-1, 1}, {1, 1}, {1, -1}};
  geometry::MaOptions options;
  options.spacing = 0.25;
  options.max_points = 40;
  // 8 vertices and 48 mm of loops: 8 + 192 points at 0.25 mm, over the cap; the spacing
  // becomes 48 / 33 mm, so a 10 mm edge takes ceil(6.875) = 7 pieces, a 2 mm edge 2.
  const std::vector<Sample> samples = geometry::ma::sample_boundary_pair({&outer, &hole}, options);
  CHECK(samples.size() == 4 * 7 + 4 * 2);
  CHECK(samples.size() <= options.max_points);
  CHECK(samples.back().loop == 1);
  // Vertices alone over the cap: every third of a 100-gon's vertices, no edge split.
  Loop round;
  for (int i = 0; i < 100; ++i) round.push_back({std::cos(0.0628 * i), std::sin(0.0628 * i)});
  options.max_points = 34;
  const std::vector<Sample> thinned = geometry::ma::sample_boundary_pair({&round}, options);
  REQUIRE(thinned.size() == 34);  // vertices 0, 3, ..., 99
  for (std::size_t i = 0; i < thinned.size(); ++i) CHECK(thinned[i].segment == 3 * i);
}

}  // namespace samples_test
