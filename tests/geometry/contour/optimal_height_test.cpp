// The optimal-height search (paper §3.1) against closed forms: when the sections shrink
// monotonically and nest, ΔV(h) = ∫ |A(z) - A(h)| dz is least where A(h) is the median of
// A(z) over the slab, i.e. at h = z_mid; and the search never returns worse than the lower
// or mid section, which it samples.
#include <doctest/doctest.h>

#include <cmath>

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
  // equators (up-facing and down-facing facets overlap seen from above), a cube's top.
  const solids::Solid sphere = solids::sphere(8, 40, 20, {0, 0, 8});
  const solids::Solid torus = solids::torus(10, 3, 36, 12, {0, 0, 3});
  const solids::Solid cube = solids::cube(5);
  for (const solids::Solid* solid : {&sphere, &torus, &cube}) {
    const LayerStack stack(solid->mesh, geometry::uniform_layers(16, 0.45));
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

TEST_CASE("optimal_height_of_a_missing_layer_is_empty") {
  const solids::Solid cube = solids::cube(1);
  const LayerStack stack(cube.mesh, geometry::uniform_layers(1, 0.5));
  const geometry::OptimalHeight none = geometry::optimal_height(stack, 7);
  CHECK(none.section.loops.empty());
  CHECK(none.evaluations == 0);
}

}  // namespace optimal_height_test
