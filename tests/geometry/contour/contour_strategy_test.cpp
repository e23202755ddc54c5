// The strategy dispatcher and the strategies against closed forms: on a cone the
// medial-axis contour is the mid-plane section, on a cylinder every strategy is the section
// and every error is zero, and no strategy beats the volume limit.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string_view>

#include "geometry/core/boundary_grid.h"
#include "geometry/contour/contour_strategy.h"
#include "geometry/metrics/layer_metrics.h"
#include "geometry/slicing/layer_stack.h"
#include "support/solids.h"

namespace contour_strategy_test {

using geometry::ContourStrategy;
using geometry::LayerStack;
using geometry::Region;

namespace {

constexpr double kPi = std::numbers::pi;

// The larger of the two directed distances between the boundaries of two regions, measured
// from every vertex (both boundaries are dense here, so vertices are where it peaks).
double boundary_distance(const Region& a, const Region& b) {
  const geometry::BoundaryGrid ga(a), gb(b);
  double worst = 0;
  for (const auto& loop : a.loops)
    for (auto p : loop) worst = std::max(worst, gb.nearest_distance(p));
  for (const auto& loop : b.loops)
    for (auto p : loop) worst = std::max(worst, ga.nearest_distance(p));
  return worst;
}

}  // namespace

const ContourStrategy& strategy(std::string_view name) { return geometry::contour_strategy(name); }

TEST_CASE("contour_names_round_trip") {
  const auto table = geometry::contour_strategies();
  REQUIRE(table.size() >= 4);
  for (const ContourStrategy& s : table) {
    CAPTURE(s.name);
    CHECK(geometry::find_contour_strategy(s.name) == &s);
  }
  CHECK(table[0].name == "lower");
  CHECK(table[1].name == "mid");
  CHECK(table[2].name == "optimal-height");
  CHECK(table[3].name == "ma");
  CHECK(table[4].name == "best");
  CHECK(geometry::find_contour_strategy("optimal_height") == &table[2]);
  CHECK(geometry::find_contour_strategy("median") == nullptr);
  CHECK(geometry::find_contour_strategy("") == nullptr);
  CHECK_THROWS_AS(geometry::contour_strategy("median"), std::logic_error);
  CHECK(geometry::contour_names() == "lower, mid, optimal-height, ma, best");
}

TEST_CASE("every_strategy_has_a_description_and_a_colour_of_its_own") {
  const auto table = geometry::contour_strategies();
  for (std::size_t i = 0; i < table.size(); ++i) {
    CAPTURE(table[i].name);
    CHECK(!table[i].description.empty());
    CHECK(table[i].description.back() != '.');
    CHECK(table[i].colour.size() == 7);
    CHECK(table[i].colour.front() == '#');
    CHECK(bool(table[i].contour));
    for (std::size_t k = 0; k < i; ++k) {
      CHECK(table[k].name != table[i].name);
      CHECK(table[k].colour != table[i].colour);
    }
  }
}

TEST_CASE("cone_ma_equals_mid") {
  // Between two concentric similar n-gons the medial axis is the similar n-gon half-way, except
  // within the corners, where it bends towards the inner corner by (drho/4) (pi/n)^2: 1e-4 mm
  // here. The medial-axis contour is sampled and faired to 1 um.
  const int n = 64;
  const double r = 10, h = 15;
  const solids::Solid cone = solids::cone(r, h, n);
  const LayerStack stack(cone.mesh, geometry::uniform_layers(h, 0.25));
  for (std::size_t i : {0u, 10u, 30u, 50u}) {
    CAPTURE(i);
    const Region ma = geometry::layer_contour(stack, i, strategy("ma"));
    const Region mid = geometry::layer_contour(stack, i, strategy("mid"));
    REQUIRE(ma.loops.size() == 1);
    CHECK(boundary_distance(ma, mid) <= 2e-3);
    // And so their distance errors agree: D = t r / (2h) for both (distance_error_test.cpp).
    const geometry::LayerMetrics m = geometry::layer_metrics(stack, i, ma);
    const double t = stack.layers()[i].thickness();
    CHECK(std::abs(m.distance - t * r / (2 * h)) <= 3e-3);
    CHECK(m.missed_features == 0);
  }
}

TEST_CASE("cylinder_all_strategies_equal_with_zero_error") {
  const solids::Solid cylinder = solids::cylinder(5, 6, 40);
  const LayerStack stack(cylinder.mesh, geometry::uniform_layers(6, 0.2));
  for (std::size_t i : {0u, 13u, 29u}) {
    CAPTURE(i);
    const Region section = stack.lower(i);
    for (const ContourStrategy& kind : geometry::contour_strategies()) {
      CAPTURE(kind.name);
      const Region region = geometry::layer_contour(stack, i, kind);
      CHECK(boundary_distance(region, section) <= 1e-3);
      const geometry::LayerMetrics m = geometry::layer_metrics(stack, i, region);
      // Exact for the section itself; the medial-axis contour of a wall sits within its
      // fairing tolerance of it.
      CHECK(m.volume_deviation <= 0.2 * geometry::perimeter(section) * 1e-3);
      CHECK(m.distance <= 1e-3);
      CHECK(m.reverse_distance <= 1e-3);
      CHECK(m.volume_limit <= 1e-9);
      CHECK(m.missed_features == 0);
    }
  }
}

TEST_CASE("no_strategy_beats_the_volume_limit") {
  const solids::Solid sphere = solids::sphere(8, 48, 24, {0, 0, 8});
  const solids::Solid torus = solids::torus(10, 3, 40, 16, {0, 0, 3});
  for (const solids::Solid* solid : {&sphere, &torus}) {
    const LayerStack stack(solid->mesh, geometry::uniform_layers(16, 0.4));
    for (std::size_t i = 0; i < stack.size(); i += 3) {
      CAPTURE(i);
      const geometry::LayerReference reference = geometry::layer_reference(stack, i);
      for (const ContourStrategy& kind : geometry::contour_strategies()) {
        CAPTURE(kind.name);
        const Region region = geometry::layer_contour(stack, i, kind);
        const geometry::LayerMetrics m = geometry::layer_metrics(reference, region);
        // Both are exact up to Clipper's 1 pm grid.
        CHECK(m.volume_limit <= m.volume_deviation + 1e-9 * 0.4 * geometry::perimeter(region) + 1e-12);
      }
    }
  }
}

TEST_CASE("out_of_range_layer_gives_an_empty_contour") {
  const solids::Solid cube = solids::cube(2);
  const LayerStack stack(cube.mesh, geometry::uniform_layers(2, 0.5));
  CHECK(geometry::layer_contour(stack, 99, strategy("ma")).loops.empty());
  CHECK(geometry::layer_contour(stack, 4, strategy("lower")).loops.empty());
}

}  // namespace contour_strategy_test
