// The exact medial axis of a region (segment Voronoi diagram) against closed forms: a strip's
// axis is its centre line at half its width, and a wedge's is its bisector, cut where the
// wedge is narrower than the narrowest bead.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <numbers>

#include "geometry/toolpaths/segment_medial_axis.h"

namespace segment_medial_axis_test {

using geometry::Region;
using geometry::SegmentMedialAxis;

TEST_CASE("strip_axis_is_its_centre_line_at_half_its_width") {
  const Region strip{{{{0, 0}, {10, 0}, {10, 0.4}, {0, 0.4}}}};
  SegmentMedialAxis axis = geometry::segment_medial_axis(strip, 0.05, 0.45);
  geometry::prune_spurs(axis);
  CHECK(axis.origin.x == 0);
  CHECK(axis.origin.y == 0);
  // The four corners are right angles, blunter than a tapering wall: their branches go.
  const auto chains = geometry::axis_chains(axis);
  REQUIRE(chains.size() == 1);
  double x_lo = 1e300, x_hi = -1e300;
  for (std::size_t i : chains[0]) {
    CHECK(axis.points[i].y == doctest::Approx(0.2e6));  // nm from the origin
    CHECK(axis.radius[i] == doctest::Approx(0.2e6));
    x_lo = std::min(x_lo, axis.points[i].x);
    x_hi = std::max(x_hi, axis.points[i].x);
  }
  // It ends where the corners' bisectors meet it: half the width in from each end.
  CHECK(x_lo == doctest::Approx(0.2e6));
  CHECK(x_hi == doctest::Approx(9.8e6));
}

TEST_CASE("sharp_wedge_axis_runs_down_its_bisector_to_the_narrowest_bead") {
  // A wedge of 20 degrees at the origin, 10 mm long, closed by an arc-free chord.
  const double half = 10 * std::numbers::pi / 180, r = 10;
  const Region wedge{{{{0, 0}, {r * std::cos(half), -r * std::sin(half)},
                       {r * std::cos(half), r * std::sin(half)}}}};
  const double min_radius = 0.1;
  SegmentMedialAxis axis = geometry::segment_medial_axis(wedge, min_radius, 5);
  geometry::prune_spurs(axis);
  // On the bisector (y = 0 in the part's frame) the inscribed radius is x sin(half): the
  // axis' point nearest the tip is where that is min_radius.
  const double tip_x = min_radius / std::sin(half);
  double nearest = 1e300;
  for (std::size_t i = 0; i < axis.points.size(); ++i) {
    const double x = axis.origin.x + axis.points[i].x * 1e-6;
    const double y = axis.origin.y + axis.points[i].y * 1e-6;
    if (std::abs(y) > 1e-6) continue;
    CHECK(axis.radius[i] * 1e-6 == doctest::Approx(x * std::sin(half)).epsilon(1e-6));
    nearest = std::min(nearest, x);
  }
  CHECK(nearest == doctest::Approx(tip_x).epsilon(1e-6));
}

namespace {

// Distance from p to a closed polygon's edges (all in the same units).
double distance_to_loop(const std::vector<geometry::Vec2>& loop, geometry::Vec2 p) {
  double best = 1e300;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const geometry::Vec2 a = loop[i], b = loop[(i + 1) % loop.size()];
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double t = std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
    best = std::min(best, std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy));
  }
  return best;
}

}  // namespace

// A thin ring between two fine polygons of 20 and 20.4 mm radius, with different vertex
// counts so that every edge of one side is nearly, never exactly, parallel to the edges
// facing it (the gap fill's strips are such; there the diagram's circles are formed in
// floating point): each axis point is as far from either side as its radius says, to a
// nanometre, and that radius is half the width, to the chords' sagitta (0.2 um).
TEST_CASE("thin_ring_axis_is_equidistant_from_its_nearly_parallel_sides") {
  auto polygon = [](double radius, int n, bool hole) {
    geometry::Loop loop;
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * (hole ? n - i : i) / n + 0.001;
      loop.push_back({radius * std::cos(a), radius * std::sin(a)});
    }
    return loop;
  };
  const geometry::Loop outer = polygon(20.4, 733, false), inner = polygon(20, 719, true);
  SegmentMedialAxis axis = geometry::segment_medial_axis(Region{{outer, inner}}, 0.05, 0.45);
  geometry::prune_spurs(axis);
  REQUIRE(axis.points.size() > 700);
  auto in_frame = [&](const geometry::Loop& loop) {  // nm from the axis' origin
    std::vector<geometry::Vec2> out;
    for (const auto& p : loop) out.push_back({(p.x - axis.origin.x) * 1e6, (p.y - axis.origin.y) * 1e6});
    return out;
  };
  const auto outer_nm = in_frame(outer), inner_nm = in_frame(inner);
  for (std::size_t i = 0; i < axis.points.size(); ++i) {
    CHECK(std::abs(distance_to_loop(outer_nm, axis.points[i]) - axis.radius[i]) < 1);
    CHECK(std::abs(distance_to_loop(inner_nm, axis.points[i]) - axis.radius[i]) < 1);
    CHECK(std::abs(axis.radius[i] - 0.2e6) < 250);
  }
}

}  // namespace segment_medial_axis_test
