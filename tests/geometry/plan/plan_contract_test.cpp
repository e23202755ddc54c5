// The tolerance as a contract (layer_plan.h), against closed forms on solids of revolution
// whose radius is linear in z between rings (solids.h): between two ring heights a section is
// a regular n-gon of circumradius rho(z), so a surface point at height z is rho(z) - rho(m)
// from the mid section's wall at the corners where rho(z) > rho(m), and
// (rho(m) - rho(z)) cos(pi / n) across its edges where rho(z) < rho(m).
//   - a tighter tolerance never gives a larger max D or total ΔV (cones between flat levels);
//   - every flat level and the top land on boundaries, where the thinnest layers alone would
//     miss them, and the last layer ends at most the printer's step above a pointed top;
//   - every layer above the first is within the tolerance, or the thinnest, or lands a level;
//   - the top layer of a flat-topped sphere cap is within the tolerance;
//   - the layer holding a flat level no allowed layer lands has the least D any plan gives it;
//   - a budget leaves over its cap only what its by-height 95th percentile leaves out, at the
//     least percentile a plan reaches, where that prints no larger D;
//   - a print-time budget takes the layer budget's plan of the count it fits.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <vector>

#include "geometry/analysis/layer_analysis.h"
#include "geometry/plan/flat_levels.h"
#include "geometry/plan/layer_plan.h"
#include "geometry/plan/swept_volume.h"
#include "geometry/slicing/layer_stack.h"
#include "support/solids.h"

namespace plan_contract_test {

using geometry::AdaptiveOptions;
using geometry::AdaptivePlan;
using geometry::AllowedThicknesses;
using geometry::Layer;
using geometry::OverTolerance;
using geometry::Vec2;

namespace {

// The UP Plus 2: 0.15 to 0.4 mm in steps of 0.05, a first layer of 0.3.
const AllowedThicknesses kUpPlus2{.listed = {}, .min = 0.15, .max = 0.4, .step = 0.05, .first = 0.3};
constexpr int kSides = 48;

// Three cones between flat levels, each slope of its own: vertical to 2 mm, then leaning in
// 3 mm over 3.1 mm to a flat ring at 5.1 mm, 1 mm over 4.25 mm to a ring at 9.35, 3.5 mm over
// 1.7 mm to a flat top at 11.05 (every level on the UP Plus 2's grid: 0.3 + k 0.05).
const std::vector<Vec2> kStack{{0, 0},    {12, 0},    {12, 2},   {9, 5.1}, {7, 5.1},
                               {6, 9.35}, {4, 9.35}, {0.5, 11.05}, {0, 11.05}};
const std::vector<double> kStackFlats{5.1, 9.35, 11.05};

AdaptivePlan plan_for(const geometry::Mesh& mesh, double tolerance) {
  const geometry::LayerStack stack(mesh, {});
  AdaptiveOptions options;
  options.tolerance = tolerance;
  return geometry::adaptive_plan(stack, geometry::bounding_box(mesh).max.z, kUpPlus2,
                                 geometry::flat_levels(mesh), options);
}

bool has_boundary(const std::vector<Layer>& layers, double z) {
  return std::any_of(layers.begin(), layers.end(),
                     [&](const Layer& l) { return std::abs(l.z_hi - z) < 1e-9; });
}

// The outer radius of a revolve profile that narrows upwards (x = rho, y = z, from the
// bottom's outer corner to the top's), at height z; `above`: the limit from above at a flat.
double profile_radius(const std::vector<Vec2>& outer, double z, bool above) {
  double r = 0;
  for (std::size_t k = 1; k < outer.size(); ++k) {
    const Vec2 a = outer[k - 1], b = outer[k];
    if (a.y == b.y) continue;  // a flat ring: the slopes on either side say which radius
    if (above ? (z >= a.y && z < b.y) : (z > a.y && z <= b.y)) {
      r = a.x + (b.x - a.x) * (z - a.y) / (b.y - a.y);
    }
  }
  return r;
}

// mid's D on [a, b] for a narrowing revolve of n sides (see the file comment): the largest of
// the surface's distances at the slab's ends and at the profile's corners inside it, a flat
// ring inside counted by both its edges.
double mid_distance(const std::vector<Vec2>& outer, double a, double b) {
  const double m = 0.5 * (a + b), r_mid = profile_radius(outer, m, true);
  std::vector<double> radii{profile_radius(outer, a, true), profile_radius(outer, b, false)};
  for (const Vec2& corner : outer) {
    if (corner.y > a && corner.y < b) {
      radii.push_back(profile_radius(outer, corner.y, false));
      radii.push_back(profile_radius(outer, corner.y, true));
    }
  }
  double d = 0;
  for (double r : radii) {
    d = std::max(d, r > r_mid ? r - r_mid : (r_mid - r) * std::cos(std::numbers::pi / kSides));
  }
  return d;
}

}  // namespace

TEST_CASE("a_tighter_tolerance_never_raises_max_d_or_volume_deviation_on_cones_between_flat_levels") {
  const solids::Solid stack = solids::revolve(kStack, kSides);
  const std::vector<Vec2> outer(kStack.begin() + 1, kStack.end() - 1);
  double looser_max = INFINITY, looser_volume = INFINITY;
  std::size_t looser_layers = 0;
  for (double tolerance : {0.3, 0.2, 0.12, 0.08, 0.05, 0.03, 0.02}) {
    CAPTURE(tolerance);
    const AdaptivePlan plan = plan_for(stack.mesh, tolerance);
    REQUIRE(plan.layers.size() > 1);
    for (double z : kStackFlats) CHECK_MESSAGE(has_boundary(plan.layers, z), "flat at " << z);
    double max_d = 0;
    for (std::size_t i = 1; i < plan.layers.size(); ++i) {
      const Layer& l = plan.layers[i];
      const double closed = mid_distance(outer, l.z_lo, l.z_hi);
      CHECK_MESSAGE(std::abs(plan.distance[i] - closed) <= 2e-3, "layer " << i << " at " << l.z_lo);
      max_d = std::max(max_d, closed);
    }
    // The volume deviation of the mid contour the plan is made for, as analyze measures it.
    const geometry::LayerStack printed(stack.mesh, plan.layers);
    const geometry::ContourStrategy* mid[] = {&geometry::contour_strategy("mid")};
    double volume = 0;
    for (const auto& layer : geometry::analyze_layers(printed, mid)) {
      volume += layer.strategies[0].metrics.volume_deviation;
    }
    CHECK(max_d <= looser_max + 1e-9);
    CHECK(volume <= looser_volume + 1e-9);
    CHECK(plan.layers.size() >= looser_layers);
    looser_max = max_d, looser_volume = volume, looser_layers = plan.layers.size();
  }
}

TEST_CASE("every_layer_above_the_first_is_within_the_tolerance_or_the_thinnest_or_lands_a_level") {
  // At 0.02 mm no layer thicker than 0.15 mm meets it on the cones (D = t s / 2, s the run
  // per mm of height: 0.97, 0.24 and 2.1; the first and last not even 0.15 mm ones): 3.1, 4.25
  // and 1.7 mm are no multiples of 0.15, so a thicker layer must land each of 5.1, 9.35, 11.05.
  const solids::Solid stack = solids::revolve(kStack, kSides);
  const AdaptivePlan plan = plan_for(stack.mesh, 0.02);
  for (double z : kStackFlats) CHECK(has_boundary(plan.layers, z));
  CHECK(plan.layers.back().z_hi == 11.05);
  std::size_t over = 0;
  std::vector<std::size_t> landing(kStackFlats.size(), 0);  // per flat level: layers landing it
  for (std::size_t i = 1; i < plan.layers.size(); ++i) {
    CAPTURE(i);
    const double t = plan.layers[i].thickness();
    if (plan.distance[i] <= 0.02) {
      CHECK(plan.why[i] == OverTolerance::none);
      continue;
    }
    ++over;
    if (t > 0.15 + 1e-9) {
      CHECK(plan.why[i] == OverTolerance::landing);
      const auto next = std::lower_bound(kStackFlats.begin(), kStackFlats.end(), plan.layers[i].z_hi - 1e-9);
      REQUIRE(next != kStackFlats.end());
      ++landing[static_cast<std::size_t>(next - kStackFlats.begin())];
    } else {
      CHECK(plan.why[i] == OverTolerance::shallow_surface);
    }
  }
  CHECK(over == plan.unmet);
  // One thicker layer below each level the 0.15 mm layers miss, none below the others.
  for (std::size_t k = 0; k < kStackFlats.size(); ++k) CHECK(landing[k] <= 1);
  CHECK(landing[0] + landing[1] + landing[2] >= 1);
}

TEST_CASE("the_layer_holding_a_ledge_off_the_reachable_heights_errs_least") {
  // A cone narrowing 1 mm per mm from radius 8 at the bed to 2.98 at a ledge at 5.02 mm (on no
  // height the UP Plus 2 reaches: 0.3 + k 0.05), under a cylinder of radius 9 overhanging it to
  // a flat top at 8 mm. Some layer [a, b], a <= 5.00 and b >= 5.05, holds the ledge, thinnest
  // (0.15 mm: no more height over the tolerance than needed). Cut by mid below the ledge, at
  // m, the cylinder's corners stand 9 - (8 - m) = 1 + m off the walls: [4.90, 5.05], D 5.975.
  // Cut above it ([4.95, 5.10] or [5.00, 5.15]), the cone's top ring is (9 - 2.98) cos(pi /
  // 48) = 6.007 inside the cylinder's walls. The cone's slope costs a thinnest layer 0.075, so
  // nothing else comes near: the plan's largest D above the first layer is the ledge's least,
  // at every tolerance and under a layer budget.
  const std::vector<Vec2> profile{{0, 0}, {8, 0}, {2.98, 5.02}, {9, 5.02}, {9, 8}, {0, 8}};
  const solids::Solid part = solids::revolve(profile, kSides);
  const std::vector<Vec2> outer(profile.begin() + 1, profile.end() - 1);
  REQUIRE(mid_distance(outer, 4.9, 5.05) == doctest::Approx(5.975).epsilon(1e-12));
  const double above = 6.02 * std::cos(std::numbers::pi / kSides);
  REQUIRE(mid_distance(outer, 4.95, 5.1) == doctest::Approx(above).epsilon(1e-12));
  REQUIRE(mid_distance(outer, 5.0, 5.15) == doctest::Approx(above).epsilon(1e-12));
  const geometry::LayerStack stack(part.mesh, {});
  const auto check = [&](const AdaptivePlan& plan) {
    REQUIRE(plan.layers.size() > 1);
    CHECK(plan.layers.back().z_hi == 8.0);
    double most = 0;
    std::size_t holding = 0;
    for (std::size_t i = 1; i < plan.layers.size(); ++i) {
      most = std::max(most, plan.distance[i]);
      if (plan.layers[i].z_lo < 5.02 && plan.layers[i].z_hi > 5.02) holding = i;
    }
    CHECK(most == doctest::Approx(5.975).epsilon(2e-3 / 5.975));
    REQUIRE(holding > 0);
    CHECK(plan.layers[holding].z_lo == doctest::Approx(4.9));
    CHECK(plan.layers[holding].z_hi == doctest::Approx(5.05));
    // Said over the tolerance for the level; under a budget, within the cap it makes.
    if (plan.cap == 0) CHECK(plan.why[holding] == OverTolerance::flat_level);
  };
  for (double tolerance : {0.08, 0.1, 0.3}) {
    CAPTURE(tolerance);
    check(plan_for(part.mesh, tolerance));
  }
  for (std::size_t budget : {30, 45, 60}) {
    CAPTURE(budget);
    AdaptiveOptions options;
    options.max_layers = budget;
    const AdaptivePlan plan = geometry::adaptive_plan(stack, 8.0, kUpPlus2, geometry::flat_levels(part.mesh), options);
    CHECK(plan.layers.size() <= budget);
    check(plan);
  }
}

TEST_CASE("a_budget_caps_its_layers_at_the_95th_percentile_of_those_a_thinner_layer_could_help") {
  // Vertical walls (D = 0 at any thickness) with two slopes that lean in between them: 12 mm
  // over 0.6 mm at 5 mm (run per mm of height s = 20) and 2.4 mm over 0.6 mm at 10 mm (s = 4).
  // Every corner is on the UP Plus 2's grid, so at any tolerance under 0.3 mm the least
  // tolerance's plan lands them: its layers on the slopes are the thinnest, 0.15 mm, of D
  // = 0.15 s / 2 at their lower corners, 1.5 and 0.3 mm; every other layer has D = 0.
  // 60 layers hold that plan at any tolerance (1 + 12 + 4 + 11 + 4 + 25 = 57 of 0.4 mm and
  // less), so the least tolerance is all but 0. Of the 20 mm above the first layer, the layers
  // of D 1.5 are 0.6 mm: the thinnest over the percentile, over it in every plan, they are
  // left out of it; of the other 19.4 mm, 0.6 (3.1%) have D 0.3 and the rest 0, so the cap is
  // the least tolerance (the whole plan's percentile, both slopes counted, would be 0.3: 1.2 mm
  // is 6% of 20).
  const std::vector<Vec2> profile{{0, 0},   {25, 0},      {25, 5},     {13, 5.6},
                                  {13, 10}, {10.6, 10.6}, {10.6, 20.3}, {0, 20.3}};
  const std::vector<Vec2> outer(profile.begin() + 1, profile.end() - 1);
  const solids::Solid part = solids::revolve(profile, kSides);
  const geometry::LayerStack stack(part.mesh, {});
  AdaptiveOptions options;
  options.max_layers = 60;
  const AdaptivePlan plan =
      geometry::adaptive_plan(stack, 20.3, kUpPlus2, geometry::flat_levels(part.mesh), options);
  REQUIRE(plan.layers.size() <= 60);
  CHECK(plan.tolerance < 0.01);
  CHECK(plan.cap == plan.tolerance);
  CHECK(plan.ceiling == doctest::Approx(1.5).epsilon(2e-3 / 1.5));
  for (double z : {5.0, 5.6, 10.0, 10.6, 20.3}) CHECK_MESSAGE(has_boundary(plan.layers, z), "corner at " << z);
  for (std::size_t i = 1; i < plan.layers.size(); ++i) {
    const Layer& l = plan.layers[i];
    CAPTURE(l.z_lo);
    CHECK(plan.distance[i] == doctest::Approx(mid_distance(outer, l.z_lo, l.z_hi)).epsilon(1e-3).scale(1));
    const bool sloped = (l.z_lo >= 5.0 - 1e-9 && l.z_hi <= 5.6 + 1e-9) || (l.z_lo >= 10.0 - 1e-9 && l.z_hi <= 10.6 + 1e-9);
    CHECK(sloped == (plan.distance[i] > plan.cap));
  }
}

namespace {

// Vertical walls (D = 0 at any thickness) with two slopes leaning in between them: r 4 to 3
// over [1.05, 1.13] mm and r 3 to 0.5 over [3.00, 3.15], then vertical to `top`.
std::vector<Vec2> two_slopes(double top) {
  return {{0, 0}, {4, 0}, {4, 1.05}, {3, 1.13}, {3, 3.0}, {0.5, 3.15}, {0.5, top}, {0, top}};
}

// The plan of `part`, `top` mm tall, in at most `budget` layers: a layer budget's
// (max_layers), or with `by_time` a print-time budget's whose `fits` takes a plan of at most
// `budget` layers (its bisection on the count then takes `budget`).
AdaptivePlan plan_in_budget(const solids::Solid& part, double top, std::size_t budget, bool by_time = false) {
  const geometry::LayerStack stack(part.mesh, {});
  AdaptiveOptions options;
  if (by_time) {
    options.overrun = [budget](const std::vector<Layer>& layers) { return static_cast<double>(layers.size()) - static_cast<double>(budget); };
  } else {
    options.max_layers = budget;
  }
  return geometry::adaptive_plan(stack, top, kUpPlus2, geometry::flat_levels(part.mesh), options);
}

}  // namespace

TEST_CASE("of_the_layers_a_budget_leaves_over_its_cap_the_plan_takes_those_least_far_over") {
  // Two slopes (two_slopes) to a top at 6.3 mm. One 0.15 mm layer holds each slope (two
  // would put more height over the cap): [3.00, 3.15] for the second, D = 3 - 1.75 = 1.25;
  // [1.00, 1.15] or [1.05, 1.20] for the first, cut at r 3.6875 and 3.0625, so D = 0.6875
  // cos(pi / 48) (the wall of r 3 above) and 0.9375 (the wall of r 4 below). Of the 6.3 mm,
  // 0.3 (4.8%) are the slopes' and the rest D = 0: the cap is the least tolerance, all but 0,
  // the ceiling 1.25, and no plan has a lower by-height 95th percentile (0), so both slopes'
  // layers are over the cap, as high each way. The layer of D 0.9375 sweeps less volume; the
  // one of D 0.686 is taken, the least far over the cap, in every budget under the most layers
  // 6 mm above the first holds (40), all spent.
  const std::vector<Vec2> profile = two_slopes(6.3);
  const std::vector<Vec2> outer(profile.begin() + 1, profile.end() - 1);
  const double near = 0.6875 * std::cos(std::numbers::pi / kSides);
  REQUIRE(mid_distance(outer, 1.0, 1.15) == doctest::Approx(near).epsilon(1e-12));
  REQUIRE(mid_distance(outer, 1.05, 1.2) == doctest::Approx(0.9375).epsilon(1e-12));
  REQUIRE(mid_distance(outer, 3.0, 3.15) == doctest::Approx(1.25).epsilon(1e-12));
  const solids::Solid part = solids::revolve(profile, kSides);
  const geometry::SweptVolume swept(part.mesh);
  REQUIRE(swept(1.05, 1.2) < swept(1.0, 1.15));
  for (std::size_t budget : {24, 28, 32}) {
    CAPTURE(budget);
    const AdaptivePlan plan = plan_in_budget(part, 6.3, budget);
    REQUIRE(plan.layers.size() == budget);
    CHECK(plan.tolerance < 0.01);
    CHECK(plan.cap == plan.tolerance);
    CHECK(plan.ceiling == doctest::Approx(1.25).epsilon(2e-3 / 1.25));
    std::vector<std::size_t> over;
    for (std::size_t i = 1; i < plan.layers.size(); ++i) {
      if (plan.distance[i] > plan.cap) over.push_back(i);
    }
    REQUIRE(over.size() == 2);
    CHECK(plan.layers[over[0]].z_lo == doctest::Approx(1.0));
    CHECK(plan.layers[over[0]].z_hi == doctest::Approx(1.15));
    CHECK(plan.distance[over[0]] == doctest::Approx(near).epsilon(2e-3 / near));
    CHECK(plan.layers[over[1]].z_lo == doctest::Approx(3.0));
    CHECK(plan.layers[over[1]].z_hi == doctest::Approx(3.15));
  }
}

TEST_CASE("a_budget_leaves_over_its_cap_the_share_of_the_height_its_95th_percentile_leaves_out") {
  // The same slopes to a top at 4 mm: 5% of the height is 0.2 mm, so of the two slopes' 0.15
  // mm layers only one may be over the by-height 95th percentile. The second's layer, D >=
  // 1.25 however cut, is that one; the first slope must be held within the percentile. The
  // least D of the layers holding it: [1.00, 1.15] 0.6875 cos(pi / 48), [1.05, 1.20] 0.9375,
  // or a boundary inside it at 1.10 (r 3.375), with [0.95, 1.10] (or thicker below, its wall
  // r 4) at (4 - 3.375) cos(pi / 48) = 0.625 cos(pi / 48) and [1.10, 1.25] (or thicker above,
  // wall r 3) at 0.375: the least is 0.625 cos(pi / 48), the plan's percentile in every budget
  // (the least tolerance's plan, both slopes' layers of 0.15 mm over its cap, 7.5% of the
  // height, has 0.686), its largest D that plan's, 1.25, and its swept volume no more.
  const std::vector<Vec2> profile = two_slopes(4.0);
  const std::vector<Vec2> outer(profile.begin() + 1, profile.end() - 1);
  const double least = 0.625 * std::cos(std::numbers::pi / kSides);
  REQUIRE(mid_distance(outer, 0.95, 1.1) == doctest::Approx(least).epsilon(1e-12));
  REQUIRE(mid_distance(outer, 1.1, 1.25) == doctest::Approx(0.375).epsilon(1e-12));
  const solids::Solid part = solids::revolve(profile, kSides);
  for (std::size_t budget : {16, 20, 24}) {
    CAPTURE(budget);
    const AdaptivePlan plan = plan_in_budget(part, 4.0, budget);
    REQUIRE(plan.layers.size() <= budget);
    CHECK(has_boundary(plan.layers, 1.1));
    // The by-height 95th percentile of the closed-form D of every layer, the first's 0 too.
    std::vector<std::pair<double, double>> by_d;
    double total = 0, most = 0;
    for (const Layer& l : plan.layers) {
      const double d = mid_distance(outer, l.z_lo, l.z_hi);
      by_d.push_back({d, l.z_hi - l.z_lo});
      total += l.z_hi - l.z_lo;
      most = std::max(most, d);
    }
    std::sort(by_d.begin(), by_d.end());
    double covered = 0, percentile = 0;
    for (const auto& [d, t] : by_d) {
      covered += t;
      percentile = d;
      if (covered >= 0.95 * total * (1 - 1e-12)) break;
    }
    CHECK(percentile == doctest::Approx(least).epsilon(1e-9));
    CHECK(most == doctest::Approx(1.25).epsilon(1e-9));
    CHECK(plan.cap >= least - 2e-3);
    for (std::size_t i = 1; i < plan.layers.size(); ++i) {
      CAPTURE(plan.layers[i].z_lo);
      CHECK(plan.distance[i] == doctest::Approx(mid_distance(outer, plan.layers[i].z_lo, plan.layers[i].z_hi)).epsilon(2e-3).scale(1));
    }
  }
}

TEST_CASE("a_print_time_budget_takes_the_layer_budgets_plan_of_the_count_it_fits") {
  // The slopes to a top at 4 mm, under a print-time budget that takes any plan of at most N
  // layers: its search takes the count N, and a plan as good as max_layers N gives, aimed at
  // the by-height percentile as above (a boundary at 1.10 mm; the walls' layers, D = 0 and no
  // volume swept, may lie otherwise), so that a plan made again in fewer layers (app/slice.cpp's
  // keep_time_budget, by max_layers) is of the kind the count was found by, and the count said
  // is the most whose layer budget's plan fits.
  const solids::Solid part = solids::revolve(two_slopes(4.0), kSides);
  for (std::size_t budget : {16, 20, 24}) {
    CAPTURE(budget);
    const AdaptivePlan counted = plan_in_budget(part, 4.0, budget);
    const AdaptivePlan timed = plan_in_budget(part, 4.0, budget, true);
    REQUIRE(counted.cap_by_height);
    CHECK(timed.cap_by_height);
    CHECK(timed.cap == counted.cap);
    CHECK(timed.layers.size() == counted.layers.size());
    CHECK(has_boundary(timed.layers, 1.1));
    // The layers' D over the walls' rounding (1e-16), by size.
    const auto slopes = [](std::vector<double> d) {
      std::erase_if(d, [](double v) { return v < 1e-9; });
      return std::sort(d.begin(), d.end()), d;
    };
    CHECK(slopes(timed.distance) == slopes(counted.distance));
    const auto total = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); };
    CHECK(total(timed.swept) == doctest::Approx(total(counted.swept)).epsilon(1e-12));
  }
}

namespace {

// mid's section with its holes filled: a planning contour whose D bounds mid's from above,
// loosely where the part has a hole (as mid's bounds best's, where mid fills a hole best keeps).
geometry::ContourResult mid_holes_filled(const geometry::ContourInput& input) {
  geometry::ContourResult result = geometry::contour_strategy("mid").contour(input);
  std::erase_if(result.region.loops, [](const geometry::Loop& loop) { return geometry::signed_area(loop) < 0; });
  return result;
}
const geometry::ContourStrategy kMidHolesFilled{"mid-holes-filled", "mid's section, holes filled", "#000000",
                                                &mid_holes_filled, nullptr};

}  // namespace

TEST_CASE("a_budget_aims_at_its_by_height_percentile_only_with_no_larger_d_as_printed") {
  // Planned by mid with holes filled, printed by mid: vertical walls of r 5 to 0.3 mm, a slope
  // of run 1 per mm of height to r 2.3 at 3 mm, one of run 4 to r 1.3 at 3.25 mm, vertical to
  // the top at 8.5 mm, and a cup of r 0.5 in the last 0.15 mm. The cup's layer, [8.35, 8.5],
  // has a planned D of at least 1.3 cos(pi / 48) - 0.5 (its hole's walls to the filled
  // section's) and a printed D of 0 (vertical walls). The steep slope is over the least
  // tolerance's cap in every plan: its thinnest layers have D = 4 * 0.15 / 2 = 0.3 ([3.10,
  // 3.25] or [3.05, 3.20]: r 1.9 to 1.3 or 2.1 to 1.5, cut at 1.6 or 1.8), 0.3 mm of the height
  // with the cup's 0.15 (5.3% of 8.5 mm); a by-height cap leaves at most 5% over it with one
  // thicker layer there ([3.00, 3.25], D = 2.3 - 1.8 = 0.5, or [3.00, 3.20], D = 0.4), whose
  // planned D is under the cup's. Printed by the planning contour, that plan is taken (its
  // largest D is the cup's either way); printed by mid it is not: no layer of the least
  // tolerance's plan prints a D over 0.3.
  const std::vector<Vec2> profile{{0, 0},      {5, 0},     {5, 0.3},     {2.3, 3.0},  {1.3, 3.25},
                                  {1.3, 8.5}, {0.5, 8.5}, {0.5, 8.35}, {0, 8.35}};
  const std::vector<Vec2> outer(profile.begin() + 1, profile.begin() + 6);
  REQUIRE(mid_distance(outer, 3.1, 3.25) == doctest::Approx(0.3).epsilon(1e-12));
  REQUIRE(mid_distance(outer, 3.05, 3.2) == doctest::Approx(0.3).epsilon(1e-12));
  REQUIRE(mid_distance(outer, 3.0, 3.2) == doctest::Approx(0.4).epsilon(1e-12));
  REQUIRE(mid_distance(outer, 3.0, 3.25) == doctest::Approx(0.5).epsilon(1e-12));
  const solids::Solid part = solids::revolve(profile, kSides);
  const geometry::LayerStack stack(part.mesh, {});
  for (std::size_t budget : {24, 26}) {
    CAPTURE(budget);
    for (const bool by_mid : {false, true}) {
      CAPTURE(by_mid);
      AdaptiveOptions options;
      options.max_layers = budget;
      options.contours = {&kMidHolesFilled};
      if (by_mid) options.printed = &geometry::contour_strategy("mid");
      const AdaptivePlan plan =
          geometry::adaptive_plan(stack, 8.5, kUpPlus2, geometry::flat_levels(part.mesh), options);
      REQUIRE(plan.layers.size() <= budget);
      CHECK(plan.ceiling >= 1.3 * std::cos(std::numbers::pi / kSides) - 0.5 - 2e-3);
      double most = 0;  // printed by mid, the cup's layer (vertical walls) 0
      for (std::size_t i = 1; i + 1 < plan.layers.size(); ++i) {
        most = std::max(most, mid_distance(outer, plan.layers[i].z_lo, plan.layers[i].z_hi));
      }
      CHECK(plan.cap_by_height == !by_mid);
      if (by_mid) {
        CHECK(most == doctest::Approx(0.3).epsilon(1e-9));
      } else {
        CHECK(most >= 0.4 - 1e-9);
        // The thicker layer over the cap lands nothing: it is said to be in the 5% the
        // by-height cap leaves out.
        std::size_t left_out = 0;
        for (std::size_t i = 1; i < plan.layers.size(); ++i) {
          CAPTURE(plan.layers[i].z_lo);
          CHECK(plan.why[i] != OverTolerance::landing);
          left_out += plan.why[i] == OverTolerance::height_share;
        }
        CHECK(left_out == 1);
      }
    }
  }
}

TEST_CASE("the_last_layer_ends_at_most_a_step_above_a_pointed_top") {
  // A cone whose apex, 20.02 mm, is on no height the UP Plus 2 reaches (0.3 + k 0.05).
  const solids::Solid cone = solids::cone(10, 20.02, kSides);
  for (double tolerance : {0.05, 0.1, 0.3}) {
    CAPTURE(tolerance);
    const AdaptivePlan plan = plan_for(cone.mesh, tolerance);
    REQUIRE(!plan.layers.empty());
    CHECK(plan.layers.back().z_hi >= 20.02);
    CHECK(plan.layers.back().z_hi <= 20.02 + 0.05 + 1e-9);
  }
}

TEST_CASE("the_top_layer_of_a_flat_topped_sphere_cap_is_within_the_tolerance") {
  // A sphere of radius 10 between 4 mm below its centre and 6 mm above: a flat top of radius
  // 8 at z = 10, the surface there 53 degrees from horizontal.
  std::vector<Vec2> profile{{0, 0}};
  const double low = std::asin(-0.4), high = std::asin(0.6);
  for (int k = 0; k <= 24; ++k) {
    const double a = low + (high - low) * k / 24;
    profile.push_back({10 * std::cos(a), 4 + 10 * std::sin(a)});
  }
  profile.back().y = 10;  // the top ring exactly at 10 mm
  profile.push_back({0, 10});
  const solids::Solid cap = solids::revolve(profile, kSides);
  const std::vector<Vec2> outer(profile.begin() + 1, profile.end() - 1);
  // (At 0.05 mm not even a 0.15 mm layer meets it up there: D = 0.15 cot(53) / 2 = 0.056.)
  for (double tolerance : {0.1, 0.2, 0.3}) {
    CAPTURE(tolerance);
    const AdaptivePlan plan = plan_for(cap.mesh, tolerance);
    REQUIRE(plan.layers.size() > 1);
    const Layer& top = plan.layers.back();
    CHECK(top.z_hi == 10.0);
    CHECK(mid_distance(outer, top.z_lo, top.z_hi) <= tolerance + 1e-9);
    CHECK(plan.distance.back() <= tolerance);
    CHECK(plan.unmet == 0);
  }
}

}  // namespace plan_contract_test

