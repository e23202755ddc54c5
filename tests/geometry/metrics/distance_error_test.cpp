// Distance error against closed forms. An n-gon cone (base circumradius r, height h) has
// concentric similar n-gon sections: circumradius rho(z) = r (1 - z/h), apothem
// a(z) = rho(z) cos(pi/n). From a smaller section to a larger one every point is at the apothem
// difference (the flank's slope across a face); from a larger one to a smaller one the
// farthest points are the corners, at the circumradius difference (the slope along the ridge
// edges, tan(alpha) = h / r). So over a layer of thickness t:
//   lower: forward (surface inside the walls) t r cos(pi/n) / h, reverse t r / h;
//   mid:   both t r / (2h), the corners of the sections below the mid-plane;
// lower's Hausdorff distance is twice mid's, as for the smooth cone's t / (2 tan(alpha)).
#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "geometry/metrics/distance_error.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/metrics/missed_features.h"
#include "geometry/slab/slab.h"
#include "support/solids.h"

namespace distance_error_test {

using geometry::DistanceError;
using geometry::LayerStack;
using geometry::Region;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTolerance = 1e-4;
// Regions from Clipper sit on the 1 nm grid: 0.71 nm from the exact sections.
constexpr double kRounding = 1e-6;

DistanceError distance_of(const LayerStack& stack, std::size_t layer, const Region& region,
                          int levels = 5) {
  const geometry::Slab slab = geometry::slab_of(stack, layer);
  geometry::DistanceOptions options;
  options.tolerance = kTolerance;
  options.reverse_levels = levels;
  const geometry::SlabSurface surface = geometry::slab_surface(slab, options);
  const auto missed = geometry::missed_features(geometry::slab_footprint(slab), region);
  return geometry::distance_error(surface, geometry::BoundaryGrid(region), missed, options);
}


// The 48-gon cone's (r 10, h 15) layer 20 of 0.25 mm layers, measured forward only: its
// surface and its lower and mid sections' walls (lower's D there is t r cos(pi/n) / h, about
// twice mid's t r / (2h)). Built in place: the slab and surface refer to the stack's mesh.
struct ConeLayer {
  static constexpr int n = 48;
  static constexpr double r = 10, h = 15;
  solids::Solid cone = solids::cone(r, h, n);
  LayerStack stack{cone.mesh, geometry::uniform_layers(h, 0.25)};
  geometry::Slab slab = geometry::slab_of(stack, 20);
  geometry::DistanceOptions options = forward_only();
  geometry::SlabSurface surface = geometry::slab_surface(slab, options);
  geometry::BoundaryGrid mid_walls{stack.mid(20)}, lower_walls{stack.lower(20)};

  static geometry::DistanceOptions forward_only() {
    geometry::DistanceOptions o;
    o.tolerance = kTolerance;
    o.reverse = false;
    return o;
  }
};

}  // namespace

TEST_CASE("cone_distance_of_lower_is_twice_that_of_mid") {
  const int n = 48;
  const double r = 10, h = 15;
  const solids::Solid cone = solids::cone(r, h, n);
  const LayerStack stack(cone.mesh, geometry::uniform_layers(h, 0.25));
  for (std::size_t i : {0u, 20u, 45u}) {
    CAPTURE(i);
    const double t = stack.layers()[i].thickness();
    const DistanceError lower = distance_of(stack, i, stack.lower(i));
    const DistanceError mid = distance_of(stack, i, stack.mid(i));
    const double bound = kTolerance + kRounding;
    CHECK(std::abs(lower.forward - t * r * std::cos(kPi / n) / h) <= bound);
    CHECK(std::abs(lower.reverse - t * r / h) <= bound);
    CHECK(std::abs(mid.forward - t * r / (2 * h)) <= bound);
    CHECK(std::abs(mid.reverse - t * r / (2 * h)) <= bound);
    CHECK(mid.hausdorff == std::max(mid.forward, mid.reverse));
    CHECK(std::abs(lower.hausdorff - 2 * mid.hausdorff) <= 3 * bound);
  }
}

TEST_CASE("settling_below_a_bound_proves_the_cone_within_it_and_measures_it_exactly_above") {
  // lower's forward D on the cone's layer is t r cos(pi/n) / h (above): asked to settle
  // below a bound over it, the search shows D within the bound (forward then a lower bound,
  // at most D); below it, it measures D as ever.
  const ConeLayer c;
  const double d = 0.25 * c.r * std::cos(kPi / c.n) / c.h;
  geometry::DistanceOptions options = c.options;
  const geometry::SlabSurface& surface = c.surface;
  const geometry::BoundaryGrid& walls = c.lower_walls;
  const DistanceError exact = geometry::distance_error(surface, walls, {}, options);
  CHECK_FALSE(exact.settled);
  CHECK(std::abs(exact.forward - d) <= kTolerance + kRounding);
  options.settle_below = 1.5 * d;
  const DistanceError within = geometry::distance_error(surface, walls, {}, options);
  CHECK(within.settled);
  CHECK(within.forward <= d + kRounding);
  options.settle_below = 0.5 * d;
  const DistanceError above = geometry::distance_error(surface, walls, {}, options);
  CHECK_FALSE(above.settled);
  CHECK(std::abs(above.forward - d) <= kTolerance + kRounding);
}

TEST_CASE("points_measured_first_refute_a_farther_region_and_leave_an_exact_distance_alone") {
  // On the cone's layer lower's D is about twice mid's (above). With the points farthest
  // from mid's walls measured first, lower is still refuted against mid's D, by a lower
  // bound of its own; measuring mid again with lower's farthest first gives the same D to
  // the bit.
  const ConeLayer c;
  geometry::DistanceOptions options = c.options;
  const geometry::SlabSurface& surface = c.surface;
  const geometry::BoundaryGrid &mid_walls = c.mid_walls, &lower_walls = c.lower_walls;
  options.farthest_count = 8;
  const DistanceError mid = geometry::distance_error(surface, mid_walls, {}, options);
  const DistanceError lower = geometry::distance_error(surface, lower_walls, {}, options);
  REQUIRE(mid.farthest.size() == 8);
  for (std::size_t k = 0; k < mid.farthest.size(); ++k) {
    const double d = mid_walls.nearest(surface.points[mid.farthest[k]]).distance;
    CHECK(d <= mid.forward + kRounding);
    if (k > 0) CHECK(d <= mid_walls.nearest(surface.points[mid.farthest[k - 1]]).distance);
  }
  options.farthest_count = 0;
  options.first_points = lower.farthest;
  const DistanceError mid_again = geometry::distance_error(surface, mid_walls, {}, options);
  CHECK(mid_again.forward == mid.forward);
  options.first_points = mid.farthest;
  options.stop_above = mid.forward + 1e-3;
  const DistanceError refuted = geometry::distance_error(surface, lower_walls, {}, options);
  CHECK(refuted.forward > options.stop_above);
  CHECK(refuted.forward <= lower.forward);
  CHECK(refuted.farthest.empty());
}

TEST_CASE("cylinder_distance_of_its_section_is_zero") {
  const solids::Solid cylinder = solids::cylinder(6, 8, 40);
  const LayerStack stack(cylinder.mesh, geometry::uniform_layers(8, 0.2));
  for (std::size_t i : {0u, 17u, 39u}) {
    const DistanceError d = distance_of(stack, i, stack.mid(i));
    CHECK(d.forward <= kRounding);
    CHECK(d.reverse <= kRounding);
  }
}

TEST_CASE("distance_maximum_inside_a_facet_is_found") {
  // A prism lying along x whose top face slopes gently (z 1.0 at y = 0 to 1.05 at y = 6)
  // covers the rectangle [0, 10] x [0, 6] seen from above: its two triangles have their
  // corners on the rectangle's boundary (distance 0), while the distance to the lower
  // section's walls peaks at 3 along y = 3, inside the facets.
  const solids::Solid wedge = solids::lying_prism({{0, 0}, {6, 0}, {6, 1.05}, {0, 1.0}}, 0, 10);
  const LayerStack stack(wedge.mesh, geometry::uniform_layers(1.05, 0.3));
  const std::size_t top = 3;  // [0.9, 1.2]
  const DistanceError d = distance_of(stack, top, stack.lower(top));
  CHECK(d.forward <= 3 + kRounding);
  CHECK(d.forward >= 3 - kTolerance - kRounding);
}

TEST_CASE("horizontal_facet_is_judged_by_its_edges") {
  // The same prism with a flat top at 1.0: the top face is parallel to the layer's faces, so
  // only its edges count, and they lie on the walls.
  const solids::Solid block = solids::lying_prism({{0, 0}, {6, 0}, {6, 1.0}, {0, 1.0}}, 0, 10);
  const LayerStack stack(block.mesh, geometry::uniform_layers(1.0, 0.3));
  const std::size_t top = 3;  // [0.9, 1.2], the top face at 1.0 strictly inside
  const DistanceError d = distance_of(stack, top, stack.lower(top));
  CHECK(d.forward <= kRounding);
}

TEST_CASE("corners_kept_in_a_state_resume_to_the_same_distance_or_a_refutation") {
  // The cone's layer again: lower's corners measured alone give their farthest one's distance
  // (at most lower's D), and mid measured in full between, the search resumed from those
  // corners gives lower's D to the bit, or at mid's D + 1 um a bound above it; the same with
  // a missed feature (the box and cone's tip, measured to the tip's outline).
  const ConeLayer c;
  geometry::DistanceOptions options = c.options;
  const geometry::SlabSurface& surface = c.surface;
  const geometry::BoundaryGrid &mid_walls = c.mid_walls, &lower_walls = c.lower_walls;
  const DistanceError lower = geometry::distance_error(surface, lower_walls, {}, options);
  const DistanceError mid = geometry::distance_error(surface, mid_walls, {}, options);
  REQUIRE(lower.forward > 1.5 * mid.forward);
  geometry::ForwardState state;
  for (const double stop : {std::numeric_limits<double>::infinity(), mid.forward + 1e-3}) {
    CAPTURE(stop);
    geometry::DistanceOptions corners = options;
    corners.state = &state;
    corners.corners_only = true;
    corners.farthest_count = 4;
    const DistanceError first = geometry::distance_error(surface, lower_walls, {}, corners);
    CHECK(first.forward <= lower.forward);
    CHECK(first.farthest.size() == 4);
    CHECK(lower_walls.nearest(surface.points[first.farthest[0]]).distance == first.forward);
    CHECK(geometry::distance_error(surface, mid_walls, {}, options).forward == mid.forward);
    geometry::DistanceOptions resume = options;
    resume.state = &state;
    resume.stop_above = stop;
    const DistanceError resumed = geometry::distance_error(surface, lower_walls, {}, resume);
    if (std::isinf(stop)) {
      CHECK(resumed.forward == lower.forward);
    } else {
      CHECK(resumed.forward > stop);
      CHECK(resumed.forward <= lower.forward);
    }
  }
  // Resumed with other walls than the corners were measured to: measured afresh.
  geometry::DistanceOptions corners = options;
  corners.state = &state;
  corners.corners_only = true;
  geometry::distance_error(surface, lower_walls, {}, corners);
  geometry::DistanceOptions resume = options;
  resume.state = &state;
  CHECK(geometry::distance_error(surface, mid_walls, {}, resume).forward == mid.forward);

  const solids::Solid both = solids::combine(solids::box({-10, -3, 0}, {0, 3, 2}),
                                             solids::cone(2, 2, 64, {7, 0, 0}));
  const LayerStack two(both.mesh, geometry::uniform_layers(2, 0.5));
  const geometry::Slab top = geometry::slab_of(two, 3);
  const geometry::SlabSurface top_surface = geometry::slab_surface(top, options);
  const Region box_only{{{{-10, -3}, {0, -3}, {0, 3}, {-10, 3}}}};
  const auto missed = geometry::missed_features(geometry::slab_footprint(top), box_only);
  REQUIRE(missed.size() == 1);
  const geometry::BoundaryGrid box_walls(box_only);
  const double whole = geometry::distance_error(top_surface, box_walls, missed, options).forward;
  geometry::distance_error(top_surface, box_walls, missed, corners);
  CHECK(geometry::distance_error(top_surface, box_walls, missed, resume).forward == whole);
}

TEST_CASE("empty_region_is_measured_to_the_footprint_outline") {
  // The cone's top layer holds the apex: with nothing printed, the apex is as far from the
  // walls shrunk onto the footprint as the base's apothem (plus the footprint's 2 um margin).
  const int n = 48;
  const solids::Solid cone = solids::cone(10, 15, n);
  const LayerStack stack(cone.mesh, geometry::uniform_layers(15, 0.25));
  const std::size_t top = stack.size() - 1;
  const double apothem = 10 * (1 - stack.layers()[top].z_lo / 15) * std::cos(kPi / n);
  const DistanceError d = distance_of(stack, top, Region{});
  CHECK(d.forward >= apothem - kTolerance);
  CHECK(d.forward <= apothem + 2.2 * geometry::kFootprintMargin);
  CHECK(d.reverse == 0);
}

TEST_CASE("missed_feature_is_measured_to_its_own_outline") {
  // A box and, 5 mm away, a cone of the same height: in the top layer [1.5, 2] the region is
  // the box's section only, so the cone's tip is a missed feature. It is measured to its own
  // outline (the apothem of its section at 1.5), not to the box's wall 5 mm away.
  const int n = 64;
  const solids::Solid both = solids::combine(solids::box({-10, -3, 0}, {0, 3, 2}),
                                             solids::cone(2, 2, n, {7, 0, 0}));
  const LayerStack stack(both.mesh, geometry::uniform_layers(2, 0.5));
  const Region box_only{{{{-10, -3}, {0, -3}, {0, 3}, {-10, 3}}}};
  const DistanceError d = distance_of(stack, 3, box_only);
  const double apothem = 2 * (1 - 1.5 / 2) * std::cos(kPi / n);
  CHECK(d.forward >= apothem - kTolerance);
  CHECK(d.forward <= apothem + 2.2 * geometry::kFootprintMargin);
}

TEST_CASE("reverse_distance_is_sampled_at_its_levels_and_forward_is_not") {
  // A double n-gon pyramid whose equator lies in the middle of a layer, printed with the
  // layer's lower section: the surface's widest section (the equator, circumradius 10) is
  // 0.4 mm outside the walls (circumradius 9.6). forward, searched over the whole surface, finds
  // that 0.4 mm (the circumradius difference); reverse, measured only at its levels, sees the
  // equator with 3 levels (z_lo, the middle, z_hi: the apothem difference 0.4 cos(pi/n)) and
  // nothing with 2, where the sections at z_lo and z_hi are the walls themselves. So D is
  // exact to its tolerance; H, which takes the reverse direction, is sampled in z.
  const int n = 8;
  const solids::Solid solid = solids::bipyramid(10, n, 0, 10, 20);
  const LayerStack stack(solid.mesh, geometry::uniform_layers(20, 0.8));
  const std::size_t i = 12;
  REQUIRE(stack.layers()[i].z_lo == doctest::Approx(9.6));
  REQUIRE(stack.layers()[i].z_hi == doctest::Approx(10.4));
  const DistanceError two = distance_of(stack, i, stack.lower(i), 2);
  const DistanceError three = distance_of(stack, i, stack.lower(i), 3);
  const double bound = kTolerance + kRounding;
  CHECK(std::abs(two.forward - 0.4) <= bound);
  CHECK(std::abs(three.forward - 0.4) <= bound);
  CHECK(two.reverse <= bound);
  CHECK(std::abs(three.reverse - 0.4 * std::cos(kPi / n)) <= bound);
}

TEST_CASE("search_finds_the_maximum_where_each_facet_spans_several_wall_segments") {
  // A sphere's band of 0.65 mm facets judged against a 360-gon of 0.17 mm segments: each
  // facet (and each wall segment against the band's level lines) faces several segments, so
  // the search's bounds are the corners' nearest segments and feet, not one segment. The
  // result is a lower bound within the tolerance of the true maximum: at least what a dense
  // sampling of every triangle (and every wall segment, at the levels) finds, less the
  // tolerance; at most that sampling's value plus the distance between its samples.
  const solids::Solid sphere = solids::sphere(10, 96, 48, {0, 0, 10});
  const LayerStack stack(sphere.mesh, geometry::uniform_layers(20, 0.4));
  const int sides = 360;
  for (std::size_t i : {5u, 30u, 44u}) {  // [2, 2.4], [12, 12.4], [17.6, 18]
    CAPTURE(i);
    const double z = stack.layers()[i].z_mid();
    const double radius = std::sqrt(100 - (z - 10) * (z - 10)) - 0.05;
    geometry::Loop circle;
    for (int k = 0; k < sides; ++k) {
      const double a = 2 * kPi * k / sides;
      circle.push_back({radius * std::cos(a), radius * std::sin(a)});
    }
    const Region region{{circle}};
    const geometry::Slab slab = geometry::slab_of(stack, i);
    geometry::DistanceOptions options;
    options.tolerance = kTolerance;
    const geometry::SlabSurface surface = geometry::slab_surface(slab, options);
    const geometry::BoundaryGrid walls(region);
    const DistanceError d = geometry::distance_error(surface, walls, {}, options);
    constexpr int kSteps = 40;
    double forward = 0, forward_step = 0;
    for (const auto& t : surface.triangles) {
      for (int u = 0; u <= kSteps; ++u) {
        for (int v = 0; u + v <= kSteps; ++v) {
          const double a = double(u) / kSteps, b = double(v) / kSteps;
          const geometry::Vec2 p = t[0] + a * (t[1] - t[0]) + b * (t[2] - t[0]);
          forward = std::max(forward, walls.nearest(p).distance);
        }
      }
      for (int k = 0; k < 3; ++k) {
        forward_step = std::max(forward_step, geometry::length(t[(k + 1) % 3] - t[k]) / kSteps);
      }
    }
    double reverse = 0, reverse_step = 0;
    for (const geometry::BoundaryGrid& level : surface.levels) {
      for (const geometry::Segment2& s : walls.segments()) {
        for (int k = 0; k <= kSteps; ++k) {
          const geometry::Vec2 p = s.a + (double(k) / kSteps) * (s.b - s.a);
          reverse = std::max(reverse, level.nearest(p).distance);
        }
        reverse_step = std::max(reverse_step, geometry::length(s.b - s.a) / kSteps);
      }
    }
    CHECK(forward > 0.05);
    CHECK(d.forward >= forward - kTolerance - kRounding);
    CHECK(d.forward <= forward + forward_step);
    CHECK(d.reverse >= reverse - kTolerance - kRounding);
    CHECK(d.reverse <= reverse + reverse_step);
  }
}

// The forward distance (to kTolerance) from a surface of the slab z 0 to 1, seen from
// above as these triangles, to the walls of the square [0, 10]^2, where the distance is
// min(x, 10 - x, y, 10 - y).
DistanceError forward_to_square_walls(const std::vector<std::array<geometry::Vec2, 3>>& triangles) {
  const geometry::Loop square{{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  const geometry::BoundaryGrid walls(Region{{square}});
  geometry::SlabSurface surface;
  surface.z_lo = 0;
  surface.z_hi = 1;
  surface.triangles = triangles;
  geometry::DistanceOptions options;
  options.tolerance = kTolerance;
  options.reverse = false;
  return geometry::distance_error(surface, walls, {}, options);
}

TEST_CASE("a_square_s_largest_distance_is_found_inside_a_facet_over_its_centre") {
  // The walls of the square [0, 10]^2 and, seen from above, a surface of 7 x 7 cells of two
  // triangles each over it: the distance to the walls, min(x, 10 - x, y, 10 - y), is 5 at the
  // centre, which is no corner of the triangles (the cells are 10/7 wide), and below 5 by the
  // distance from the centre elsewhere. On every triangle the distance is the least of the
  // affine distances to the four sides: a search that settles the triangles far from the
  // centre must still find the centre's 5 to within the tolerance.
  constexpr int kCells = 7;
  const auto at = [](int i, int j) { return geometry::Vec2{10.0 * i / kCells, 10.0 * j / kCells}; };
  std::vector<std::array<geometry::Vec2, 3>> triangles;
  for (int i = 0; i < kCells; ++i) {
    for (int j = 0; j < kCells; ++j) {
      triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  const DistanceError d = forward_to_square_walls(triangles);
  CHECK(d.forward <= 5 + kRounding);
  CHECK(d.forward >= 5 - kTolerance - kRounding);
  // Any of the triangles' corners is at most 10/7 * 3 = 4.29 from the walls.
  CHECK(d.forward > 10.0 * 3 / kCells + 0.5);
}

TEST_CASE("a_facet_whose_corners_are_nearer_than_another_s_is_still_searched_inside") {
  // The walls of the square [0, 10]^2, where the distance is min(x, 10 - x, y, 10 - y). A
  // small triangle near the centre, corners 4.9 to 4.95 from the walls and 4.925 at most, is
  // searched first (farthest corner first); a larger one around the centre has its corners
  // 3 to 4 from the walls but 5 at the centre, 0.075 above what the first found: a bound of
  // the second triangle below that (unsound: the true maximum is 5) would leave its inside
  // unsearched.
  const DistanceError d = forward_to_square_walls(
      {{geometry::Vec2{4.9, 4.9}, {4.95, 4.9}, {4.9, 4.95}}, {geometry::Vec2{4, 4}, {7, 4.5}, {4.5, 7}}});
  CHECK(d.forward <= 5 + kRounding);
  CHECK(d.forward >= 5 - kTolerance - kRounding);
}

}  // namespace distance_error_test
