// The best contour: per layer never above mid's or ma's distance error, on closed-form solids
// whose layers favour different candidates, and the same D analyze measures for it.
#include <doctest/doctest.h>

#include <algorithm>

#include "geometry/analysis/layer_analysis.h"
#include "geometry/contour/best_contour.h"
#include "geometry/contour/contour_strategy.h"
#include "support/solids.h"

using geometry::ContourStrategy;

namespace {

const ContourStrategy* strategy(std::string_view name) { return &geometry::contour_strategy(name); }

// analyze's D of mid, ma and best on every layer of a stack.
void check_never_worse(const geometry::Mesh& mesh, double thickness) {
  const double top = geometry::bounding_box(mesh).max.z;
  const geometry::LayerStack stack(mesh, geometry::uniform_layers(top, thickness));
  const ContourStrategy* strategies[] = {strategy("mid"), strategy("ma"), strategy("best")};
  const auto layers = geometry::analyze_layers(stack, strategies);
  REQUIRE(!layers.empty());
  for (const auto& layer : layers) {
    CAPTURE(layer.layer.z_lo);
    const double mid = layer.strategies[0].metrics.distance;
    const double ma = layer.strategies[1].metrics.distance;
    const double best = layer.strategies[2].metrics.distance;
    CHECK(best <= std::min(mid, ma) + geometry::kDistanceTie);
    CHECK(layer.strategies[2].metrics.missed_features <=
          std::min(layer.strategies[0].metrics.missed_features,
                   layer.strategies[1].metrics.missed_features));
  }
}

}  // namespace

TEST_CASE("best_is_never_worse_than_mid_or_ma_on_a_sphere") {
  check_never_worse(solids::sphere(10, 48, 24, {0, 0, 10}).mesh, 0.4);
}

TEST_CASE("best_is_never_worse_than_mid_or_ma_on_a_torus_and_a_bipyramid") {
  check_never_worse(solids::torus(12, 5, 48, 24, {0, 0, 5}).mesh, 0.35);
  check_never_worse(solids::bipyramid(10, 6, 0, 3.3, 10).mesh, 0.3);
}

TEST_CASE("best_choice_takes_the_candidate_of_least_distance") {
  // A cone: mid's walls stand at the slab's middle, t/2 from both ends in the radial
  // direction (scaled by the slope); every candidate is within a hair of that, so best's D
  // is the least of the three and equal to the formula within the metric's tolerance.
  const solids::Solid cone = solids::cone(10, 20, 64);
  const geometry::LayerStack stack(cone.mesh, geometry::uniform_layers(20, 0.4));
  const geometry::ContourOptions options;
  for (std::size_t i = 0; i + 2 < stack.size(); i += 7) {
    const geometry::BestChoice choice = geometry::best_choice({stack, i, options});
    const double least = *std::min_element(std::begin(choice.candidate_distance),
                                           std::end(choice.candidate_distance));
    CHECK(choice.distance <= least + geometry::kDistanceTie);
    CHECK(choice.distance == doctest::Approx(0.4 / 2 * 10 / 20).epsilon(0.05));
    CHECK((choice.chosen == "mid" || choice.chosen == "ma" || choice.chosen == "optimal-height"));
  }
}
