// The optimal-height search (paper §3.1) against closed forms: when the sections shrink
// monotonically and nest, ΔV(h) = ∫ |A(z) - A(h)| dz is least where A(h) is the median of
// A(z) over the slab, i.e. at h = z_mid; and the search never returns worse than the lower
// or mid section, which it samples.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/mesh/orientation.h"
#include "geometry/mesh/placement.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/contour/optimal_height.h"
#include "geometry/slab/slab.h"
#include "geometry/slab/slab_columns.h"
#include "geometry/metrics/volume_deviation.h"
#include "support/solids.h"

namespace optimal_height_test {

using geometry::LayerStack;

TEST_CASE("cone_optimal_height_is_the_mid_plane") {
  const solids::Solid cone = solids::cone(10, 20, 48);
  const LayerStack stack(cone.mesh, geometry::uniform_layers(20, 0.3));
  geometry::OptimalHeightOptions options;
  options.tolerance = 1e-5;
  for (std::size_t i : {0u, 25u, 60u}) {
    CAPTURE(i);
    const geometry::OptimalHeight best = geometry::optimal_height(stack, i, options);
    const geometry::Layer layer = stack.layers()[i];
    const geometry::SlabColumns columns =
        geometry::slab_columns(geometry::slab_of(stack, i), stack.lower(i));
    const double mid = geometry::volume_deviation(columns, stack.mid(i));
    // Near its minimum ΔV(h) = ΔV(z_mid) + |A'| (h - z_mid)^2 with |A'| ~ 30 mm^2/mm, while the
    // sections' 1 nm rounding moves ΔV by ~1e-6 mm^3: the height is pinned to a few 1e-4 mm,
    // the deviation to the rounding.
    const double rounding = 1e-6 * layer.thickness() * geometry::perimeter(stack.mid(i));
    CHECK(std::abs(best.height - layer.z_mid()) <= 1e-3);
    CHECK(best.volume_deviation <= mid + rounding);
    CHECK(best.volume_deviation >= mid - 2 * rounding);
    CHECK(best.evaluations >= options.coarse_samples);
    CHECK(best.evaluations <= options.coarse_samples + 40);
  }
}

TEST_CASE("optimal_height_is_never_worse_than_lower_or_mid") {
  const solids::Solid sphere = solids::sphere(8, 40, 20, {0, 0, 8});
  const solids::Solid torus = solids::torus(10, 3, 36, 12, {0, 0, 3});
  for (const solids::Solid* solid : {&sphere, &torus}) {
    const LayerStack stack(solid->mesh, geometry::uniform_layers(16, 0.45));
    for (std::size_t i = 0; i < stack.size(); i += 2) {
      CAPTURE(i);
      const geometry::SlabColumns columns =
          geometry::slab_columns(geometry::slab_of(stack, i), stack.lower(i));
      const geometry::OptimalHeight best = geometry::optimal_height(stack, i, columns);
      // The search sums ΔV(h) per facet (SectionDeviation), exact to floating point; the metric
      // measures the section rounded to 1 nm: the two agree to ~1e-8.
      const auto at_most = [](double value, double bound) { return value <= bound * (1 + 1e-8) + 1e-12; };
      CHECK(at_most(best.volume_deviation, geometry::volume_deviation(columns, stack.lower(i))));
      CHECK(at_most(best.volume_deviation, geometry::volume_deviation(columns, stack.mid(i))));
      CHECK(best.height >= stack.layers()[i].z_lo);
      CHECK(best.height <= stack.layers()[i].z_hi);
      // What it reports is the ΔV of the section it returns.
      CHECK(best.volume_deviation ==
            doctest::Approx(geometry::volume_deviation(columns, best.section)).epsilon(1e-8));
    }
  }
}

TEST_CASE("section_deviation_sums_what_the_section_would_give") {
  // ΔV(h) summed per facet against ΔV of the section built at h, at heights that cut facets,
  // hit vertex rings, and on folded slabs: the sphere's equator, the torus's inner and outer
  // equators (up-facing and down-facing facets overlap seen from above), a cube's top; and the
  // sphere and torus turned about a skew axis, whose facets have corners at three heights
  // inside a slab (a revolved solid's have two), so that h meets them in two pieces.
  const solids::Solid sphere = solids::sphere(8, 40, 20, {0, 0, 8});
  const solids::Solid torus = solids::torus(10, 3, 36, 12, {0, 0, 3});
  const solids::Solid cube = solids::cube(5);
  geometry::Placement turn;
  turn.rotation = geometry::rotation_about({1, 2, 3}, 37);
  const geometry::Mesh turned_sphere = geometry::place(sphere.mesh, turn);
  const geometry::Mesh turned_torus = geometry::place(torus.mesh, turn);
  for (const geometry::Mesh* mesh : {&sphere.mesh, &torus.mesh, &cube.mesh, &turned_sphere, &turned_torus}) {
    const LayerStack stack(*mesh, geometry::uniform_layers(16, 0.45));
    for (std::size_t i = 0; i < stack.size(); ++i) {
      const geometry::Layer layer = stack.layers()[i];
      const geometry::SlabColumns columns =
          geometry::slab_columns(geometry::slab_of(stack, i), stack.lower(i));
      const geometry::SectionDeviation deviation(columns);
      for (double f : {0.0, 0.1, 0.37, 0.5, 0.81, 0.999}) {
        const double h = layer.z_lo + f * layer.thickness();
        CAPTURE(i);
        CAPTURE(h);
        const double built = geometry::volume_deviation(columns, stack.cross_section(h));
        CHECK(deviation(h) == doctest::Approx(built).epsilon(1e-8).scale(1));
      }
    }
  }
  // Exactly at a horizontal face inside the slab: the section from above, which the cube's
  // top has left (ΔV = the whole slab's volume, 5 x 5 x 0.05).
  const LayerStack stack(cube.mesh, {geometry::Layer{4.95, 5.4}});
  const geometry::SlabColumns columns = geometry::slab_columns(geometry::slab_of(stack, 0), stack.lower(0));
  CHECK(geometry::SectionDeviation(columns)(5.0) == doctest::Approx(25 * 0.05).epsilon(1e-12));
  CHECK(geometry::volume_deviation(columns, stack.cross_section(5.0)) == doctest::Approx(25 * 0.05).epsilon(1e-12));
}

// ΔV(h) of a slab whose sections are concentric regular n-gons (same phase, so nested) of
// circumradius R(z), piecewise linear through `knots` (z, R): vol(S △ C(h) x [z_lo, z_hi]) =
// ∫ |A(z) - A(h)| dz with A = k R^2, k = n/2 sin(2 pi/n). Split at the knots and where
// R(z) = R(h), the integrand is one quadratic on each part: Simpson's rule is exact there.
double nested_deviation(const std::vector<geometry::Vec2>& knots, int n, double z_lo, double z_hi,
                        double h) {
  const auto radius = [&](double z) {
    for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
      if (z <= knots[k + 1].x || k + 2 == knots.size()) {
        return knots[k].y + (knots[k + 1].y - knots[k].y) * (z - knots[k].x) / (knots[k + 1].x - knots[k].x);
      }
    }
    return knots.back().y;
  };
  const double k = n / 2.0 * std::sin(2 * M_PI / n), target = radius(h);
  std::vector<double> cuts{z_lo, z_hi};
  for (std::size_t j = 0; j + 1 < knots.size(); ++j) {
    const geometry::Vec2 a = knots[j], b = knots[j + 1];
    if (a.x > z_lo && a.x < z_hi) cuts.push_back(a.x);
    if (a.y != b.y) {
      const double z = a.x + (target - a.y) / (b.y - a.y) * (b.x - a.x);
      if (z > std::max(a.x, z_lo) && z < std::min(b.x, z_hi)) cuts.push_back(z);
    }
  }
  std::sort(cuts.begin(), cuts.end());
  const auto f = [&](double z) { return std::abs(k * radius(z) * radius(z) - k * target * target); };
  double sum = 0;
  for (std::size_t j = 0; j + 1 < cuts.size(); ++j) {
    const double a = cuts[j], b = cuts[j + 1];
    sum += (b - a) / 6 * (f(a) + 4 * f((a + b) / 2) + f(b));
  }
  return sum;
}

TEST_CASE("section_deviation_against_nested_ngons_closed_form") {
  // A frustum shrinking (its facets up-facing, over C(z_lo)), one growing (down-facing,
  // outside it), and a bipyramid whose equator lies inside the slab, so that facets of either
  // kind have a corner between z_lo and z_hi: ΔV(h) at 41 heights of each slab against the
  // closed form, and the search's height against the frustums' minimiser z_mid
  // (ΔV'(h) = ±A'(h) (2h - z_lo - z_hi)).
  const int n = 48;
  struct Case {
    solids::Solid solid;
    std::vector<geometry::Vec2> knots;
    geometry::Layer layer;
    bool minimum_at_mid;
  };
  const std::vector<Case> cases{
      {solids::frustum(10, 4, 6, n), {{0, 10}, {6, 4}}, {2.3, 2.5}, true},
      {solids::frustum(3, 9, 6, n), {{0, 3}, {6, 9}}, {4.1, 4.25}, true},
      {solids::bipyramid(8, n, 0, 3.07, 7), {{0, 0}, {3.07, 8}, {7, 0}}, {3.0, 3.15}, false},
  };
  for (const Case& c : cases) {
    const LayerStack stack(c.solid.mesh, {geometry::Layer{0, c.layer.z_lo}, c.layer,
                                          geometry::Layer{c.layer.z_hi, c.knots.back().x}});
    const geometry::SlabColumns columns = geometry::slab_columns(geometry::slab_of(stack, 1), stack.lower(1));
    const geometry::SectionDeviation deviation(columns);
    const double t = c.layer.thickness();
    for (int j = 0; j <= 40; ++j) {
      const double h = c.layer.z_lo + t * j / 40;
      CAPTURE(h);
      const double exact = nested_deviation(c.knots, n, c.layer.z_lo, c.layer.z_hi, h);
      CHECK(deviation(h) == doctest::Approx(exact).epsilon(1e-9).scale(1e-9));
    }
    const geometry::OptimalHeight best = geometry::optimal_height(stack, 1, columns);
    CHECK(best.volume_deviation ==
          doctest::Approx(nested_deviation(c.knots, n, c.layer.z_lo, c.layer.z_hi, best.height)).epsilon(1e-9));
    if (c.minimum_at_mid) CHECK(std::abs(best.height - c.layer.z_mid()) <= 1e-4);
    // No height of a fine scan does better than the search by more than its tolerance allows
    // (|ΔV''| (1e-4 mm)^2, ~1e-6 of ΔV here).
    for (int j = 0; j <= 200; ++j) {
      const double h = c.layer.z_lo + t * j / 200;
      CHECK(best.volume_deviation <= nested_deviation(c.knots, n, c.layer.z_lo, c.layer.z_hi, h) * (1 + 1e-5));
    }
  }
}

TEST_CASE("section_deviation_of_a_fold_of_two_planes_closed_form") {
  // A prism lying along x, 10 mm long, whose section at z is [0, 10] x [0, y(z)] with y
  // falling from 6 at z = 0 to 3 at z = 1.1 and rising to 7 at z = 2. In the slab [1.0, 1.3]
  // the falling plane (up-facing, over C(z_lo): y in [3, 3.27]) and the rising one
  // (down-facing: y in [3, 3.89], partly outside C(z_lo)) overlap seen from above, a fold:
  // each facet's share at h takes its intersection with its partners cut at h, for h on
  // either side of the crease and exactly on it. The sections nest, so
  // ΔV(h) = 10 ∫ |y(z) - y(h)| dz over the slab; y is linear on each part between the crease
  // and where y(z) = y(h), where the trapezoid rule is exact.
  const std::vector<geometry::Vec2> knots{{0, 6}, {1.1, 3}, {2, 7}};  // (z, y)
  const solids::Solid prism = solids::lying_prism({{0, 0}, {6, 0}, {3, 1.1}, {7, 2}, {0, 2}}, 0, 10);
  const geometry::Layer layer{1.0, 1.3};
  const auto y = [&](double z) {
    const geometry::Vec2 a = z <= knots[1].x ? knots[0] : knots[1], b = z <= knots[1].x ? knots[1] : knots[2];
    return a.y + (b.y - a.y) * (z - a.x) / (b.x - a.x);
  };
  const auto exact = [&](double h) {
    const double target = y(h);
    std::vector<double> cuts{layer.z_lo, layer.z_hi, knots[1].x};
    for (std::size_t j = 0; j + 1 < knots.size(); ++j) {
      const geometry::Vec2 a = knots[j], b = knots[j + 1];
      const double z = a.x + (target - a.y) / (b.y - a.y) * (b.x - a.x);
      if (z > layer.z_lo && z < layer.z_hi) cuts.push_back(z);
    }
    std::sort(cuts.begin(), cuts.end());
    double sum = 0;
    for (std::size_t j = 0; j + 1 < cuts.size(); ++j) {
      const double a = cuts[j], b = cuts[j + 1];
      sum += (b - a) / 2 * (std::abs(y(a) - target) + std::abs(y(b) - target));
    }
    return 10 * sum;
  };
  const LayerStack stack(prism.mesh, {geometry::Layer{0, layer.z_lo}, layer, geometry::Layer{layer.z_hi, 2}});
  const geometry::SlabColumns columns = geometry::slab_columns(geometry::slab_of(stack, 1), stack.lower(1));
  std::size_t folded = 0;
  for (const std::vector<int>& partners : columns.overlapping) folded += partners.size();
  CHECK(folded > 0);
  const geometry::SectionDeviation deviation(columns);
  for (int j = 0; j <= 60; ++j) {
    const double h = layer.z_lo + layer.thickness() * j / 60;
    if (!(h < layer.z_hi)) continue;
    CAPTURE(h);
    CHECK(deviation(h) == doctest::Approx(exact(h)).epsilon(1e-9).scale(1e-9));
  }
  CHECK(deviation(1.1) == doctest::Approx(exact(1.1)).epsilon(1e-9).scale(1e-9));
  // The search's height is no worse than a fine scan's best beyond its tolerance.
  const geometry::OptimalHeight best = geometry::optimal_height(stack, 1, columns);
  CHECK(best.volume_deviation == doctest::Approx(exact(best.height)).epsilon(1e-9).scale(1e-9));
  for (int j = 0; j <= 300; ++j) {
    const double h = layer.z_lo + layer.thickness() * j / 300;
    CHECK(best.volume_deviation <= exact(h) + 1e-6);
  }
}

TEST_CASE("optimal_height_of_a_missing_layer_is_empty") {
  const solids::Solid cube = solids::cube(1);
  const LayerStack stack(cube.mesh, geometry::uniform_layers(1, 0.5));
  const geometry::OptimalHeight none = geometry::optimal_height(stack, 7);
  CHECK(none.section.loops.empty());
  CHECK(none.evaluations == 0);
}

}  // namespace optimal_height_test
