// The swept volume (swept_volume.h) against closed forms and against the exact volume
// deviation of the mid contour (volume_deviation.h, through layer_metrics.h).
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/metrics/layer_metrics.h"
#include "geometry/plan/swept_volume.h"
#include "geometry/slicing/layer_stack.h"
#include "support/solids.h"

namespace swept_volume_test {

namespace {

// mid's ΔV of the slab [a, b] of a stack's mesh, as analyze measures it.
double mid_deviation(const geometry::Mesh& mesh, double a, double b) {
  const geometry::LayerStack stack(mesh, {geometry::Layer{a, b}});
  return geometry::layer_metrics(stack, 0, stack.mid(0)).volume_deviation;
}

}  // namespace

TEST_CASE("swept_volume_of_a_cone_is_the_closed_form_of_its_mid_contour") {
  // Sections are n-gons of circumradius r(z) = R (1 - z / H), nested: the area between the
  // section at z and at the middle m is |A(z) - A(m)|, A = n/2 r^2 sin(2 pi / n).
  const int n = 64;
  const double radius = 10, height = 20;
  const solids::Solid cone = solids::cone(radius, height, n);
  const geometry::SweptVolume swept(cone.mesh);
  const double k = 0.5 * n * std::sin(2 * std::numbers::pi / n);
  const auto area = [&](double z) { const double r = radius * (1 - z / height); return k * r * r; };
  for (const auto& [a, b] : std::vector<std::pair<double, double>>{{0, 0.2}, {3.1, 3.5}, {12, 12.15}, {19.7, 20}}) {
    CAPTURE(a);
    const double m = 0.5 * (a + b);
    // |A(z) - A(m)| is a quadratic on each side of m: Simpson's rule is exact there.
    const auto half = [&](double lo, double hi) {
      const auto f = [&](double z) { return std::abs(area(z) - area(m)); };
      return (hi - lo) / 6 * (f(lo) + 4 * f(0.5 * (lo + hi)) + f(hi));
    };
    const double closed = half(a, m) + half(m, b);
    CHECK(swept(a, b) == doctest::Approx(closed).epsilon(1e-9));
    CHECK(swept(a, b) == doctest::Approx(mid_deviation(cone.mesh, a, b)).epsilon(1e-6));
  }
  CHECK(swept(5, 5) == 0);
  CHECK(swept(30, 31) == 0);  // above the part
}

TEST_CASE("swept_volume_is_mid_deviation_on_one_sheet_and_above_it_on_two") {
  // A sphere: one sheet between any height of a layer and its middle over every point, at its
  // poles too, but for a layer whose middle is on one side of the equator and some of it on the
  // other: the surface there runs out to the equator and back in over the same points.
  const solids::Solid ball = solids::sphere(8, 48, 24, {0, 0, 8});
  const geometry::SweptVolume ball_swept(ball.mesh);
  for (double a : {0.0, 2.3, 7.75, 13.1, 15.75}) {
    CAPTURE(a);
    CHECK(ball_swept(a, a + 0.25) == doctest::Approx(mid_deviation(ball.mesh, a, a + 0.25)).epsilon(1e-6));
  }
  CHECK(ball_swept(7.9, 8.15) > mid_deviation(ball.mesh, 7.9, 8.15) + 1e-3);
  // A rhombus lying on its side (45 degree faces meeting at an edge at z = 5 all round): in
  // [4.8, 5.1] the middle is below the edge, and above it the surface between the middle and
  // z runs up the lower faces to the edge and back in along the upper ones, over the same
  // points: seen from above twice, in the section's difference once.
  const solids::Solid diamond = solids::diamond_prism(20, 5, 5, 5);
  const geometry::SweptVolume diamond_swept(diamond.mesh);
  CHECK(diamond_swept(4.8, 5.1) > mid_deviation(diamond.mesh, 4.8, 5.1) + 1e-3);
  CHECK(diamond_swept(4.8, 5.2) == doctest::Approx(mid_deviation(diamond.mesh, 4.8, 5.2)).epsilon(1e-6));
}

TEST_CASE("swept_volume_of_a_flat_level_inside_a_slab_is_the_step_it_leaves") {
  // A stepped box (20 x 20 to 4 mm, 10 x 10 above to 7.5): a slab across the step at 4 whose
  // middle is above it leaves the 300 mm^2 ledge out from the step to its bottom.
  const solids::Solid block = solids::stepped_box({20, 20}, 4, {10, 10}, 3.5);
  const geometry::SweptVolume swept(block.mesh);
  CHECK(swept(3.9, 4.3) == doctest::Approx(300 * 0.1).epsilon(1e-9));
  CHECK(swept(3.9, 4.3) == doctest::Approx(mid_deviation(block.mesh, 3.9, 4.3)).epsilon(1e-6));
  CHECK(swept(4.0, 4.4) == doctest::Approx(0).epsilon(1e-12));
}

}  // namespace swept_volume_test
