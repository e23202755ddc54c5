// All metrics of one region in one call, on a cone layer whose figures are known in closed
// form (see distance_error_test.cpp and volume_limit_test.cpp).
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "geometry/metrics/layer_metrics.h"
#include "geometry/slab/boundary_pair.h"
#include "geometry/slab/slab.h"
#include "support/solids.h"

namespace layer_metrics_test {

TEST_CASE("cone_layer_metrics_in_one_call") {
  const int n = 48;
  const double r = 10, h = 20;
  const solids::Solid cone = solids::cone(r, h, n);
  const geometry::LayerStack stack(cone.mesh, geometry::uniform_layers(h, 0.4));
  const std::size_t i = 12;
  const geometry::Layer layer = stack.layers()[i];
  const geometry::LayerReference reference = geometry::layer_reference(stack, i);
  const geometry::LayerMetrics lower = geometry::layer_metrics(reference, stack.lower(i));
  const geometry::LayerMetrics mid = geometry::layer_metrics(reference, stack.mid(i));

  CHECK(lower.z_lo == layer.z_lo);
  CHECK(lower.thickness == doctest::Approx(0.4));
  CHECK(lower.area == doctest::Approx(solids::regular_polygon_area(n, r * (1 - layer.z_lo / h))));
  // k ∫ (rho(z_lo)^2 - rho(z)^2) dz with rho(z) = r (1 - z/h).
  const double k = n / 2.0 * std::sin(2 * std::numbers::pi / n);
  const auto big_r = [&](double z) { return -r * r * h / 3 * std::pow(1 - z / h, 3); };
  const double rho_lo = r * (1 - layer.z_lo / h);
  const double exact_lower =
      k * (rho_lo * rho_lo * layer.thickness() - (big_r(layer.z_hi) - big_r(layer.z_lo)));
  // Exact up to the 1 pm grid of the cap intersection: 1e-9 mm x 60 mm x 0.4 mm.
  CHECK(lower.volume_deviation == doctest::Approx(exact_lower).epsilon(1e-7));
  CHECK(lower.volume_limit == doctest::Approx(mid.volume_deviation).epsilon(1e-7));
  CHECK(lower.distance == doctest::Approx(0.4 * r * std::cos(std::numbers::pi / n) / h).epsilon(1e-3));
  CHECK(mid.distance == doctest::Approx(0.4 * r / (2 * h)).epsilon(1e-3));
  CHECK(lower.hausdorff == std::max(lower.distance, lower.reverse_distance));
  CHECK(lower.missed_features == 0);

  // The reference and the one-shot call agree.
  const geometry::LayerMetrics again = geometry::layer_metrics(stack, i, stack.lower(i));
  CHECK(again.volume_deviation == lower.volume_deviation);
  CHECK(again.distance == lower.distance);
}

TEST_CASE("distance_only_metrics_keep_the_distance_and_leave_the_rest") {
  // What advise asks for: D alone, the same D as the full metrics give.
  const solids::Solid cone = solids::cone(10, 20, 48);
  const geometry::LayerStack stack(cone.mesh, geometry::uniform_layers(20, 0.4));
  geometry::MetricOptions distance_only;
  distance_only.volumes = false;
  distance_only.distance.reverse = false;
  for (std::size_t i : {3u, 12u, 40u}) {
    const geometry::Region mid = stack.mid(i);
    const geometry::LayerMetrics full = geometry::layer_metrics(stack, i, mid);
    const geometry::LayerMetrics d = geometry::layer_metrics(stack, i, mid, distance_only);
    CAPTURE(i);
    CHECK(d.distance == full.distance);
    CHECK(full.volume_deviation > 0);
    CHECK(full.reverse_distance > 0);
    CHECK(d.volume_deviation == 0);
    CHECK(d.volume_limit == 0);
    CHECK(d.reverse_distance == 0);
    CHECK(d.hausdorff == d.distance);
    CHECK(d.area == full.area);
  }
}

TEST_CASE("layer_metrics_of_a_missing_layer_are_zero") {
  const solids::Solid cube = solids::cube(2);
  const geometry::LayerStack stack(cube.mesh, geometry::uniform_layers(2, 0.5));
  const geometry::Region square{{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}};
  const geometry::LayerMetrics m = geometry::layer_metrics(stack, 9, square);
  CHECK(m.area == doctest::Approx(1));
  CHECK(m.volume_deviation == doctest::Approx(0));
  CHECK(m.volume_limit == 0);
  CHECK(m.distance == 0);
  CHECK(m.missed_features == 0);
}

TEST_CASE("layer_reference_keeps_the_boundary_pairs_of_the_slab_footprint") {
  // A torus lying flat, cut above its middle, beside a cone cut through its flank: the slab's
  // footprint is three annuli (each a pair with one hole), the torus's outer and inner flanks
  // and the cone's; the islands the reference keeps are boundary_pairs of the footprint, loop
  // for loop.
  const solids::Solid both =
      solids::combine(solids::torus(6, 2, 32, 16), solids::cone(4, 8, 24, {20, 0, -2}));
  const geometry::LayerStack stack(both.mesh, geometry::uniform_layers(4, 0.3));
  for (const std::size_t i : {std::size_t{2}, std::size_t{5}}) {
    const geometry::LayerReference reference = geometry::layer_reference(stack, i);
    const std::vector<geometry::BoundaryPair> expected =
        geometry::boundary_pairs(geometry::slab_footprint(geometry::slab_of(stack, i)));
    REQUIRE(expected.size() == 3);
    REQUIRE(reference.islands.size() == expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      CHECK(expected[k].inner.size() == 1);
      CHECK(reference.islands[k].outer == expected[k].outer);
      CHECK(reference.islands[k].inner == expected[k].inner);
    }
  }
}

}  // namespace layer_metrics_test
