// The plan's measure of one slab (geometry/plan/slab_error.h) against analyze's (layer_metrics)
// and closed forms, where a piece of the slab's surface does not cross the mid section's
// height: a small ball inside a prism (its island overlaps the section, so the slab is
// measured to the walls without a footprint) and the same ball floating beside it (an island
// the section misses, measured to its own outline).
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "geometry/contour/contour_strategy.h"
#include "geometry/metrics/layer_metrics.h"
#include "geometry/plan/slab_error.h"
#include "geometry/slab/slab.h"
#include "geometry/slicing/layer_stack.h"
#include "support/solids.h"

namespace {

constexpr int kSides = 48;
constexpr double kRadius = 10, kBall = 0.015;
constexpr double kLo = 5.0, kHi = 5.1;  // the slab; its mid section at 5.05, above the ball

// D of the slab [kLo, kHi] by the plan's meter (with and without a threshold to refute past)
// and by analyze's measure of the same layer and region.
void check_both(const geometry::Mesh& mesh, double expected) {
  const geometry::LayerStack stack(mesh, {geometry::Layer{kLo, kHi}});
  const geometry::ContourStrategy* mid[] = {&geometry::contour_strategy("mid")};
  const geometry::SlabMeter meter(stack);
  const geometry::SlabError exact = meter(kLo, kHi, mid);
  const geometry::LayerMetrics analyzed = geometry::layer_metrics(stack, 0, stack.mid(0));
  CHECK(exact.exact());
  CHECK(std::abs(exact.distance() - analyzed.distance) <= 1e-3);
  CHECK(std::abs(exact.distance() - expected) <= 2e-3);
  // Refuted below D: a lower bound past the threshold; settled above it: within it.
  const geometry::SlabError refuted = meter(kLo, kHi, mid, expected / 2, expected / 2);
  CHECK(refuted.distance() > expected / 2);
  CHECK(refuted.distance() <= expected + 2e-3);
  const geometry::SlabError settled = meter(kLo, kHi, mid, expected + 0.01, expected + 0.01, true);
  CHECK(settled.distance() <= expected + 0.01);
}

}  // namespace

TEST_CASE("a_slab_with_a_ball_inside_its_mid_section_below_its_height_is_measured_to_the_walls") {
  // The ball (z 5.005-5.035) is a piece of surface of its own that does not reach 5.05. Its
  // farthest point from the 48-gon's walls is the one nearest the axis, (3 - r, 0): as far
  // from the two nearest sides, whose normals lie pi/48 either side of +x, as
  // R cos(pi/48) - (3 - r) cos(pi/48).
  const solids::Solid part = solids::combine(solids::cylinder(kRadius, 10, kSides),
                                             solids::sphere(kBall, 16, 8, {3, 0, 5.02}));
  check_both(part.mesh, (kRadius - (3 - kBall)) * std::cos(std::numbers::pi / kSides));
}

TEST_CASE("a_slab_with_a_ball_beside_its_mid_section_below_its_height_measures_it_to_its_outline") {
  // The ball floats outside the prism: an island the mid section misses, whose surface is
  // measured to the island's own outline (distance_error.h): the equator's 16-gon grown by
  // the footprint's margin. Its top, over the centre, is the farthest: r cos(pi/16) + margin.
  const solids::Solid part = solids::combine(solids::cylinder(kRadius, 10, kSides),
                                             solids::sphere(kBall, 16, 8, {13, 0, 5.02}));
  check_both(part.mesh, kBall * std::cos(std::numbers::pi / 16) + geometry::kFootprintMargin);
}

TEST_CASE("a_frustums_slab_is_refused_from_its_end_sections_as_measuring_it_would_refuse_it") {
  // A 48-gon frustum narrowing from r 10 to 5 over 10 mm: at z its corners lie on a circle of
  // r(z) = 10 - z / 2. The slab [5.0, 5.2] cuts its mid section at 5.1, corners at 7.45; the
  // bottom section's corners stand 7.5 - 7.45 = 0.05 mm outside the mid section's (the top's
  // as far inside), and the points where a section crosses a side's diagonal
  // 0.05 cos(pi/48) from the nearest side. D of the slab is 0.05.
  const solids::Solid part = solids::frustum(10, 5, 10, kSides);
  const geometry::LayerStack stack(part.mesh, {});
  const geometry::ContourStrategy& mid = geometry::contour_strategy("mid");
  const geometry::ContourStrategy* strategies[] = {&mid};
  const geometry::SlabMeter meter(stack);
  const double step = 0.05, side = step * std::cos(std::numbers::pi / kSides);
  const double past = meter.ends_past(5.0, 5.2, mid, 0.04);
  CHECK(past >= side - 1e-6);
  CHECK(past <= step + 1e-6);
  // Measuring the slab refutes it with the same figure; within 0.06 the ends show nothing.
  CHECK(meter(5.0, 5.2, strategies, 0.04, 0.04).distance() == past);
  CHECK(meter.ends_past(5.0, 5.2, mid, 0.06) == 0);
  CHECK(std::abs(meter(5.0, 5.2, strategies).distance() - step) <= 2e-3);
}

TEST_CASE("a_slab_whose_section_misses_an_island_is_not_refused_from_its_end_sections") {
  // A post of r 0.5 beside the prism with a conical tip from 5.0 to 5.03, inside the slab
  // [5.0, 5.1] and below its mid section: an island the section misses. The post's section
  // at 5.0 stands 2.5 mm and more from the prism's walls, but the tip is measured to the
  // island's own outline (the post's 48-gon grown by the footprint's margin), its apex
  // farthest: 0.5 cos(pi/48) + margin. The ends prove nothing there.
  const solids::Solid part = solids::combine(solids::cylinder(kRadius, 10, kSides),
                                             solids::revolve({{0, 0}, {0.5, 0}, {0.5, 5.0}, {0, 5.03}}, kSides, {13, 0}));
  const geometry::LayerStack stack(part.mesh, {});
  const geometry::ContourStrategy& mid = geometry::contour_strategy("mid");
  const geometry::ContourStrategy* strategies[] = {&mid};
  const geometry::SlabMeter meter(stack);
  CHECK(meter.ends_past(kLo, kHi, mid, 1.0) == 0);
  const geometry::SlabError measured = meter(kLo, kHi, strategies);
  CHECK(measured.trials.front().missed == 1);
  CHECK(std::abs(measured.distance() - (0.5 * std::cos(std::numbers::pi / kSides) + geometry::kFootprintMargin)) <= 2e-3);
}
