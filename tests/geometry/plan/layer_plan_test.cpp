// The layer plan against closed forms: flat levels of stepped boxes, uniform layers that land
// an 8.00 mm top at 8.00 mm, and adaptive plans whose layers meet the tolerance by the exact
// distance error of the mid contour on cones and spheres, derived here from the polygonal
// sections (solids.h): between two ring heights a section is a regular n-gon whose
// circumradius rho(z) is linear in z, so a surface point at height z is |rho(z) - rho(m)|
// from the mid section's wall at the n-gon's corners where rho(z) > rho(m), and
// (rho(m) - rho(z)) cos(pi / n) across its edges where rho(z) < rho(m).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "geometry/analysis/layer_analysis.h"
#include "geometry/metrics/layer_metrics.h"
#include "geometry/plan/flat_levels.h"
#include "geometry/plan/layer_plan.h"
#include "geometry/slicing/layer_stack.h"
#include "support/build_kind.h"
#include "support/bunny.h"
#include "support/solids.h"

namespace layer_plan_test {

using geometry::AdaptiveOptions;
using geometry::AdaptivePlan;
using geometry::Layer;
using geometry::AllowedThicknesses;

namespace {

// The UP Plus 2: 0.15 to 0.4 mm in steps of 0.05, a first layer of 0.3.
const AllowedThicknesses kUpPlus2{.listed = {}, .min = 0.15, .max = 0.4, .step = 0.05, .first = 0.3};

bool allowed(double t, const AllowedThicknesses& a) {
  if (t < a.min - 1e-9 || t > a.max + 1e-9) return false;
  const double steps = (t - a.min) / a.step;
  return std::abs(steps - std::round(steps)) < 1e-6;
}

void check_thicknesses(const std::vector<Layer>& layers, const AllowedThicknesses& a) {
  REQUIRE(!layers.empty());
  CHECK(layers.front().z_lo == 0);
  CHECK(layers.front().z_hi == doctest::Approx(a.first).epsilon(1e-12));
  for (std::size_t i = 1; i < layers.size(); ++i) {
    CHECK(layers[i].z_lo == layers[i - 1].z_hi);
    CHECK_MESSAGE(allowed(layers[i].thickness(), a), "layer " << i << " is "
                                                               << layers[i].thickness() << " mm");
  }
}

bool has_boundary(const std::vector<Layer>& layers, double z) {
  return std::any_of(layers.begin(), layers.end(), [&](const Layer& l) { return l.z_hi == z; });
}

// D of the mid contour of [a, b] for a solid of revolution whose section is a regular n-gon of
// circumradius rho(z), piecewise linear with breakpoints `rings` (see the file comment); a
// missed tip (empty mid section, surface below it) is measured to the surface's own outline,
// as distance_error.h does.
double mid_distance(const std::function<double(double)>& rho, std::span<const double> rings,
                    int n, double a, double b) {
  const double m = 0.5 * (a + b);
  std::vector<double> heights{a, b};
  for (double z : rings) {
    if (z > a && z < b) heights.push_back(z);
  }
  const double r_mid = rho(m);
  double widest = 0, d = 0;
  for (double z : heights) widest = std::max(widest, rho(z));
  if (r_mid <= 0) return widest;
  for (double z : heights) {
    const double r = rho(z);
    d = std::max(d, r > r_mid ? r - r_mid : (r_mid - r) * std::cos(std::numbers::pi / n));
  }
  return d;
}

// The plan a greedy slicer would make from the same formula: from the bottom, each layer the
// thickest allowed whose D meets the tolerance (the thinnest where none does). A valid plan,
// so the optimum has no more layers.
std::size_t greedy_layers(const std::function<double(double, double)>& distance, double top,
                          double tolerance, const AllowedThicknesses& a) {
  std::size_t count = 1;
  for (double z = a.first; z < top - 1e-9; ++count) {
    double chosen = a.min;
    for (double t = a.max; t >= a.min - 1e-9; t -= a.step) {
      if (distance(z, z + t) <= tolerance) {
        chosen = t;
        break;
      }
    }
    z += chosen;
  }
  return count;
}

AdaptivePlan plan_for(const geometry::Mesh& mesh, double tolerance,
                      const AllowedThicknesses& allowed_thicknesses = kUpPlus2,
                      std::vector<const geometry::ContourStrategy*> contours = {
                          &geometry::contour_strategy("mid")}) {
  const geometry::LayerStack stack(mesh, {});
  AdaptiveOptions options;
  options.tolerance = tolerance;
  options.contours = std::move(contours);
  const double top = geometry::bounding_box(mesh).max.z;
  return geometry::adaptive_plan(stack, top, allowed_thicknesses, geometry::flat_levels(mesh),
                                 options);
}

}  // namespace

TEST_CASE("flat_levels_of_a_stepped_box_are_its_floor_step_and_top") {
  const solids::Solid block = solids::stepped_box({20, 20}, 4, {10, 10}, 3.5);
  const auto levels = geometry::flat_levels(block.mesh);
  REQUIRE(levels.size() == 3);
  CHECK(levels[0].z == 0);
  CHECK(levels[0].area == doctest::Approx(400));
  CHECK(levels[1].z == 4);
  CHECK(levels[1].area == doctest::Approx(300));  // the ledge round the upper box
  CHECK(levels[2].z == 7.5);
  CHECK(levels[2].area == doctest::Approx(100));
}

TEST_CASE("flat_levels_leave_out_sloped_faces_and_specks") {
  CHECK(geometry::flat_levels(solids::cone(10, 20, 64).mesh).size() == 1);  // the base only
  CHECK(geometry::flat_levels(solids::sphere(10, 32, 16).mesh).empty());
  CHECK(geometry::flat_levels(solids::cube(0.2).mesh).empty());  // 0.04 mm^2 < kFlatMinArea
  CHECK(geometry::flat_levels(geometry::Mesh{}).empty());
}

TEST_CASE("uniform_plan_lands_an_8_mm_top_at_8_mm") {
  const solids::Solid part = solids::box({-10, -10, 0}, {10, 10, 8});
  const auto plan =
      geometry::uniform_plan(8.0, 0.15, kUpPlus2, geometry::flat_levels(part.mesh));
  check_thicknesses(plan.layers, kUpPlus2);
  CHECK(plan.layers.back().z_hi == 8.0);
  // 7.7 mm above the first layer: 51 layers of 0.15 leave 0.05, one step on one layer.
  CHECK(plan.layers.size() == 52);
  const auto odd = std::count_if(plan.layers.begin() + 1, plan.layers.end(), [](const Layer& l) {
    return std::abs(l.thickness() - 0.15) > 1e-9;
  });
  CHECK(odd == 1);
  REQUIRE(plan.flats.size() == 1);
  CHECK(plan.flats[0].on_boundary());
}

TEST_CASE("uniform_plan_without_flat_levels_above_the_bed_is_uniform_layers") {
  const solids::Solid cone = solids::cone(10, 20, 64);
  const auto plan = geometry::uniform_plan(20, 0.15, kUpPlus2, geometry::flat_levels(cone.mesh));
  const auto plain = geometry::uniform_layers(20, 0.15, 0.3);
  REQUIRE(plan.layers.size() == plain.size());
  for (std::size_t i = 0; i < plain.size(); ++i) {
    CHECK(plan.layers[i].z_lo == plain[i].z_lo);  // bit for bit
    CHECK(plan.layers[i].z_hi == plain[i].z_hi);
  }
}

TEST_CASE("uniform_plan_puts_each_step_of_a_stepped_box_on_a_boundary") {
  const solids::Solid block = solids::stepped_box({20, 20}, 4, {10, 10}, 3.5);
  for (double t : {0.15, 0.2, 0.25, 0.3, 0.4}) {
    const auto plan = geometry::uniform_plan(7.5, t, kUpPlus2, geometry::flat_levels(block.mesh));
    check_thicknesses(plan.layers, kUpPlus2);
    CHECK(has_boundary(plan.layers, 4.0));
    CHECK(plan.layers.back().z_hi == 7.5);
    for (const auto& flat : plan.flats) CHECK(flat.on_boundary());
  }
}

TEST_CASE("uniform_plan_reports_a_level_the_thicknesses_cannot_reach") {
  // 8.03 - 0.3 is no multiple of 0.05: the top stays where the plain grid puts it.
  const solids::Solid part = solids::box({-10, -10, 0}, {10, 10, 8.03});
  const auto plan = geometry::uniform_plan(8.03, 0.15, kUpPlus2, geometry::flat_levels(part.mesh));
  check_thicknesses(plan.layers, kUpPlus2);
  REQUIRE(plan.flats.size() == 1);
  CHECK_FALSE(plan.flats[0].on_boundary());
  CHECK(std::abs(plan.flats[0].boundary - 8.03) == doctest::Approx(0.02).epsilon(1e-6));
}

TEST_CASE("adaptive_plan_of_a_vertical_prism_is_thickest_everywhere") {
  // 0.3 + 24 x 0.4: vertical walls have D = 0 at any thickness.
  const solids::Solid prism = solids::cylinder(10, 9.9, 48);
  const AdaptivePlan plan = plan_for(prism.mesh, 0.05);
  check_thicknesses(plan.layers, kUpPlus2);
  CHECK(plan.layers.size() == 25);
  for (std::size_t i = 1; i < plan.layers.size(); ++i) {
    CHECK(plan.layers[i].thickness() == doctest::Approx(0.4));
  }
  CHECK(plan.unmet == 0);
  CHECK(plan.layers.back().z_hi == doctest::Approx(9.9).epsilon(1e-12));
}

TEST_CASE("adaptive_plan_lands_a_flat_top_that_thickest_layers_would_pass") {
  // 10 - 0.3 = 9.7 = 24 x 0.4 + 0.1: the fewest layers reaching exactly 10 is 25 above the
  // first, and the top lands on a boundary.
  const solids::Solid prism = solids::box({-5, -5, 0}, {5, 5, 10});
  const AdaptivePlan plan = plan_for(prism.mesh, 0.05);
  check_thicknesses(plan.layers, kUpPlus2);
  CHECK(plan.layers.back().z_hi == 10.0);
  CHECK(plan.layers.size() == 26);
  CHECK(plan.unmet == 0);
}

TEST_CASE("adaptive_plan_of_a_stepped_box_has_each_step_on_a_boundary") {
  const solids::Solid block = solids::stepped_box({20, 20}, 4, {10, 10}, 3.5);
  const AdaptivePlan plan = plan_for(block.mesh, 0.05);
  check_thicknesses(plan.layers, kUpPlus2);
  CHECK(has_boundary(plan.layers, 4.0));
  CHECK(plan.layers.back().z_hi == 7.5);
  for (const auto& flat : plan.flats) CHECK(flat.on_boundary());
  CHECK(plan.unmet == 0);
}

TEST_CASE("adaptive_plan_names_a_step_off_the_reachable_heights_as_the_reason_for_its_layer") {
  // A 20 mm box with a 10 mm one on it from 4.13 mm: the UP Plus 2 reaches 4.10 and 4.15
  // (0.3 + k 0.05), so some layer holds the step, and its D is at least the step's 5 mm width
  // (7.07 at the corners, with the upper box's section). That layer has only vertical walls
  // besides the step: the reason is the flat level, not a slope.
  const solids::Solid block = solids::stepped_box({20, 20}, 4.13, {10, 10}, 3.5);
  const AdaptivePlan plan = plan_for(block.mesh, 0.05);
  check_thicknesses(plan.layers, kUpPlus2);
  std::size_t holding = 0;
  for (std::size_t i = 1; i < plan.layers.size(); ++i) {
    const Layer& l = plan.layers[i];
    CAPTURE(l.z_lo);
    if (l.z_lo < 4.13 && l.z_hi > 4.13) {
      ++holding;
      CHECK(plan.distance[i] >= 5 - 1e-6);
      CHECK(plan.why[i] == geometry::OverTolerance::flat_level);
    } else {
      CHECK(plan.why[i] == geometry::OverTolerance::none);
    }
  }
  CHECK(holding == 1);
  CHECK(plan.unmet == 1);
}

TEST_CASE("adaptive_plan_of_a_cone_meets_the_tolerance_by_the_closed_form") {
  // Circumradius 10 (1 - z / 20): D of a layer t thick is t / 4 off the apex, so the
  // tolerance 0.07 allows 0.28 mm and the UP Plus 2's steps 0.25 mm.
  const int n = 64;
  const solids::Solid cone = solids::cone(10, 20, n);
  auto rho = [](double z) { return std::max(0.0, 10 * (1 - z / 20)); };
  const std::vector<double> rings{20};
  auto distance = [&](double a, double b) { return mid_distance(rho, rings, n, a, b); };
  const double tolerance = 0.07;
  const AdaptivePlan plan = plan_for(cone.mesh, tolerance);
  check_thicknesses(plan.layers, kUpPlus2);
  CHECK(plan.layers.back().z_hi >= 20.0);
  for (std::size_t i = 1; i < plan.layers.size(); ++i) {
    const Layer& l = plan.layers[i];
    if (plan.met[i]) {
      CHECK_MESSAGE(distance(l.z_lo, l.z_hi) <= tolerance + 1e-3, "layer " << i);
    }
    if (l.z_hi <= 19) CHECK(l.thickness() <= 0.25 + 1e-9);
  }
  CHECK(plan.layers.size() <= greedy_layers(distance, 20, tolerance, kUpPlus2));
  // 19.7 mm of 0.25 mm layers (and the tip).
  CHECK(plan.layers.size() <= 1 + 80);
}

TEST_CASE("adaptive_plan_of_a_sphere_is_thinner_where_the_surface_flattens") {
  const int segments = 96, rings = 48;
  const double radius = 10;
  const solids::Solid ball = solids::sphere(radius, segments, rings, {0, 0, radius});
  std::vector<double> ring_z;
  std::vector<double> ring_rho;
  for (int k = 0; k <= rings; ++k) {
    const double polar = std::numbers::pi * k / rings;
    ring_z.push_back(radius - radius * std::cos(polar));  // from the bottom pole up
    ring_rho.push_back(radius * std::sin(polar));
  }
  auto rho = [&](double z) {
    if (z <= 0 || z >= 2 * radius) return 0.0;
    const auto hi = std::upper_bound(ring_z.begin(), ring_z.end(), z) - ring_z.begin();
    const auto lo = hi - 1;
    const double f = (z - ring_z[lo]) / (ring_z[hi] - ring_z[lo]);
    return ring_rho[lo] + f * (ring_rho[hi] - ring_rho[lo]);
  };
  auto distance = [&](double a, double b) { return mid_distance(rho, ring_z, segments, a, b); };
  const double tolerance = 0.1;
  const AdaptivePlan plan = plan_for(ball.mesh, tolerance);
  check_thicknesses(plan.layers, kUpPlus2);
  double equator_sum = 0, pole_sum = 0;
  int equator = 0, pole = 0;
  for (std::size_t i = 1; i < plan.layers.size(); ++i) {
    const Layer& l = plan.layers[i];
    const double d = distance(l.z_lo, l.z_hi);
    if (plan.met[i]) {
      CHECK_MESSAGE(d <= tolerance + 1e-3, "layer " << i << " at " << l.z_lo);
    } else {
      // Unmet only where even the thinnest layer cannot meet it.
      CHECK(l.thickness() == doctest::Approx(0.15));
      CHECK_MESSAGE(distance(l.z_lo, l.z_lo + 0.15) > tolerance - 1e-3, "layer " << i);
    }
    const double z = l.z_mid();
    if (std::abs(z - radius) < 3) equator_sum += l.thickness(), ++equator;
    if (std::abs(z - radius) > 8.5) pole_sum += l.thickness(), ++pole;
  }
  REQUIRE(equator > 0);
  REQUIRE(pole > 0);
  CHECK(equator_sum / equator > 0.35);  // nearly vertical: nearly the thickest
  CHECK(pole_sum / pole < 0.2);         // nearly flat: nearly the thinnest
  CHECK(plan.layers.size() <= greedy_layers(distance, 2 * radius, tolerance, kUpPlus2));
  CHECK(plan.unmet > 0);  // the poles: a 0.15 mm layer there is far more than 0.1 mm off
}

TEST_CASE("adaptive_plan_reports_a_tolerance_no_thickness_meets") {
  // A cone 20 mm wide and 4 mm tall spreads 5 mm per mm of height: a 0.15 mm layer is
  // 0.375 mm off, far above 0.2.
  const solids::Solid cone = solids::cone(20, 4, 64);
  const AdaptivePlan plan = plan_for(cone.mesh, 0.2);
  check_thicknesses(plan.layers, kUpPlus2);
  CHECK(plan.unmet >= plan.layers.size() - 2);
  for (std::size_t i = 1; i < plan.layers.size(); ++i) {
    if (!plan.met[i]) CHECK(plan.layers[i].thickness() == doctest::Approx(0.15));
    CHECK(static_cast<bool>(plan.met[i]) == (plan.distance[i] <= 0.2));
  }
}

TEST_CASE("adaptive_plan_with_a_layer_budget_finds_the_least_tolerance") {
  const solids::Solid cone = solids::cone(10, 20, 64);
  const geometry::LayerStack stack(cone.mesh, {});
  AdaptiveOptions options;
  options.max_layers = 60;
  const auto flats = geometry::flat_levels(cone.mesh);
  const AdaptivePlan plan = geometry::adaptive_plan(stack, 20, kUpPlus2, flats, options);
  CHECK(plan.layers.size() <= 60);
  // D = t / 4 (see above): 19.7 mm in at most 59 layers needs 0.35 mm ones, D 0.0875.
  CHECK(plan.tolerance == doctest::Approx(0.0875).epsilon(0.02));
  options.max_layers = 0;
  options.tolerance = plan.tolerance - 0.005;
  CHECK(geometry::adaptive_plan(stack, 20, kUpPlus2, flats, options).layers.size() > 60);
}

TEST_CASE("adaptive_plan_spends_a_layer_budget_where_more_layers_take_off_nothing") {
  // A box of vertical walls, 10 mm: D = 0 and no volume left off at any thickness, so the least
  // error needs only the fewest layers (0.3 + 25 above it, as above). A budget is still spent
  // to the last layer, every layer one the printer allows and the top landed, up to the most
  // layers there are: 9.7 mm is at most 64 layers of 0.15 mm and more (62 x 0.15 + 2 x 0.2).
  const solids::Solid prism = solids::box({-5, -5, 0}, {5, 5, 10});
  const geometry::LayerStack stack(prism.mesh, {});
  const auto flats = geometry::flat_levels(prism.mesh);
  for (std::size_t budget : {26, 40, 60, 65, 500}) {
    CAPTURE(budget);
    AdaptiveOptions options;
    options.max_layers = budget;
    const AdaptivePlan plan = geometry::adaptive_plan(stack, 10, kUpPlus2, flats, options);
    check_thicknesses(plan.layers, kUpPlus2);
    CHECK(plan.layers.size() == std::min<std::size_t>(budget, 65));
    CHECK(plan.layers.back().z_hi == 10.0);
    for (std::size_t i = 1; i < plan.layers.size(); ++i) CHECK(plan.distance[i] <= 1e-9);
  }
}

TEST_CASE("a_layer_budget_is_not_spent_on_a_last_layer_that_prints_nothing") {
  // The box above, 10 mm, with nothing printed by a layer starting at or above 9.8 mm (a tip
  // no bead fits in, as the toolpaths would find). Every plan of the most layers reaching the
  // top, 65 (62 x 0.15 + 2 x 0.2 above the first), ends in a layer starting at 9.8 or 9.85,
  // which prints nothing. Not counted against the budget, nor kept, such a layer leaves the
  // budget to layers that print: 65 of them still, 63 x 0.15 to 9.75 and a 0.25 mm layer to
  // the top; fewer if the budget is smaller, every one printing.
  const solids::Solid prism = solids::box({-5, -5, 0}, {5, 5, 10});
  const geometry::LayerStack stack(prism.mesh, {});
  const auto flats = geometry::flat_levels(prism.mesh);
  const auto prints = [](const Layer& layer) { return layer.z_lo < 9.8 - 1e-9; };
  for (std::size_t budget : {40, 64, 500}) {
    CAPTURE(budget);
    AdaptiveOptions options;
    options.max_layers = budget;
    options.prints = prints;
    const AdaptivePlan plan = geometry::adaptive_plan(stack, 10, kUpPlus2, flats, options);
    check_thicknesses(plan.layers, kUpPlus2);
    CHECK(plan.layers.size() == std::min<std::size_t>(budget, 65));
    CHECK(plan.distance.size() == plan.layers.size());
    for (const Layer& layer : plan.layers) CHECK(prints(layer));
    // It ends at the top, or where a layer to the top would print nothing.
    const double top = plan.layers.back().z_hi;
    CHECK(top <= 10.0 + 1e-9);
    CHECK((top == doctest::Approx(10.0) || top >= 9.8 - 1e-9));
  }
}

TEST_CASE("adaptive_plan_of_the_bunny_spends_a_budget_of_331_layers" * test_support::release_build_only()) {
  // 50 mm tall on the UP Plus 2: 49.7 mm above the first layer holds at most 331 layers of
  // 0.15 mm and more, and 331 sweep less volume than 330. Plans of 330 and 331 layers put
  // thinnest layers over the cap at different heights, whose thicknesses (0.45 - 0.3, 31.4 -
  // 31.25) add up to the same height but for their last bits; those bits must not decide
  // before the volume does.
  const geometry::Mesh bunny = test_support::paper_bunny();
  const double top = geometry::bounding_box(bunny).max.z;
  const geometry::LayerStack stack(bunny, {});
  AdaptiveOptions options;
  options.max_layers = 331;
  const AdaptivePlan plan = geometry::adaptive_plan(stack, top, kUpPlus2, geometry::flat_levels(bunny), options);
  check_thicknesses(plan.layers, kUpPlus2);
  CHECK(plan.layers.size() == 331);
  CHECK(plan.layers.back().z_hi == doctest::Approx(top).epsilon(1e-9));
}

TEST_CASE("adaptive_plan_with_any_budget_finds_the_least_tolerance_it_accepts") {
  // The cone above under a budget that only a plan's layers can judge (here their count, as a
  // print-time estimate would be): the same least tolerance, D = t / 4 at 0.35 mm layers.
  const solids::Solid cone = solids::cone(10, 20, 64);
  const geometry::LayerStack stack(cone.mesh, {});
  AdaptiveOptions options;
  std::size_t asked = 0;
  options.overrun = [&](const std::vector<geometry::Layer>& layers) {
    ++asked;
    check_thicknesses(layers, kUpPlus2);
    return static_cast<double>(layers.size()) - 60;
  };
  const auto flats = geometry::flat_levels(cone.mesh);
  const AdaptivePlan plan = geometry::adaptive_plan(stack, 20, kUpPlus2, flats, options);
  CHECK(plan.layers.size() <= 60);
  CHECK(plan.tolerance == doctest::Approx(0.0875).epsilon(0.03));
  CHECK(asked <= 12);  // a log-scale bisection to 2%, not a scan
  // Each candidate slab counts once, however many of the bisection's searches measured it.
  CHECK(plan.measured > 0);
  CHECK(plan.measured <= plan.candidates);
  // A budget no plan meets gets the thickest plan (every layer within its tolerance).
  options.overrun = [](const std::vector<geometry::Layer>&) { return 1.0; };
  const AdaptivePlan thickest = geometry::adaptive_plan(stack, 20, kUpPlus2, flats, options);
  CHECK(thickest.unmet == 0);
  CHECK(thickest.layers.size() <= 1 + 50 + 1);  // 19.7 mm of 0.4 mm layers
}

TEST_CASE("adaptive_plan_within_a_budget_of_layers_by_their_plan_is_the_plan_of_that_many") {
  // A budget judged by the plan (a print time, say) that only a count decides gets the plan
  // --max-layers makes of that count: the cone's tolerance plans come in steps of 0.05 mm
  // layers over its uniform slope (58, 67, 80 layers), and a budget between two steps is
  // spent in full, not left at the step below.
  const solids::Solid cone = solids::cone(10, 20, 64);
  const geometry::LayerStack stack(cone.mesh, {});
  const auto flats = geometry::flat_levels(cone.mesh);
  for (std::size_t count : {60, 63, 70, 75}) {
    CAPTURE(count);
    AdaptiveOptions by_count;
    by_count.max_layers = count;
    const AdaptivePlan counted = geometry::adaptive_plan(stack, 20, kUpPlus2, flats, by_count);
    AdaptiveOptions by_plan;
    by_plan.overrun = [&](const std::vector<Layer>& layers) {
      return static_cast<double>(layers.size()) - static_cast<double>(count);
    };
    const AdaptivePlan judged = geometry::adaptive_plan(stack, 20, kUpPlus2, flats, by_plan);
    CHECK(judged.layers.size() == count);
    REQUIRE(judged.layers.size() == counted.layers.size());
    for (std::size_t i = 0; i < counted.layers.size(); ++i) {
      CHECK(judged.layers[i].z_lo == counted.layers[i].z_lo);
      CHECK(judged.layers[i].z_hi == counted.layers[i].z_hi);
    }
    CHECK(judged.cap == counted.cap);
  }
}

TEST_CASE("adaptive_plan_within_any_print_time_is_the_least_total_error_that_fits") {
  // A ball of radius 8 under a print-time-like budget: a layer takes 1 s plus 0.05 s per mm^2
  // of its section at mid height (pi (64 - (z - 8)^2)), so thin layers cost more where the
  // ball is wide, and a least-swept plan (its thin layers where the volume is) takes longer
  // than the least tolerance's plan of as many layers. For every budget between the thickest
  // and the thinnest plans' times the result fits and is a least total error (found within
  // the cap: cap > 0), whatever the budget.
  const solids::Solid ball = solids::sphere(8, 48, 24, {0, 0, 8});
  const geometry::LayerStack stack(ball.mesh, {});
  const auto flats = geometry::flat_levels(ball.mesh);
  const auto seconds = [](const std::vector<Layer>& layers) {
    double total = 0;
    for (const Layer& l : layers) {
      const double r = 0.5 * (l.z_lo + l.z_hi) - 8;
      total += 1 + 0.05 * std::numbers::pi * std::max(0.0, 64 - r * r);
    }
    return total;
  };
  AdaptiveOptions thinnest;
  thinnest.tolerance = 0;
  AdaptiveOptions thickest;
  thickest.tolerance = 10;
  const double most = seconds(geometry::adaptive_plan(stack, 16, kUpPlus2, flats, thinnest).layers);
  const double least = seconds(geometry::adaptive_plan(stack, 16, kUpPlus2, flats, thickest).layers);
  REQUIRE(least < most);
  for (int k = 1; k < 12; ++k) {
    const double budget = least + (most - least) * k / 12.0;
    CAPTURE(budget);
    AdaptiveOptions options;
    options.overrun = [&](const std::vector<Layer>& layers) { return seconds(layers) - budget; };
    const AdaptivePlan plan = geometry::adaptive_plan(stack, 16, kUpPlus2, flats, options);
    check_thicknesses(plan.layers, kUpPlus2);
    CHECK(seconds(plan.layers) <= budget);
    CHECK(plan.cap > 0);
  }
}

TEST_CASE("adaptive_plan_distance_is_what_analyze_measures") {
  const solids::Solid ball = solids::sphere(8, 48, 24, {0, 0, 8});
  const AdaptivePlan plan = plan_for(ball.mesh, 0.15, kUpPlus2,
                                   {&geometry::contour_strategy("mid"), &geometry::contour_strategy("ma")});
  const geometry::LayerStack stack(ball.mesh, plan.layers);
  const geometry::ContourStrategy* strategies[] = {&geometry::contour_strategy("mid"),
                                                   &geometry::contour_strategy("ma")};
  const auto analysis = geometry::analyze_layers(stack, strategies);
  REQUIRE(analysis.size() == plan.layers.size());
  for (std::size_t i = 0; i < analysis.size(); ++i) {
    // The first contour within the tolerance (mid), else the lesser of the two.
    const double mid = analysis[i].strategies[0].metrics.distance;
    const double best = mid <= 0.15 ? mid : std::min(mid, analysis[i].strategies[1].metrics.distance);
    // The same measure, to its tolerance (1 um: the search may stop anywhere within it).
    CHECK(std::abs(plan.distance[i] - best) <= 1e-3);
  }
}

TEST_CASE("adaptive_plan_asking_only_whether_slabs_are_within_is_the_plan_of_all_measured") {
  // The search settles a slab once it is seen within the tolerance (layer_plan.cpp); with
  // every candidate measured exactly first instead, the plan is as good (as many layers, as
  // many unmet; of paths that good it may take another), and its layers' D are exact too.
  const solids::Solid ball = solids::sphere(8, 48, 24, {0, 0, 8});
  const solids::Solid ring = solids::torus(12, 5, 48, 24, {0, 0, 5});
  for (const geometry::Mesh* mesh : {&ball.mesh, &ring.mesh}) {
    const geometry::LayerStack stack(*mesh, {});
    AdaptiveOptions options;
    options.tolerance = 0.2;
    const double top = geometry::bounding_box(*mesh).max.z;
    const AdaptivePlan lazy = geometry::adaptive_plan(stack, top, kUpPlus2, geometry::flat_levels(*mesh), options);
    options.measure_all = true;
    const AdaptivePlan all = geometry::adaptive_plan(stack, top, kUpPlus2, geometry::flat_levels(*mesh), options);
    CHECK(lazy.layers.size() == all.layers.size());
    CHECK(lazy.unmet == all.unmet);
    CHECK(lazy.measured < all.measured);
    const geometry::LayerStack printed(*mesh, lazy.layers);
    for (std::size_t i = 0; i < lazy.layers.size(); ++i) {
      CAPTURE(i);
      const geometry::LayerMetrics m = geometry::layer_metrics(printed, i, printed.mid(i));
      CHECK(std::abs(lazy.distance[i] - m.distance) <= 1e-3);
    }
  }
}

TEST_CASE("the_lazy_search_keeping_its_costs_from_round_to_round_plans_as_one_that_starts_afresh") {
  // A round of the lazy search works out again only the nodes above the lowest slab measured
  // since the round before, and of those only up to where the candidates from below the
  // highest measured one reach, the rest taken from the best ways on through the grid as it
  // was before any was measured (layer_plan.cpp: shortest_path); each candidate's cost in a
  // path is kept and worked out again only where it is measured (EdgeStep). A search over
  // the whole grid from the bed in every round instead must give the same plan, layer for
  // layer, and measure the same slabs, with a tolerance and with a budget, on a printer of
  // fine steps (many rounds) and on the UP Plus 2, on smooth parts and on one with a ledge
  // between the steps' heights (4.013 mm: candidates measured exactly from the start, high
  // above the first measured).
  const AllowedThicknesses fine{.listed = {}, .min = 0.05, .max = 0.3, .step = 0.01, .first = 0.2};
  const solids::Solid ball = solids::sphere(8, 48, 24, {0, 0, 8});
  const solids::Solid ring = solids::torus(12, 5, 48, 24, {0, 0, 5});
  const solids::Solid ledged = solids::revolve({{0, 0}, {9, 0}, {6, 4.013}, {4, 4.013}, {2.5, 9}, {0, 9}}, 48);
  for (const geometry::Mesh* mesh : {&ball.mesh, &ring.mesh, &ledged.mesh}) {
    const geometry::LayerStack stack(*mesh, {});
    const double top = geometry::bounding_box(*mesh).max.z;
    for (const AllowedThicknesses* allowed : {&fine, &kUpPlus2}) {
      for (const std::size_t budget : {std::size_t{0}, std::size_t{60}}) {
        CAPTURE(allowed->step);
        CAPTURE(budget);
        AdaptiveOptions options;
        options.tolerance = 0.1;
        options.max_layers = budget;
        const AdaptivePlan kept = geometry::adaptive_plan(stack, top, *allowed, geometry::flat_levels(*mesh), options);
        options.search_afresh = true;
        const AdaptivePlan afresh = geometry::adaptive_plan(stack, top, *allowed, geometry::flat_levels(*mesh), options);
        CHECK(kept.rounds > 10);
        CHECK(kept.rounds == afresh.rounds);
        CHECK(kept.measured == afresh.measured);
        REQUIRE(kept.layers.size() == afresh.layers.size());
        for (std::size_t i = 0; i < kept.layers.size(); ++i) {
          CHECK(kept.layers[i].z_lo == afresh.layers[i].z_lo);
          CHECK(kept.layers[i].z_hi == afresh.layers[i].z_hi);
          CHECK(kept.distance[i] == afresh.distance[i]);
        }
      }
    }
  }
}

TEST_CASE("plans_on_a_printer_of_any_thickness_in_a_range_land_flat_levels_exactly") {
  // generic-marlin: 0.05 to 0.3 mm, any value, first layer 0.2 mm; steps at 4.013 and 7.5.
  const AllowedThicknesses range{.listed = {}, .min = 0.05, .max = 0.3, .step = 0, .first = 0.2};
  const solids::Solid block = solids::stepped_box({20, 20}, 4.013, {10, 10}, 3.487);
  const auto flats = geometry::flat_levels(block.mesh);
  const auto uniform = geometry::uniform_plan(7.5, 0.2, range, flats);
  const AdaptivePlan adaptive = plan_for(block.mesh, 0.05, range);
  for (const auto* layers : {&uniform.layers, &adaptive.layers}) {
    REQUIRE(!layers->empty());
    CHECK(layers->front().z_hi == doctest::Approx(0.2));
    for (std::size_t i = 1; i < layers->size(); ++i) {
      CHECK((*layers)[i].thickness() >= 0.05 - 1e-9);
      CHECK((*layers)[i].thickness() <= 0.3 + 1e-9);
    }
    CHECK(has_boundary(*layers, 4.013));
    CHECK(layers->back().z_hi == 7.5);
  }
  CHECK(adaptive.unmet == 0);
  // Vertical walls: the thickest layers but where the steps need a shorter one.
  CHECK(adaptive.layers.size() <= 1 + 13 + 12 + 2);
}

TEST_CASE("plans_with_a_listed_set_of_thicknesses_use_only_those") {
  const AllowedThicknesses listed{.listed = {0.1, 0.2, 0.3}, .first = 0.2};
  const solids::Solid block = solids::stepped_box({20, 20}, 4, {10, 10}, 3.5);
  const auto flats = geometry::flat_levels(block.mesh);
  for (const auto& layers : {geometry::uniform_plan(7.5, 0.2, listed, flats).layers,
                             plan_for(block.mesh, 0.05, listed).layers}) {
    for (std::size_t i = 1; i < layers.size(); ++i) CHECK(listed.allows(layers[i].thickness()));
    CHECK(has_boundary(layers, 4.0));
    CHECK(layers.back().z_hi == 7.5);
  }
}

}  // namespace layer_plan_test
