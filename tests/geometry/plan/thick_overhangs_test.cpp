// Layers kept thin where thick ones would overhang (slab_bound.h's ThickOverhangEstimate,
// AdaptiveOptions::thick_overhangs) against closed forms: an n-gon frustum widening upwards
// has side facets leaning phi from vertical, tan(phi) = (dR/dz) cos(pi/n) (R the
// circumradius; a side's distance from the axis is R cos(pi/n)), and seen from below its
// sides between heights a and b cover the n-gon annulus between R(a) and R(b).
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/plan/flat_levels.h"
#include "geometry/plan/layer_plan.h"
#include "geometry/plan/slab_bound.h"
#include "geometry/slicing/layer_stack.h"
#include "support/solids.h"

namespace thick_overhangs_test {

using geometry::AdaptiveOptions;
using geometry::AdaptivePlan;
using geometry::AllowedThicknesses;

namespace {

const AllowedThicknesses kUpPlus2{.listed = {}, .min = 0.15, .max = 0.4, .step = 0.05, .first = 0.3};
constexpr int kSides = 64;
constexpr double kBead = 0.45;

// A frustum from radius 5 at z = 0 over 10 mm, its sides leaning `degrees` from vertical.
struct Frustum {
  double degrees, r_bottom = 5, height = 10;
  double growth() const {  // dR/dz
    return std::tan(degrees * std::numbers::pi / 180) / std::cos(std::numbers::pi / kSides);
  }
  double radius(double z) const { return r_bottom + growth() * z; }
  double lean() const { return std::tan(degrees * std::numbers::pi / 180); }
  solids::Solid solid() const { return solids::frustum(r_bottom, radius(height), height, kSides); }
  // The annulus the sides cover seen from below between heights a and b.
  double annulus(double a, double b) const {
    return solids::regular_polygon_area(kSides, radius(b)) - solids::regular_polygon_area(kSides, radius(a));
  }
};

AdaptivePlan plan_for(const geometry::Mesh& mesh, double tolerance, double overhang_angle) {
  const geometry::LayerStack stack(mesh, {});
  AdaptiveOptions options;
  options.tolerance = tolerance;
  options.thick_overhangs = {overhang_angle, kBead, 0.2};
  return geometry::adaptive_plan(stack, geometry::bounding_box(mesh).max.z, kUpPlus2,
                                 geometry::flat_levels(mesh), options);
}

}  // namespace

TEST_CASE("thick_overhang_estimate_of_a_widening_frustum_is_its_step_beyond_half_a_bead") {
  const Frustum frustum{40};
  const geometry::ThickOverhangEstimate estimate(frustum.solid().mesh, 50, kBead);
  // 0.2 mm: a step of 0.2 tan 40 = 0.168 mm, within half a bead.
  CHECK(estimate(2, 2.2) == 0);
  // 0.4 mm: 0.336 mm, a third of it beyond 0.225.
  const double share = 1 - kBead / 2 / (0.4 * frustum.lean());
  CHECK(estimate(2, 2.4) == doctest::Approx(share * frustum.annulus(2, 2.4)).epsilon(1e-9));
  // A slab past the part's ends holds only its part of it.
  CHECK(estimate(9.8, 10.2) == doctest::Approx((1 - kBead / 2 / (0.4 * frustum.lean())) *
                                               frustum.annulus(9.8, 10)).epsilon(1e-9));
}

TEST_CASE("thick_overhang_estimate_leaves_out_slopes_past_the_angle_and_upward_ones") {
  // Leaning 60 degrees: supported at any thickness, so none of it is the thickness's.
  const geometry::ThickOverhangEstimate steep(Frustum{60}.solid().mesh, 50, kBead);
  CHECK(steep(2, 2.4) == 0);
  // Narrowing upwards: every side faces up.
  const geometry::ThickOverhangEstimate narrowing(solids::frustum(12, 5, 10, kSides).mesh, 50, kBead);
  CHECK(narrowing(2, 2.4) == 0);
}

TEST_CASE("adaptive_plan_with_supports_keeps_layers_thin_on_slopes_the_material_holds") {
  // A tolerance every thickness meets (D = t tan 40 / 2 = 0.17 mm at 0.4): without supports
  // the thickest layers; with them no layer steps past 0.225 mm, w / (2 tan 40) = 0.268 mm,
  // so 0.25 mm: 9.7 mm above the first layer in 39 layers.
  const Frustum frustum{40};
  const AdaptivePlan free = plan_for(frustum.solid().mesh, 1.0, 0);
  const AdaptivePlan held = plan_for(frustum.solid().mesh, 1.0, 50);
  REQUIRE(free.layers.size() > 1);
  REQUIRE(held.layers.size() == 40);
  CHECK(free.layers.size() == 26);  // 0.3 + 24 x 0.4 + 0.1 rounded up: a flat top at 10
  CHECK(free.refused_for_overhangs == 0);
  CHECK(held.refused_for_overhangs > 0);
  CHECK(held.unmet == 0);
  for (std::size_t i = 1; i < held.layers.size(); ++i) {
    CHECK(held.layers[i].thickness() <= 0.25 + 1e-9);
  }
  CHECK(held.layers.back().z_hi == doctest::Approx(10).epsilon(1e-12));
}

TEST_CASE("adaptive_plan_with_supports_keeps_thick_layers_where_support_goes_anyway") {
  // Leaning 60 degrees, past the 50 the material holds: supported at any thickness, so the
  // plan is the same with supports as without.
  const Frustum steep{60};
  const AdaptivePlan free = plan_for(steep.solid().mesh, 1.0, 0);
  const AdaptivePlan held = plan_for(steep.solid().mesh, 1.0, 50);
  CHECK(held.refused_for_overhangs == 0);
  REQUIRE(held.layers.size() == free.layers.size());
  for (std::size_t i = 0; i < held.layers.size(); ++i) {
    CHECK(held.layers[i].z_hi == free.layers[i].z_hi);
  }
}

}  // namespace thick_overhangs_test
