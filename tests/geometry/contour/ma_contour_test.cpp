// The medial-axis contour (paper §3.2-3.3) against closed forms.
//
// Every expected shape below is derived by hand. Two facts carry most of them:
// - the strip between two concentric regular n-gons of circumradii r1 < r2 with the same phase
//   has its medial axis on the n-gon of circumradius (r1 + r2)/2 along the edges (their
//   parallel offsets meet half-way); near each corner it is a parabola with the inner corner
//   as focus, which crosses the corner's ray at (r1 + r2 c)/(1 + c), c = cos(pi/n), so at most
//   (r2 - r1)(1 - c) / (2 (1 + c)) inside the mean n-gon;
// - a solid whose flank is linear between two heights (a cone, a frustum, a band of a UV
//   sphere between ring heights) has as section at the layer's middle exactly that mean n-gon.
// The footprint is grown by kFootprintMargin (2 um) on both sides of the strip, which moves
// the axis by at most a fraction of that; fairing keeps the contour within 1 um of the axis.
#include <doctest/doctest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "geometry/slab/boundary_pair.h"
#include "geometry/core/clipper.h"
#include "geometry/core/point_in_region.h"
#include "geometry/metrics/layer_metrics.h"
#include "geometry/slicing/layer_stack.h"
#include "geometry/contour/ma_contour.h"
#include "geometry/mesh/placement.h"
#include "geometry/core/polygon.h"
#include "geometry/mesh/repair.h"
#include "geometry/slab/slab.h"
#include "geometry/slab/slab_columns.h"
#include "geometry/mesh/stl_io.h"
#include "support/solids.h"

namespace ma_contour_test {

using namespace geometry;

namespace {

constexpr double kPi = std::numbers::pi;
// Allowance for the margin and the fairing tolerance together, mm.
constexpr double kStripAllowance = kFootprintMargin + 0.0015;

Loop circle(double radius, int n, Vec2 centre = {}, bool clockwise = false) {
  Loop loop;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * kPi * i / n * (clockwise ? -1 : 1);
    loop.push_back({centre.x + radius * std::cos(a), centre.y + radius * std::sin(a)});
  }
  return loop;
}

double distance_to_boundary(Vec2 p, const Region& region) {
  double best = INFINITY;
  for (const Loop& loop : region.loops) {
    for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
      best = std::min(best, distance_to_segment(p, loop[i], loop[(i + 1) % n]));
    }
  }
  return best;
}

// The largest distance from a point of a's boundary (vertices and points every `step` mm on
// its edges) to b's boundary.
double one_sided(const Region& a, const Region& b, double step) {
  double worst = 0;
  for (const Loop& loop : a.loops) {
    for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
      const Vec2 p = loop[i], q = loop[(i + 1) % n];
      const int pieces = std::max(1, static_cast<int>(std::ceil(std::hypot(q.x - p.x, q.y - p.y) / step)));
      for (int k = 0; k < pieces; ++k) {
        worst = std::max(worst, distance_to_boundary(p + (double(k) / pieces) * (q - p), b));
      }
    }
  }
  return worst;
}

// Hausdorff distance between two regions' boundaries, to within `step`/2.
double boundary_hausdorff(const Region& a, const Region& b, double step = 0.05) {
  return std::max(one_sided(a, b, step), one_sided(b, a, step));
}

double max_radius(const Loop& loop) {
  double r = 0;
  for (Vec2 p : loop) r = std::max(r, std::hypot(p.x, p.y));
  return r;
}

// The circumradius of an n-gon section's loop that is outer (ccw) or hole (cw).
double section_radius(const Region& section, bool outer) {
  for (const Loop& loop : section.loops) {
    if ((signed_area(loop) > 0) == outer) return max_radius(loop);
  }
  return 0;
}

int count_ccw(const Region& r) {
  return static_cast<int>(std::count_if(r.loops.begin(), r.loops.end(),
                                        [](const Loop& l) { return signed_area(l) > 0; }));
}
int count_cw(const Region& r) { return static_cast<int>(r.loops.size()) - count_ccw(r); }

}  // namespace

// ---- one island, synthetic boundary pairs ----

TEST_CASE("concentric_circles_ma_is_the_mean_radius_circle") {
  const int n = 720;
  const double r1 = 8, r2 = 10;
  const BoundaryPair pair{circle(r2, n), {circle(r1, n, {}, true)}};
  const std::vector<char> solid{0, 1};  // empty outside, solid inside the hole
  const std::vector<Loop> loops = medial_axis_loops(pair, solid);
  REQUIRE(loops.size() == 1);
  CHECK(signed_area(loops[0]) > 0);  // solid on the left: counter-clockwise
  // Inscribed 720-gons: the boundary is within r (1 - cos(pi/720)) < 1e-4 mm of the circles.
  const double polygon_error = r2 * (1 - std::cos(kPi / n));
  for (std::size_t i = 0; i < loops[0].size(); ++i) {
    const Vec2 p = loops[0][i], q = loops[0][(i + 1) % loops[0].size()];
    CHECK(std::abs(std::hypot(p.x, p.y) - 9) <= polygon_error + 0.001);
    const Vec2 m = 0.5 * (p + q);  // fairing: the contour's edges follow the axis too
    CHECK(std::abs(std::hypot(m.x, m.y) - 9) <= polygon_error + 0.001);
  }
}

TEST_CASE("concentric_circles_unfaired_ma_is_near_the_mean_radius") {
  // Unfaired, a vertex is the midpoint of a Delaunay edge from one circle to the other: with
  // samples 0.1 mm apart its ends are at most 0.05 mm apart along the circle, so it lies at
  // most 0.05^2 / (8 * 8) mm inside the mean circle, and the chord sag adds 0.1^2 / (8 * 9).
  MaOptions options;
  options.fairing = false;
  options.spacing = 0.1;
  const BoundaryPair pair{circle(10, 720), {circle(8, 720, {}, true)}};
  const std::vector<char> solid{0, 1};
  const std::vector<Loop> loops = medial_axis_loops(pair, solid, options);
  REQUIRE(loops.size() == 1);
  for (Vec2 p : loops[0]) CHECK(std::abs(std::hypot(p.x, p.y) - 9) <= 0.002);
}

TEST_CASE("fairing_puts_the_contour_on_the_axis_of_the_boundary_polygons") {
  // The medial axis between two loops is where the distances to them are equal. A 90-gon in
  // a 70-gon (edges 0.7 and 0.56 mm, vertices at unrelated angles), sampled 0.5 mm apart:
  // unfaired, a vertex is the midpoint of a Delaunay edge and an edge a chord (measured: the
  // distances differ by up to 7 um); faired, vertices and edge midpoints are on the axis to
  // 1 um, so the distances agree to 2 um.
  const Loop outer = circle(10, 90), inner = circle(8, 70, {}, true);
  const BoundaryPair pair{outer, {inner}};
  const std::vector<char> solid{0, 1};
  const Region to_outer{{outer}}, to_inner{{inner}};
  MaOptions options;
  options.spacing = 0.5;
  const auto worst = [&](bool fairing) {
    options.fairing = fairing;
    const std::vector<Loop> loops = medial_axis_loops(pair, solid, options);
    REQUIRE(loops.size() == 1);
    double off = 0;
    for (std::size_t i = 0; i < loops[0].size(); ++i) {
      const Vec2 p = loops[0][i], q = loops[0][(i + 1) % loops[0].size()];
      for (Vec2 x : {p, 0.5 * (p + q)}) {
        off = std::max(off, std::abs(distance_to_boundary(x, to_outer) - distance_to_boundary(x, to_inner)));
      }
    }
    return off;
  };
  CHECK(worst(true) <= 0.002);
  CHECK(worst(false) > 0.005);
}

TEST_CASE("strip_with_solid_outside_gives_a_clockwise_loop") {
  // A round hole through a plate: the strip round the hole wall has solid outside it.
  const BoundaryPair pair{circle(3.1, 360), {circle(2.9, 360, {}, true)}};
  const std::vector<char> solid{1, 0};
  const std::vector<Loop> loops = medial_axis_loops(pair, solid);
  REQUIRE(loops.size() == 1);
  CHECK(signed_area(loops[0]) < 0);
  for (Vec2 p : loops[0]) CHECK(std::abs(std::hypot(p.x, p.y) - 3) <= 0.001);
}

TEST_CASE("strip_with_three_loops_gives_one_closed_loop_round_both_holes") {
  // Two solid bodies that merge inside the slab: one outer loop, two holes. The contour must
  // not branch: one loop, equidistant from the outer loop and the nearer hole.
  const Loop outer = circle(10, 720);
  const Loop left = circle(2, 240, {-4, 0}, true), right = circle(2, 240, {4, 0}, true);
  const BoundaryPair pair{outer, {left, right}};
  const std::vector<char> solid{0, 1, 1};
  const std::vector<Loop> loops = medial_axis_loops(pair, solid);
  REQUIRE(loops.size() == 1);
  CHECK(signed_area(loops[0]) > 0);
  const Region holes{{left, right}};
  const Region rim{{outer}};
  for (Vec2 p : loops[0]) {
    const double to_rim = distance_to_boundary(p, rim);
    const double to_hole = distance_to_boundary(p, holes);
    CHECK(std::abs(to_rim - to_hole) <= 0.003);
  }
  // Both holes are inside it.
  const Region contour{loops};
  CHECK(point_in_region(contour, {-4, 0}));
  CHECK(point_in_region(contour, {4, 0}));
  CHECK_FALSE(point_in_region(contour, {0, 9.9}));
}

TEST_CASE("strip_with_two_empty_holes_gives_one_clockwise_loop_round_both") {
  // Two holes through a plate that merge inside the slab: the territories of the two holes
  // touch, so the contour is one hole round both; a septum between them that ends inside
  // the slab is not kept (it is part of the strip, not a wall of the layer).
  const Loop outer = circle(10, 720);
  const Loop left = circle(2, 240, {-4, 0}, true), right = circle(2, 240, {4, 0}, true);
  const BoundaryPair pair{outer, {left, right}};
  const std::vector<char> solid{1, 0, 0};
  const std::vector<Loop> loops = medial_axis_loops(pair, solid);
  REQUIRE(loops.size() == 1);
  CHECK(signed_area(loops[0]) < 0);
  const Region holes{{left, right}};
  const Region rim{{outer}};
  for (Vec2 p : loops[0]) {
    CHECK(std::abs(distance_to_boundary(p, rim) - distance_to_boundary(p, holes)) <= 0.003);
  }
}

TEST_CASE("cap_and_malformed_labels_give_no_loops") {
  const BoundaryPair disc{circle(5, 100), {}};
  CHECK(medial_axis_loops(disc, std::vector<char>{0}).empty());
  const BoundaryPair ring{circle(5, 100), {circle(4, 100, {}, true)}};
  CHECK(medial_axis_loops(ring, std::vector<char>{1, 1}).empty());
  CHECK(medial_axis_loops(ring, std::vector<char>{1}).empty());
  CHECK(medial_axis_loops(BoundaryPair{}, std::vector<char>{0}).empty());
}

TEST_CASE("max_points_caps_the_samples") {
  MaOptions options;
  options.spacing = 0.001;  // 125 000 points if uncapped
  options.max_points = 5000;
  MaStats stats;
  const BoundaryPair pair{circle(10, 720), {circle(8, 720, {}, true)}};
  const std::vector<Loop> loops = medial_axis_loops(pair, std::vector<char>{0, 1}, options, &stats);
  CHECK(stats.samples <= 5000 + 2);
  CHECK(stats.samples >= 1440);
  REQUIRE(loops.size() == 1);
  for (Vec2 p : loops[0]) CHECK(std::abs(std::hypot(p.x, p.y) - 9) <= 0.0011);
}

// ---- whole layers of closed-form solids ----

TEST_CASE("cone_ma_equals_mid") {
  // A cone's flank is linear, at angle alpha to the horizontal: for every layer the strip lies
  // between the n-gons at z_lo and z_hi, and its axis is the mid section (see the top).
  const int n = 64;
  const double c = std::cos(kPi / n);
  for (double alpha_degrees : {20.0, 45.0, 70.0}) {
    const double radius = 10, height = radius * std::tan(alpha_degrees * kPi / 180);
    const solids::Solid cone = solids::cone(radius, height, n);
    const double t = 0.2;
    LayerStack stack(cone.mesh, uniform_layers(height, t));
    for (std::size_t i = 0; i + 2 < stack.size(); i += 3) {
      const Layer& layer = stack.layers()[i];
      const double r_lo = radius * (1 - layer.z_lo / height), r_hi = radius * (1 - layer.z_hi / height);
      const Region ma = ma_contour(stack, i);
      const Region mid = cone.section(layer.z_mid());
      CAPTURE(alpha_degrees);
      CAPTURE(i);
      REQUIRE(ma.loops.size() == 1);
      CHECK(signed_area(ma.loops[0]) > 0);
      const double corner = (r_lo - r_hi) * (1 - c) / (2 * (1 + c));
      CHECK(boundary_hausdorff(ma, mid) <= corner + kStripAllowance);
    }
  }
}

TEST_CASE("cylinder_ma_equals_its_contour") {
  // A vertical wall: lower = upper contour, the footprint a ring 2 * margin wide round it.
  // Such a strip's contour is that section itself, exactly.
  const solids::Solid cylinder = solids::cylinder(5, 12, 48, {1, -2, 0});
  LayerStack stack(cylinder.mesh, uniform_layers(12, 0.3));
  for (std::size_t i : {std::size_t{0}, std::size_t{7}, stack.size() - 1}) {
    MaStats stats;
    const Region ma = ma_contour(stack, i, {}, stats);
    CHECK(stats.walls == 1);
    CHECK(stats.samples == 0);
    REQUIRE(ma.loops.size() == 1);
    CHECK(boundary_hausdorff(ma, cylinder.section(stack.layers()[i].z_mid())) <= 1e-6);
  }
}

TEST_CASE("nearly_vertical_wall_is_not_taken_for_a_wall") {
  // A frustum whose radius changes by 0.05 mm over a 0.3 mm layer: its strip is 50 um wide,
  // far more than a wall's few margins, so the axis is computed: the mean n-gon.
  const int n = 48;
  const solids::Solid frustum = solids::frustum(5.5, 5, 3, n);
  LayerStack stack(frustum.mesh, uniform_layers(3, 0.3));
  MaStats stats;
  const Region ma = ma_contour(stack, 4, {}, stats);
  CHECK(stats.walls == 0);
  CHECK(stats.samples > 0);
  const Layer& layer = stack.layers()[4];
  const double r_lo = 5.5 - 0.5 * layer.z_lo / 3, r_hi = 5.5 - 0.5 * layer.z_hi / 3;
  const Region mean{{solids::regular_polygon(n, 0.5 * (r_lo + r_hi))}};
  CHECK(boundary_hausdorff(ma, mean) <= kStripAllowance);
}

TEST_CASE("sphere_layer_ma_is_the_mean_radius_polygon_between_lower_and_upper") {
  // UV sphere: between ring heights each band is a frustum, so a layer's strip lies between
  // the n-gons of its lower and upper sections, and its axis is the n-gon of their mean
  // circumradius, even when a ring height falls inside the layer (then it is not the mid
  // section: the flank bends there).
  const int n = 64;
  const double c = std::cos(kPi / n);
  const solids::Solid sphere = solids::sphere(10, n, 32, {0, 0, 10});
  LayerStack stack(sphere.mesh, uniform_layers(20, 0.15));
  int checked = 0;
  for (std::size_t i = 5; i < stack.size() - 5; i += 11) {
    const Layer& layer = stack.layers()[i];
    if (std::abs(layer.z_lo - 10) < 0.5 || std::abs(layer.z_hi - 10) < 0.5) continue;  // equator
    const double r_lo = section_radius(sphere.section(layer.z_lo), true);
    const double r_hi = section_radius(sphere.section(layer.z_hi), true);
    const Region ma = ma_contour(stack, i);
    CAPTURE(i);
    REQUIRE(ma.loops.size() == 1);
    const Region mean{{solids::regular_polygon(n, 0.5 * (r_lo + r_hi))}};
    const double corner = std::abs(r_lo - r_hi) * (1 - c) / (2 * (1 + c));
    CHECK(boundary_hausdorff(ma, mean) <= corner + kStripAllowance);
    // Between the lower and upper contours.
    const double r = max_radius(ma.loops[0]);
    CHECK(r >= std::min(r_lo, r_hi));
    CHECK(r <= std::max(r_lo, r_hi));
    ++checked;
  }
  CHECK(checked >= 8);
}

TEST_CASE("sphere_equator_layer_ma_lies_between_the_sections") {
  // A layer spanning the equator ring: the footprint runs from the smaller of the lower and
  // upper sections out to the equator n-gon (the silhouette), and the axis is half-way.
  const int n = 64;
  const solids::Solid sphere = solids::sphere(10, n, 32, {0, 0, 10});
  std::vector<Layer> layers{{9.9, 10.2}};
  LayerStack stack(sphere.mesh, layers);
  const double r_lo = section_radius(sphere.section(9.9), true);
  const double r_hi = section_radius(sphere.section(10.2), true);
  const Region ma = ma_contour(stack, 0);
  REQUIRE(ma.loops.size() == 1);
  const Region mean{{solids::regular_polygon(n, 0.5 * (std::min(r_lo, r_hi) + 10))}};
  CHECK(boundary_hausdorff(ma, mean) <= 0.001 + kStripAllowance);
}

// Caps (ma_contour.cpp): the mid section inside the island, the least volume deviation any
// layer can have there; the section half-way through the feature if the middle misses it.
TEST_CASE("sphere_bottom_layer_cap_is_the_mid_section") {
  // The first layer holds the pole: the footprint is the n-gon of the section at z_hi with
  // nothing solid beside it, a cap.
  const solids::Solid sphere = solids::sphere(10, 64, 32, {0, 0, 10});
  LayerStack stack(sphere.mesh, uniform_layers(20, 0.15));
  MaStats stats;
  const Region ma = ma_contour(stack, 0, {}, stats);
  CHECK(stats.caps == 1);
  REQUIRE(ma.loops.size() == 1);
  CHECK(boundary_hausdorff(ma, sphere.section(0.075)) <= 1e-6);
}

TEST_CASE("small_sphere_inside_one_layer_is_kept") {
  // A ball spanning [0.15, 0.25] inside the layer [0.1, 0.4]: the middle (0.25) only touches
  // its pole, so the mid section is empty and `mid` would lose it. The cap is cut half-way
  // through its own height, at its equator.
  const solids::Solid ball = solids::sphere(0.05, 32, 8, {1, 2, 0.2});
  LayerStack stack(ball.mesh, {Layer{0.1, 0.4}});
  MaStats stats;
  const Region ma = ma_contour(stack, 0, {}, stats);
  CHECK(stats.caps == 1);
  CHECK(stack.mid(0).loops.empty());
  REQUIRE(ma.loops.size() == 1);
  CHECK(boundary_hausdorff(ma, ball.section(0.2), 0.005) <= 1e-6);
}

TEST_CASE("torus_layer_ma_is_the_annulus_of_mean_radii") {
  // Torus lying flat, tube a 16-gon: between tube vertex heights the section is an annulus of
  // two n-gons whose circumradii are linear in z; the slab has two strips (outer wall, inner
  // wall), the solid between them: the MA is an annulus, outer CCW at the mean outer radius,
  // hole CW at the mean inner radius.
  const int n = 48;
  const double c = std::cos(kPi / n);
  const solids::Solid torus = solids::torus(10, 3, n, 16, {0, 0, 3});
  LayerStack stack(torus.mesh, uniform_layers(6, 0.15));
  for (std::size_t i : {std::size_t{3}, std::size_t{12}, std::size_t{25}, std::size_t{33}}) {
    const Layer& layer = stack.layers()[i];
    const Region lower = torus.section(layer.z_lo), upper = torus.section(layer.z_hi);
    const double outer = 0.5 * (section_radius(lower, true) + section_radius(upper, true));
    const double inner = 0.5 * (section_radius(lower, false) + section_radius(upper, false));
    const Region ma = ma_contour(stack, i);
    CAPTURE(i);
    REQUIRE(count_ccw(ma) == 1);
    REQUIRE(count_cw(ma) == 1);
    Loop hole = solids::regular_polygon(n, inner);
    std::reverse(hole.begin(), hole.end());
    const Region mean{{solids::regular_polygon(n, outer), hole}};
    const double width = std::abs(section_radius(lower, true) - section_radius(upper, true));
    CHECK(boundary_hausdorff(ma, mean) <= width * (1 - c) / (2 * (1 + c)) + kStripAllowance);
  }
}

TEST_CASE("torus_top_cap_below_the_middle_is_cut_half_way_through_the_feature") {
  // The tube's top vertex ring lies at z = 6. In the layer [5.95, 6.3] the torus ends in the
  // lower seventh, the mid section (6.125) is empty and the feature would be lost: the cap is
  // cut half-way through its own height, at (5.95 + 6) / 2.
  const solids::Solid torus = solids::torus(10, 3, 48, 16, {0, 0, 3});
  LayerStack stack(torus.mesh, {Layer{5.95, 6.3}});
  MaStats stats;
  const Region ma = ma_contour(stack, 0, {}, stats);
  CHECK(stats.caps == 1);
  CHECK(stack.mid(0).loops.empty());
  REQUIRE(count_ccw(ma) == 1);
  REQUIRE(count_cw(ma) == 1);
  CHECK(boundary_hausdorff(ma, torus.section(5.975)) <= 1e-6);
}

TEST_CASE("torus_top_cap_above_the_middle_is_the_mid_section") {
  const solids::Solid torus = solids::torus(10, 3, 48, 16, {0, 0, 3});
  LayerStack stack(torus.mesh, {Layer{5.76, 6.08}});
  const Region ma = ma_contour(stack, 0);
  REQUIRE(count_ccw(ma) == 1);
  REQUIRE(count_cw(ma) == 1);
  CHECK(boundary_hausdorff(ma, torus.section(5.92)) <= 1e-6);
}

TEST_CASE("cube_with_hole_ma_is_the_square_and_a_clockwise_hole") {
  const solids::Solid cube = solids::cube_with_square_hole(20, 8);
  LayerStack stack(cube.mesh, uniform_layers(20, 0.25));
  for (std::size_t i : {std::size_t{0}, std::size_t{40}, stack.size() - 1}) {
    MaStats stats;
    const Region ma = ma_contour(stack, i, {}, stats);
    CHECK(stats.walls == 2);
    REQUIRE(count_ccw(ma) == 1);
    REQUIRE(count_cw(ma) == 1);
    CHECK(boundary_hausdorff(ma, cube.section(stack.layers()[i].z_mid())) <= 1e-6);
    CHECK(area(ma) == doctest::Approx(20 * 20 - 8 * 8).epsilon(1e-9));
  }
}

TEST_CASE("overhang_beginning_at_the_layer_bottom_is_not_a_strip") {
  // A 20 x 12 box on an 8 x 6 stem, the step face exactly at z_lo = 5: it bounds the slab, so
  // the layer is the bar's section, not an axis half-way between bar and stem.
  const solids::Solid step = solids::stepped_box({8, 6}, 5, {20, 12}, 7);
  LayerStack stack(step.mesh, uniform_layers(12, 0.25));
  const Region ma = ma_contour(stack, 20);  // [5, 5.25]
  CHECK(boundary_hausdorff(ma, step.section(5.1)) <= kStripAllowance);
}

TEST_CASE("layers_beside_the_part_are_empty") {
  const solids::Solid cube = solids::cube(10);
  LayerStack stack(cube.mesh, {{{10, 10.2}, {-1, 0}, {3, 3}}});
  CHECK(ma_contour(stack, 0).loops.empty());  // above the top face
  CHECK(ma_contour(stack, 1).loops.empty());  // below the bottom
  CHECK(ma_contour(stack, 2).loops.empty());  // zero thickness
  CHECK(ma_contour(stack, 3).loops.empty());  // no such layer
  const Mesh nothing;
  LayerStack empty(nothing, uniform_layers(1, 0.2));
  CHECK(ma_contour(empty, 0).loops.empty());
}

TEST_CASE("ma_contour_is_deterministic_across_threads") {
  const solids::Solid torus = solids::torus(10, 3, 48, 16, {0, 0, 3});
  LayerStack stack(torus.mesh, uniform_layers(6, 0.15));
  std::vector<Region> sequential(stack.size()), parallel(stack.size());
  for (std::size_t i = 0; i < stack.size(); ++i) sequential[i] = ma_contour(stack, i);
  tbb::parallel_for(std::size_t{0}, stack.size(),
                    [&](std::size_t i) { parallel[i] = ma_contour(stack, i); });
  for (std::size_t i = 0; i < stack.size(); ++i) {
    REQUIRE(sequential[i].loops.size() == parallel[i].loops.size());
    for (std::size_t k = 0; k < sequential[i].loops.size(); ++k) {
      CHECK(sequential[i].loops[k].size() == parallel[i].loops[k].size());
      CHECK(std::equal(sequential[i].loops[k].begin(), sequential[i].loops[k].end(),
                       parallel[i].loops[k].begin()));
    }
  }
}

// ---- where the strip is not a strip (ma_contour.h): floating features and pockets ----

TEST_CASE("wavy_underside_in_one_slab_follows_the_mid_section") {
  // A solid of revolution whose nearly flat underside rises and falls round the layer's middle
  // (the bunny's hole-filled base in closed form): profile (rho, z) = (0, 0), (1, 0.1),
  // (3, 0.5), (5, 0.3), (7, 0.55), (8, 0.25), then up the wall at rho = 8. In the layer
  // [0.2, 0.6] the footprint is the annulus from rho = 1.5 (where the underside enters the
  // layer; inside it every column is full: solid) to the wall at 8 (empty outside): a strip
  // 6.5 mm wide whose axis is the circle of radius 4.75. But the underside crosses the middle
  // (0.4) at rho = 2.5, 4, 5.8 and 7.5: the mid section is the disc 2.5, the ring 4-5.8 and
  // the ring 7.5-8, and all but the disc are faces of it that hold none of the island's
  // loops. With the floating-feature rule the contour is exactly the mid section.
  const int n = 48;
  const solids::Solid wavy = solids::revolve(
      {{0, 0}, {1, 0.1}, {3, 0.5}, {5, 0.3}, {7, 0.55}, {8, 0.25}, {8, 2}, {0, 2}}, n);
  LayerStack stack(wavy.mesh, {Layer{0.2, 0.6}});
  const Region mid = wavy.section(0.4);
  REQUIRE(mid.loops.size() == 5);
  MaStats stats;
  const Region ma = ma_contour(stack, 0, {}, stats);
  CHECK(stats.caps == 0);
  CHECK(stats.features == 4);
  CHECK(boundary_hausdorff(ma, mid) <= 1e-5);
  CHECK(area(ma) == doctest::Approx(area(mid)).epsilon(1e-6));
  // Without the rule: the axis of the 6.5 mm strip, the mean circle.
  MaOptions basic;
  basic.floating_features = false;
  basic.pockets = false;
  const Region axis = ma_contour(stack, 0, basic);
  REQUIRE(axis.loops.size() == 1);
  const double corner = 6.5 * (1 - std::cos(kPi / n)) / (2 * (1 + std::cos(kPi / n)));
  CHECK(boundary_hausdorff(axis, Region{{solids::regular_polygon(n, 4.75)}}) <= corner + kStripAllowance);
  // D: the wall at rho = 8 is 3.25 from the axis; the mid section has a wall wherever the
  // underside crosses the middle, and the farthest surface is where the underside enters the
  // layer, rho = 1.5, 1 from the wall at 2.5.
  CHECK(layer_metrics(stack, 0, axis).distance == doctest::Approx(3.25).epsilon(0.002));
  const double d = layer_metrics(stack, 0, ma).distance;
  CHECK(d == doctest::Approx(layer_metrics(stack, 0, mid).distance).epsilon(1e-6));
  CHECK(d == doctest::Approx(1).epsilon(0.005));
}

TEST_CASE("ball_above_a_cone_flank_inside_the_slab_is_kept") {
  // A tail tip that begins and ends inside a slab but belongs to a larger island: a ball of
  // radius 0.2 centred at (6.1, 0, 4.35), 0.12 mm above the flank of a 45-degree cone
  // (radius 10, height 10), inside the layer [4, 4.6]. Its projection overlaps the cone's
  // strip (rho 5.4 to 6), so the footprint is one island, the ball a lobe of its empty outer
  // loop. The axis of the strip stays near rho = 5.7 and never reaches the ball; its section
  // at the middle (4.3) is a face of the mid section that holds none of the island's loops,
  // and is kept.
  const int n = 64;
  const solids::Solid cone = solids::cone(10, 10, n);
  const solids::Solid ball = solids::sphere(0.2, 32, 16, {6.1, 0, 4.35});
  const solids::Solid part = solids::combine(cone, ball);
  LayerStack stack(part.mesh, {Layer{4, 4.6}});
  REQUIRE(boundary_pairs(slab_footprint(slab_of(stack, 0))).size() == 1);
  const Region tip = ball.section(4.3);
  REQUIRE(tip.loops.size() == 1);
  MaStats stats;
  const Region ma = ma_contour(stack, 0, {}, stats);
  CHECK(stats.features == 1);
  CHECK(intersection_area(ma, tip) == doctest::Approx(area(tip)).epsilon(1e-6));
  // The cone's part is still its axis, the mean 64-gon (away from the ball, which the axis
  // bends round), and the region is the two of them.
  CHECK(area(ma) == doctest::Approx(area(Region{{solids::regular_polygon(n, 5.7)}}) + area(tip)).epsilon(2e-3));
  MaOptions basic;
  basic.floating_features = false;
  basic.pockets = false;
  CHECK(intersection_area(ma_contour(stack, 0, basic), tip) < 1e-3 * area(tip));
}

TEST_CASE("septum_ending_inside_the_slab_is_cut_where_the_mid_section_cuts_it") {
  // A saddle: a 10 x 10 block (x, y in [-5, 5], z in [0, 4]) with a V-groove cut along x from
  // its top down to z = 1 (flanks y = +-2 (z - 1) / 3). In the layer [0.9, 1.5] the block is
  // whole below z = 1 and two bars above it: the footprint is the ring of the outer walls and
  // the groove's band |y| <= 1/3, one island whose two holes (the bars, solid) merge across
  // the band, a septum between two solid loops whose ends meet the empty outer loop. The
  // solid loops are nearer each other (2/3) than the band's ends (10), so the axis fills the
  // band and leaves its surface 4.7 mm from any wall. The band is a pocket; the mid section
  // (1.2) cuts it with a channel |y| < 2/15, whose walls are 1/5 from the band's edges
  // (1/3 - 2/15) and 2/15 from the groove's bottom: D = 1/5. The pocket takes the mid section.
  const solids::Solid grooved =
      solids::lying_prism({{-5, 0}, {5, 0}, {5, 4}, {2, 4}, {0, 1}, {-2, 4}, {-5, 4}}, -5, 5);
  LayerStack stack(grooved.mesh, {Layer{0.9, 1.5}});
  const Region mid = grooved.section(1.2);
  REQUIRE(mid.loops.size() == 2);
  MaStats stats;
  const Region ma = ma_contour(stack, 0, {}, stats);
  CHECK(stats.pockets >= 1);
  CHECK(count_ccw(ma) == 2);  // cut, as the section at the middle is
  const double d_mid = layer_metrics(stack, 0, mid).distance;
  CHECK(d_mid == doctest::Approx(0.2).epsilon(1e-3));
  CHECK(layer_metrics(stack, 0, ma).distance <= d_mid + 0.002);
  MaOptions basic;
  basic.pockets = false;
  const Region axis = ma_contour(stack, 0, basic);
  CHECK(count_ccw(axis) == 1);
  CHECK(layer_metrics(stack, 0, axis).distance > 4);
  CHECK(layer_metrics(stack, 0, ma).volume_deviation < layer_metrics(stack, 0, axis).volume_deviation);
}

TEST_CASE("square_frustum_corner_takes_the_mid_section") {
  // Where the axis is worse than the mid section on a plain strip: the corners of a square
  // frustum. Layer [1, 1.5] of a 4-gon frustum (circumradius 10 at z = 0, 6 at z = 4):
  // circumradii 9 and 8.5, a strip w = 0.5 / sqrt(2) wide along the sides. The mid section's
  // corner is 0.25 = (9 - 8.5) / 2 from the outer corner O, its sides w/2 from everything
  // else: D_mid = 0.25. The axis bends round the inner corner I (a parabola with focus I) and
  // meets the outer corner's bisector at J, equidistant from I and from O's two sides:
  // |OJ| = (9 - 8.5)(2 - sqrt(2)) = 0.2929. O is non-contributing (its Voronoi cell ends
  // before the axis), farther from the walls than any contributing sample (|IJ| = 0.2071):
  // the pocket round it takes the mid section, and D falls to mid's.
  const solids::Solid frustum = solids::frustum(10, 6, 4, 4);
  LayerStack stack(frustum.mesh, {Layer{1, 1.5}});
  const Region mid = frustum.section(1.25);
  CHECK(layer_metrics(stack, 0, mid).distance == doctest::Approx(0.25).epsilon(1e-3));
  MaOptions basic;
  basic.pockets = false;
  CHECK(layer_metrics(stack, 0, ma_contour(stack, 0, basic)).distance ==
        doctest::Approx(0.5 * (2 - std::sqrt(2.0))).epsilon(0.01));
  MaStats stats;
  const Region ma = ma_contour(stack, 0, {}, stats);
  CHECK(stats.pockets == 4);
  CHECK(layer_metrics(stack, 0, ma).distance <= 0.25 + 0.002);
}

// ---- the paper's part ----

TEST_CASE("bunny_every_layer_is_closed_valid_and_touches_every_island") {
  // The Stanford bunny placed as in the paper (Y up, metres, 50 mm tall), 334 layers of
  // 0.15 mm. Every layer's contour must be closed loops (a Loop is closed by construction;
  // here: at least 3 points and some area), valid (outer loops CCW, holes CW, nested as their
  // orientation says, unchanged by Clipper's normalisation: no self-intersections or
  // overlaps), and must touch every island of the slab's footprint, holes included.
  Placement placement;
  placement.units_to_mm = 1000;
  placement.up = Axis::y;
  placement.height = 50;
  const Mesh bunny = place(repair(read_stl(std::string(MAHOST_DATA_DIR) + "/bunny.stl")), placement);
  LayerStack stack(bunny, uniform_layers(50, 0.15));
  REQUIRE(stack.size() == 334);
  std::vector<Region> contours(stack.size());
  std::vector<std::vector<BoundaryPair>> islands(stack.size());
  tbb::parallel_for(std::size_t{0}, stack.size(), [&](std::size_t i) {
    contours[i] = ma_contour(stack, i);
    islands[i] = boundary_pairs(slab_footprint(slab_of(stack, i)));
  });
  std::size_t loops = 0, holes = 0, touched = 0, total_islands = 0;
  for (std::size_t i = 0; i < stack.size(); ++i) {
    CAPTURE(i);
    const Region& r = contours[i];
    REQUIRE_FALSE(r.loops.empty());
    for (const Loop& loop : r.loops) {
      CHECK(loop.size() >= 3);
      CHECK(std::abs(signed_area(loop)) > 0);
      // Depth of nesting from the other loops: even for outer loops (CCW), odd for holes.
      int depth = 0;
      for (const Loop& other : r.loops) {
        if (&other != &loop && point_in_region(Region{{other}}, loop[0])) ++depth;
      }
      CHECK((signed_area(loop) > 0) == (depth % 2 == 0));
      holes += signed_area(loop) < 0;
    }
    loops += r.loops.size();
    const ClipperLib::Paths normalised = geometry::clipper::union_nonzero(to_clipper(r));
    CHECK(normalised.size() == r.loops.size());
    CHECK(area(from_clipper(normalised)) == doctest::Approx(area(r)).epsilon(1e-9));
    for (const BoundaryPair& pair : islands[i]) {
      Region ring{{pair.outer}};
      ring.loops.insert(ring.loops.end(), pair.inner.begin(), pair.inner.end());
      bool touches = false;
      for (const Loop& loop : r.loops) {
        for (std::size_t k = 0; k < loop.size() && !touches; ++k) touches = point_in_region(ring, loop[k]);
      }
      CHECK(touches);
      touched += touches;
      ++total_islands;
    }
  }
  MESSAGE("bunny: " << loops << " contour loops (" << holes << " holes), " << touched << " of "
                    << total_islands << " footprint islands touched");
  CHECK(touched == total_islands);
}

}  // namespace ma_contour_test
