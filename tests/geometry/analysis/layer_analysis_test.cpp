// Comparing strategies over a part: the summary's means, maxima, limit share and defect
// counts on numbers chosen by hand, and analyze_layers against layer-by-layer calls.
#include <doctest/doctest.h>

#include <cmath>
#include <string_view>
#include <vector>

#include "geometry/analysis/layer_analysis.h"
#include "geometry/metrics/layer_metrics.h"
#include "support/solids.h"

namespace layer_analysis_test {

using geometry::LayerAnalysis;
using geometry::StrategyLayer;

namespace {

const geometry::ContourStrategy* strategy(std::string_view name) {
  return &geometry::contour_strategy(name);
}

StrategyLayer result(const geometry::ContourStrategy* kind, double distance, double deviation, double limit,
                     std::size_t missed = 0) {
  StrategyLayer s;
  s.strategy = kind;
  s.metrics.distance = distance;
  s.metrics.hausdorff = distance + 0.1;
  s.metrics.volume_deviation = deviation;
  s.metrics.volume_limit = limit;
  s.metrics.missed_features = missed;
  return s;
}

}  // namespace

TEST_CASE("summary_counts_defect_cases_against_lower_and_mid") {
  std::vector<LayerAnalysis> layers(3);
  // layer 0: ma beats both; layer 1: ma worse than mid only; layer 2: worse than both, but by
  // less than the tolerance against lower.
  layers[0].strategies = {result(strategy("lower"), 0.4, 2.0, 1.0),
                          result(strategy("mid"), 0.3, 1.2, 1.0),
                          result(strategy("ma"), 0.2, 1.1, 1.0)};
  layers[1].strategies = {result(strategy("lower"), 0.4, 2.0, 1.0),
                          result(strategy("mid"), 0.1, 1.0, 1.0),
                          result(strategy("ma"), 0.2, 1.5, 1.0, 1)};
  layers[2].strategies = {result(strategy("lower"), 0.3, 3.0, 2.0),
                          result(strategy("mid"), 0.2, 2.0, 2.0),
                          result(strategy("ma"), 0.3005, 2.5, 2.0)};
  const auto summary = geometry::summarize(layers, 0.001);
  REQUIRE(summary.size() == 3);
  const geometry::StrategySummary& ma = summary[2];
  CHECK(ma.strategy == strategy("ma"));
  CHECK(ma.layers == 3);
  CHECK(ma.mean_distance == doctest::Approx((0.2 + 0.2 + 0.3005) / 3));
  CHECK(ma.max_distance == doctest::Approx(0.3005));
  CHECK(ma.max_hausdorff == doctest::Approx(0.4005));
  CHECK(ma.total_deviation == doctest::Approx(5.1));
  CHECK(ma.mean_deviation == doctest::Approx(1.7));
  CHECK(ma.total_limit == doctest::Approx(4.0));
  CHECK(ma.above_limit_percent == doctest::Approx(27.5));
  CHECK(ma.missed_features == 1);
  CHECK(ma.worse_than_lower == 0);  // 0.3005 vs 0.3 is within the 1 um tolerance
  CHECK(ma.worse_than_mid == 2);
  CHECK(summary[0].worse_than_lower == 0);
  CHECK(summary[1].worse_than_mid == 0);
  CHECK(summary[0].above_limit_percent == doctest::Approx(75));
  CHECK(geometry::summarize({}).empty());
}

TEST_CASE("analyze_layers_matches_layer_by_layer_metrics") {
  const solids::Solid sphere = solids::sphere(4, 32, 16, {0, 0, 4});
  const geometry::LayerStack stack(sphere.mesh, geometry::uniform_layers(8, 0.5));
  const std::vector<const geometry::ContourStrategy*> kinds{strategy("lower"), strategy("ma")};
  const auto layers = geometry::analyze_layers(stack, kinds);
  REQUIRE(layers.size() == stack.size());
  for (std::size_t i = 0; i < stack.size(); ++i) {
    CAPTURE(i);
    REQUIRE(layers[i].strategies.size() == 2);
    CHECK(layers[i].layer.z_lo == stack.layers()[i].z_lo);
    const geometry::LayerMetrics lower =
        geometry::layer_metrics(stack, i, stack.lower(i));
    CHECK(layers[i].strategies[0].metrics.volume_deviation == doctest::Approx(lower.volume_deviation));
    CHECK(layers[i].strategies[0].metrics.distance == doctest::Approx(lower.distance));
    CHECK(layers[i].strategies[1].strategy == strategy("ma"));
    CHECK(layers[i].strategies[1].height == stack.layers()[i].z_mid());
    CHECK(!layers[i].strategies[1].region.loops.empty());
  }
}

TEST_CASE("weighted_percentile_is_the_least_value_reaching_the_share") {
  const std::vector<double> d{0.3, 0.1, 0.2, 0.5};
  const std::vector<double> w{2, 1, 1, 0.25};  // total 4.25
  // Sorted: 0.1 (1), 0.2 (2), 0.3 (4), 0.5 (4.25).
  CHECK(geometry::weighted_percentile(d, w, 20) == 0.1);        // 0.85 of weight
  CHECK(geometry::weighted_percentile(d, w, 2.0 / 4.25 * 100) == 0.2);  // exactly 2
  CHECK(geometry::weighted_percentile(d, w, 90) == 0.3);        // 3.825 <= 4
  CHECK(geometry::weighted_percentile(d, w, 95) == 0.5);        // 4.0375 > 4
  CHECK(geometry::weighted_percentile(d, w, 100) == 0.5);
  CHECK(geometry::weighted_percentile(d, w, 0) == 0.1);
  // Weightless items count for nothing; nothing at all is NaN.
  const std::vector<double> none{0, -1, 0, 0};
  CHECK(std::isnan(geometry::weighted_percentile(d, none, 50)));
  const std::vector<double> heavy_last{0, 0, 0, 1};
  CHECK(geometry::weighted_percentile(d, heavy_last, 1) == 0.5);
}

TEST_CASE("percentile_by_height_weighs_layers_by_thickness_outside_the_excluded_range") {
  // Ten thin layers of D 1 (0.1 mm each, 1 mm) under one thick layer of D 2 (3 mm): by count
  // 91% of layers have D 1, by height only 25% of the part does.
  std::vector<geometry::LayerAnalysis> layers;
  const auto add = [&](double z_lo, double z_hi, double d) {
    geometry::LayerAnalysis a;
    a.layer = {z_lo, z_hi};
    geometry::StrategyLayer s;
    s.strategy = &geometry::contour_strategy("mid");
    s.metrics.distance = d;
    a.strategies.push_back(s);
    layers.push_back(a);
  };
  for (int i = 0; i < 10; ++i) add(0.1 * i, 0.1 * (i + 1), 1.0);
  add(1.0, 4.0, 2.0);
  CHECK(geometry::distance_percentile_by_height(layers, 0, 95) == 2.0);
  CHECK(geometry::distance_percentile_by_height(layers, 0, 25) == 1.0);
  CHECK(geometry::distance_percentile_by_height(layers, 0, 26) == 2.0);
  // Leaving out z < 0.55: the thin layers weigh 0.45 mm of 3.45 (13%); the one straddling
  // 0.55 counts by its part above it.
  const geometry::ZRange base{0, 0.55};
  CHECK(geometry::distance_percentile_by_height(layers, 0, 13, base) == 1.0);
  CHECK(geometry::distance_percentile_by_height(layers, 0, 13.1, base) == 2.0);
  // Everything left out: nothing to judge.
  CHECK(std::isnan(geometry::distance_percentile_by_height(layers, 0, 95, {0, 10})));
  // The summary carries it.
  CHECK(geometry::summarize(layers)[0].p95_distance_by_height == 2.0);
}

}  // namespace layer_analysis_test
