// The layer plan's cheap estimate of a slab's D (slab_bound.h's SlabSpreadEstimate) against
// the closed form of a frustum, whose sides lean phi from vertical: every side facet spans
// the whole height and moves tan(phi) per mm, so a slab [a, b] inside the part is estimated
// (b - a) tan(phi) / 2, and a slab reaching past the part's top or bottom by its overlap.
// The form taking a node's candidates at once gives each single one's figure exactly.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/plan/slab_bound.h"
#include "support/solids.h"

namespace slab_spread_test {

TEST_CASE("slab_spread_estimate_of_a_frustum_is_half_its_sides_move_across_the_slab") {
  constexpr int kSides = 64;
  for (const double degrees : {10.0, 35.0, 60.0}) {
    const double lean = std::tan(degrees * std::numbers::pi / 180);
    const double growth = lean / std::cos(std::numbers::pi / kSides);  // circumradius per mm
    const solids::Solid frustum = solids::frustum(5, 5 + 10 * growth, 10, kSides);
    const geometry::SlabSpreadEstimate estimate(frustum.mesh);
    CAPTURE(degrees);
    for (const double a : {-0.1, 0.0, 2.0, 7.35, 9.8}) {
      std::vector<double> tops;
      for (double t = 0.15; t < 0.4 + 1e-9; t += 0.05) tops.push_back(a + t);
      std::vector<double> together(tops.size(), -1);
      estimate(a, tops, together);
      for (std::size_t j = 0; j < tops.size(); ++j) {
        const double overlap = std::min(tops[j], 10.0) - std::max(a, 0.0);
        CAPTURE(a);
        CAPTURE(tops[j]);
        CHECK(together[j] == doctest::Approx(0.5 * overlap * lean).epsilon(1e-9));
        CHECK(together[j] == estimate(a, tops[j]));
      }
    }
    // Above the part: nothing to spread.
    std::vector<double> above(2, -1);
    const double tops[] = {10.3, 10.5};
    estimate(10.1, tops, above);
    CHECK(above[0] == 0);
    CHECK(above[1] == 0);
  }
}

TEST_CASE("slab_spread_estimate_of_a_node_s_candidates_at_once_is_each_one_s_on_a_sphere") {
  // A sphere's rows of facets start and end at every height: a candidate's facets are not its
  // thickest neighbour's.
  const solids::Solid sphere = solids::sphere(15, 64, 32, {0, 0, 15});
  const geometry::SlabSpreadEstimate estimate(sphere.mesh);
  int rising = 0;
  for (double a = 0; a < 30; a += 0.35) {
    std::vector<double> tops;
    for (double t = 0.15; t < 0.4 + 1e-9; t += 0.05) tops.push_back(a + t);
    std::vector<double> together(tops.size(), -1);
    estimate(a, tops, together);
    for (std::size_t j = 0; j < tops.size(); ++j) {
      CAPTURE(a);
      CHECK(together[j] == estimate(a, tops[j]));
      if (j > 0 && together[j] > together[j - 1]) ++rising;
    }
  }
  CHECK(rising > 100);  // thicker slabs spread more: the figures differ from one another
}

}  // namespace slab_spread_test
