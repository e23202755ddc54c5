// The volume limit ∫ min(occ, t - occ) against closed forms, and no region below it.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/slicing/layer_stack.h"
#include "geometry/slab/slab.h"
#include "geometry/slab/slab_columns.h"
#include "geometry/metrics/volume_deviation.h"
#include "geometry/metrics/volume_limit.h"
#include "support/solids.h"

namespace volume_limit_test {

using geometry::LayerStack;
using geometry::Region;

namespace {

constexpr double kPi = std::numbers::pi;

geometry::SlabColumns columns_of(const LayerStack& stack, std::size_t layer) {
  return geometry::slab_columns(geometry::slab_of(stack, layer), stack.lower(layer));
}

double rounding_bound(double t, const Region& region) {
  return 1e-9 * t * geometry::perimeter(region) + 1e-12;
}

// Exact ∫_0^H psi(h) dh for psi piecewise linear in h (trapezoids between all its kinks).
template <class F>
double integrate_piecewise_linear(F psi, std::vector<double> kinks) {
  std::sort(kinks.begin(), kinks.end());
  double total = 0;
  for (std::size_t i = 0; i + 1 < kinks.size(); ++i) {
    total += (kinks[i + 1] - kinks[i]) * (psi(kinks[i]) + psi(kinks[i + 1])) / 2;
  }
  return total;
}

}  // namespace

TEST_CASE("cone_limit_equals_mid_deviation") {
  // No fold: every column meets one facet, so the best region is the mid-plane section and
  // the limit is ΔV(mid): k [2 R(m) - R(lo) - R(hi) ... ] by the closed form of the cone test.
  const int n = 48;
  const solids::Solid cone = solids::cone(10, 20, n);
  const LayerStack stack(cone.mesh, geometry::uniform_layers(20, 0.4));
  const double k = n / 2.0 * std::sin(2 * kPi / n);
  const auto rho2 = [](double z) { return std::pow(10 * (1 - z / 20), 2); };
  const auto big_r = [](double z) { return -100.0 * 20 / 3 * std::pow(1 - z / 20, 3); };
  for (std::size_t i : {0u, 17u, 40u}) {
    const geometry::Layer layer = stack.layers()[i];
    const double h = layer.z_mid();
    const double exact = k * ((big_r(h) - big_r(layer.z_lo)) - rho2(h) * (h - layer.z_lo) +
                              rho2(h) * (layer.z_hi - h) - (big_r(layer.z_hi) - big_r(h)));
    const geometry::SlabColumns columns = columns_of(stack, i);
    CAPTURE(i);
    CHECK(geometry::volume_limit(columns) == doctest::Approx(exact).epsilon(1e-10));
    CHECK(std::abs(geometry::volume_deviation(columns, stack.mid(i)) - exact) <=
          rounding_bound(layer.thickness(), stack.mid(i)));
  }
}

TEST_CASE("folded_slab_limit_matches_closed_form") {
  // A rhombus prism lying along x (length L, half-width W, half-height H about z_mid = 2):
  // column y meets the solid over [2 - h, 2 + h], h = H (1 - |y|/W). For the slab
  // [2 - q, 2 + p]: occ(h) = min(h, p) + min(h, q), and the limit is
  //   2 L (W/H) ∫_0^H min(occ, t - occ) dh.
  // Where h < min(p, q) the column meets both an up- and a down-facing facet: a fold.
  const double L = 8, W = 3, H = 1.5;
  const solids::Solid diamond = solids::diamond_prism(L, W, 2.0, H);
  const LayerStack stack(diamond.mesh, geometry::layers_from_tops(std::vector<double>{1.7, 2.25, 3.5}));
  const geometry::Layer layer = stack.layers()[1];  // [1.7, 2.25]
  const double p = layer.z_hi - 2.0, q = 2.0 - layer.z_lo, t = layer.thickness();
  const auto occ = [&](double h) { return std::min(h, p) + std::min(h, q); };
  const auto psi = [&](double h) { return std::min(occ(h), t - occ(h)); };
  // Kinks: h = p, h = q, and where occ = t/2 (on 2h or on h + min(p, q)).
  std::vector<double> kinks{0, H, p, q, t / 4, t / 2 - std::min(p, q)};
  kinks.erase(std::remove_if(kinks.begin(), kinks.end(), [&](double h) { return h < 0 || h > H; }),
              kinks.end());
  const double exact = 2 * L * (W / H) * integrate_piecewise_linear(psi, kinks);
  const geometry::SlabColumns columns = columns_of(stack, 1);
  CHECK(geometry::volume_limit(columns) == doctest::Approx(exact).epsilon(1e-9));
  // Here the mid-plane section is not the best region: the fold costs it.
  CHECK(geometry::volume_deviation(columns, stack.mid(1)) > exact * (1 + 1e-3));
}

TEST_CASE("no_region_beats_the_limit") {
  const solids::Solid sphere = solids::sphere(10, 40, 20, {0, 0, 10});
  const solids::Solid torus = solids::torus(12, 4, 36, 12, {0, 0, 4});
  for (const solids::Solid* solid : {&sphere, &torus}) {
    const LayerStack stack(solid->mesh, geometry::uniform_layers(20, 0.45));
    for (std::size_t i = 0; i < stack.size(); i += 2) {
      const geometry::Layer layer = stack.layers()[i];
      const geometry::SlabColumns columns = columns_of(stack, i);
      const double limit = geometry::volume_limit(columns);
      CAPTURE(i);
      for (double f : {0.0, 0.2, 0.5, 0.7, 0.999}) {
        const Region region = stack.cross_section(layer.z_lo + f * layer.thickness());
        CHECK(limit <= geometry::volume_deviation(columns, region) +
                           rounding_bound(layer.thickness(), region));
      }
    }
  }
}

}  // namespace volume_limit_test
