// The slab of a layer and its footprint (slab.h), against closed forms.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>
#include <span>
#include <vector>

#include "geometry/slicing/layer_stack.h"
#include "geometry/core/clipper.h"
#include "geometry/core/polygon.h"
#include "geometry/slab/slab.h"
#include "support/solids.h"

namespace slab_test {

using namespace geometry;

namespace {

constexpr double kPi = std::numbers::pi;

double area3(std::span<const Vec3> polygon) {
  Vec3 twice{};
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    twice = twice + cross(polygon[i] - polygon[0], polygon[i + 1] - polygon[0]);
  }
  return 0.5 * std::sqrt(dot(twice, twice));
}

Vec3 normal(const std::vector<Vec3>& polygon) {
  Vec3 twice{};
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
    twice = twice + cross(polygon[i] - polygon[0], polygon[i + 1] - polygon[0]);
  }
  return twice;
}

bool same(Vec3 a, Vec3 b) {
  return std::abs(a.x - b.x) < 1e-12 && std::abs(a.y - b.y) < 1e-12 && std::abs(a.z - b.z) < 1e-12;
}

int count_ccw(const Region& r) {
  int n = 0;
  for (const Loop& l : r.loops) n += signed_area(l) > 0;
  return n;
}

// The footprint as its definition reads, from Clipper alone: every facet's projection turned
// counter-clockwise, their non-zero union, grown by ClipperOffset (mitred, limit 2). For
// slabs without edge-on facets.
ClipperLib::Paths footprint_by_definition(const Slab& slab, double margin) {
  ClipperLib::Paths projections;
  for (const auto& facet : slab.facets) {
    ClipperLib::Path projected;
    for (const Vec3& v : facet) projected.push_back(to_clipper(Vec2{v.x, v.y}));
    if (!ClipperLib::Orientation(projected)) ClipperLib::ReversePath(projected);
    projections.push_back(std::move(projected));
  }
  return clipper::library_offset(clipper::union_nonzero(projections), margin, ClipperLib::jtMiter,
                                 ClipperLib::etClosedPolygon, 0.25 / kClipperScale);
}

// Whether slab_footprint is the footprint by definition as a set, to Clipper's rounding: the
// two differ by at most `units` Clipper units (nm) across their boundary on average, and
// have as many loops. Checked on each slab of the stack that holds facets.
void check_footprint_is_its_definition(const LayerStack& stack, double units) {
  for (std::size_t i = 0; i < stack.size(); ++i) {
    const Slab slab = slab_of(stack, i);
    if (slab.facets.empty()) continue;
    CAPTURE(i);
    const ClipperLib::Paths expected = footprint_by_definition(slab, kFootprintMargin);
    const Region footprint = slab_footprint(slab);
    CHECK(footprint.loops.size() == expected.size());
    const double apart =
        clipper::area_mm2(clipper::symmetric_difference(to_clipper(footprint), expected));
    CHECK(apart <= perimeter(from_clipper(expected)) * units / kClipperScale);
  }
}

}  // namespace

TEST_CASE("clip_to_slab_cuts_a_triangle_through_both_planes_into_a_pentagon") {
  // A below z_lo = 0, B above z_hi = 1, C between. By hand: AB meets z = 0 at (1,0,0) and
  // z = 1 at (2,0,1); BC meets z = 1 at (1,2,1); CA meets z = 0 at (0,2,0).
  const std::vector<Vec3> triangle{{0, 0, -1}, {3, 0, 2}, {0, 3, 0.5}};
  const std::vector<Vec3> piece = clip_to_slab(triangle, 0, 1);
  REQUIRE(piece.size() == 5);
  const std::vector<Vec3> expected{{1, 0, 0}, {2, 0, 1}, {1, 2, 1}, {0, 3, 0.5}, {0, 2, 0}};
  std::size_t start = 0;
  while (start < 5 && !same(piece[start], expected[0])) ++start;
  REQUIRE(start < 5);
  for (std::size_t k = 0; k < 5; ++k) CHECK(same(piece[(start + k) % 5], expected[k]));
  // Orientation kept: the normals point the same way.
  CHECK(dot(normal(piece), normal(triangle)) > 0);
}

// A face of many corners (clipped on the heap) is cut as a small one (on the stack): the
// rectangle x in [0, 1], z in [-1, 2] in the plane y = 0, with extra corners along its sides,
// cut to [0, 1] is the unit square with the corners at z = 0.5 kept: six corners, area 1.
TEST_CASE("clip_to_slab_cuts_a_many_cornered_face_as_a_few_cornered_one") {
  const std::vector<Vec3> ten{{0, 0, -1},  {1, 0, -1}, {1, 0, -0.5}, {1, 0, 0.5}, {1, 0, 1.5},
                              {1, 0, 2},   {0, 0, 2},  {0, 0, 1.5},  {0, 0, 0.5}, {0, 0, -0.5}};
  std::vector<Vec3> eleven = ten;
  eleven.insert(eleven.begin() + 1, Vec3{0.5, 0, -1});
  const std::vector<Vec3> expected{{1, 0, 0}, {1, 0, 0.5}, {1, 0, 1},
                                   {0, 0, 1}, {0, 0, 0.5}, {0, 0, 0}};
  for (const std::vector<Vec3>& face : {ten, eleven}) {
    CAPTURE(face.size());
    const std::vector<Vec3> piece = clip_to_slab(face, 0, 1);
    REQUIRE(piece.size() == expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) CHECK(same(piece[k], expected[k]));
    CHECK(area3(piece) == doctest::Approx(1.0));
  }
}

TEST_CASE("clip_to_slab_keeps_what_lies_inside_and_drops_what_bounds_it") {
  const std::vector<Vec3> inside{{0, 0, 0.2}, {1, 0, 0.3}, {0, 1, 0.8}};
  CHECK(clip_to_slab(inside, 0, 1).size() == 3);
  const std::vector<Vec3> flat_inside{{0, 0, 0.5}, {1, 0, 0.5}, {0, 1, 0.5}};
  CHECK(clip_to_slab(flat_inside, 0, 1).size() == 3);
  const std::vector<Vec3> flat_on_bottom{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  CHECK(clip_to_slab(flat_on_bottom, 0, 1).empty());
  const std::vector<Vec3> flat_on_top{{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  CHECK(clip_to_slab(flat_on_top, 0, 1).empty());
  const std::vector<Vec3> touching_along_an_edge{{0, 0, 1}, {1, 0, 1}, {0, 1, 3}};
  CHECK(clip_to_slab(touching_along_an_edge, 0, 1).empty());
  const std::vector<Vec3> touching_at_a_corner{{0, 0, 1}, {1, 0, 2}, {0, 1, 3}};
  CHECK(clip_to_slab(touching_at_a_corner, 0, 1).empty());
  const std::vector<Vec3> beside{{0, 0, 2}, {1, 0, 2}, {0, 1, 3}};
  CHECK(clip_to_slab(beside, 0, 1).empty());
  CHECK(clip_to_slab(std::vector<Vec3>{}, 0, 1).empty());
}

TEST_CASE("cube_slab_is_its_four_walls_even_at_the_bottom_and_top") {
  // The bottom face lies on z_lo of the first layer and the top face on z_hi of the last:
  // they bound those slabs. Every layer holds the 8 wall triangles' pieces, 4 * 10 * t of area.
  const solids::Solid cube = solids::cube(10);
  LayerStack stack(cube.mesh, uniform_layers(10, 0.5));
  for (std::size_t i : {std::size_t{0}, std::size_t{7}, stack.size() - 1}) {
    const Slab slab = slab_of(stack, i);
    CHECK(slab.z_lo == stack.layers()[i].z_lo);
    CHECK(slab.z_hi == stack.layers()[i].z_hi);
    REQUIRE(slab.facets.size() == 8);
    double total = 0;
    for (const auto& facet : slab.facets) {
      total += area3(facet);
      for (const Vec3& v : facet) {
        CHECK(v.z >= slab.z_lo);
        CHECK(v.z <= slab.z_hi);
      }
    }
    CHECK(total == doctest::Approx(4 * 10 * 0.5));
  }
  LayerStack above(cube.mesh, {Layer{10, 10.5}});
  CHECK(slab_of(above, 0).facets.empty());
  CHECK(slab_of(above, 1).facets.empty());  // no such layer
}

TEST_CASE("a_slab_of_straight_walls_is_a_prism_and_one_of_a_lean_or_a_step_is_not") {
  // A cylinder's walls stand straight up, also in the layer whose bottom plane holds the
  // floor and in the one whose top plane holds the lid (those faces bound the slab).
  const solids::Solid cylinder = solids::cylinder(5, 10, 48);
  const LayerStack straight(cylinder.mesh, uniform_layers(10, 0.5));
  for (std::size_t i = 0; i < straight.size(); ++i) CHECK(is_prism(slab_of(straight, i)));
  // A cone's walls lean on every layer.
  const solids::Solid cone = solids::cone(5, 10, 48);
  const LayerStack leaning(cone.mesh, uniform_layers(10, 0.5));
  for (std::size_t i = 0; i < leaning.size(); ++i) CHECK_FALSE(is_prism(slab_of(leaning, i)));
  // A stepped block: the layer holding the step face is not a prism; the one whose bottom
  // plane holds it is (the lower box's top bounds it), as is every other layer.
  const solids::Solid steps = solids::stepped_box({20, 20}, 4, {10, 10}, 4);
  const LayerStack across(steps.mesh, {Layer{1, 1.4}, Layer{3.8, 4.2}});
  const LayerStack above(steps.mesh, {Layer{4, 4.4}});
  CHECK(is_prism(slab_of(across, 0)));
  CHECK_FALSE(is_prism(slab_of(across, 1)));
  CHECK(is_prism(slab_of(above, 0)));
  // Nothing in it: no prism (there is no section to be exact).
  CHECK_FALSE(is_prism(Slab{}));
}

TEST_CASE("vertical_wall_footprint_is_a_ring_twice_the_margin_wide") {
  // Each wall projects to a segment; grown by the margin d with square ends they make the
  // square of side s + 2d minus the square of side s - 2d: area (s+2d)^2 - (s-2d)^2 = 8 s d.
  const solids::Solid cube = solids::cube(10);
  LayerStack stack(cube.mesh, uniform_layers(10, 0.5));
  const Region footprint = slab_footprint(slab_of(stack, 4));
  REQUIRE(footprint.loops.size() == 2);
  CHECK(count_ccw(footprint) == 1);
  CHECK(area(footprint) == doctest::Approx(8 * 10 * kFootprintMargin).epsilon(1e-4));
}

TEST_CASE("cone_footprint_is_the_annulus_between_lower_and_upper_grown_by_the_margin") {
  // The flank between z_lo and z_hi projects onto the annulus between the n-gons of the two
  // sections; grown by d (mitred), the outer n-gon's apothem becomes a_lo + d, the hole's
  // a_hi - d: area n tan(pi/n) ((a_lo + d)^2 - (a_hi - d)^2).
  const int n = 40;
  const solids::Solid cone = solids::cone(6, 15, n);
  LayerStack stack(cone.mesh, uniform_layers(15, 0.3));
  const std::size_t i = 20;
  const Layer& layer = stack.layers()[i];
  const double c = std::cos(kPi / n), d = kFootprintMargin;
  const double a_lo = 6 * (1 - layer.z_lo / 15) * c, a_hi = 6 * (1 - layer.z_hi / 15) * c;
  const Region footprint = slab_footprint(slab_of(stack, i));
  REQUIRE(footprint.loops.size() == 2);
  CHECK(count_ccw(footprint) == 1);
  const double expected = n * std::tan(kPi / n) * ((a_lo + d) * (a_lo + d) - (a_hi - d) * (a_hi - d));
  // Coordinates are rounded to whole nanometres: the area to perimeter x 1 nm, 1e-4 mm^2.
  CHECK(std::abs(area(footprint) - expected) <= 1e-4);
  // Without the margin the projections' union is the annulus itself.
  const double bare = n * std::tan(kPi / n) * (a_lo * a_lo - a_hi * a_hi);
  CHECK(std::abs(area(slab_footprint(slab_of(stack, i), 0)) - bare) <= 1e-4);
}

TEST_CASE("facets_touching_at_a_point_merge_into_one_island") {
  // Where the lower and upper contours touch, the raw union pinches into pieces that meet in
  // a point; the margin joins them (DESIGN.md §6).
  Slab slab{0, 1, {}};
  slab.facets.push_back({{0, 0, 0.5}, {1, 0, 0.5}, {1, 1, 0.5}});
  slab.facets.push_back({{1, 1, 0.5}, {2, 1, 0.5}, {2, 2, 0.5}});
  CHECK(slab_footprint(slab, 0).loops.size() == 2);
  const Region grown = slab_footprint(slab);
  REQUIRE(grown.loops.size() == 1);
  CHECK(area(grown) > 1.0);
}

TEST_CASE("footprint_is_the_same_whichever_way_facets_face") {
  // A facet seen from below (its normal points down) covers the same ground as from above.
  Slab up{0, 1, {}}, down{0, 1, {}};
  up.facets.push_back({{0, 0, 0.2}, {4, 0, 0.4}, {0, 3, 0.8}});
  down.facets.push_back({{0, 0, 0.2}, {0, 3, 0.8}, {4, 0, 0.4}});
  const double a_up = area(slab_footprint(up)), a_down = area(slab_footprint(down));
  CHECK(a_up == doctest::Approx(a_down));
  CHECK(a_up == doctest::Approx(6).epsilon(1e-2));
  CHECK(area(slab_footprint(up, 0)) == doctest::Approx(6));
}

TEST_CASE("footprint_is_the_grown_union_of_the_projections") {
  // Each slab's boundary chains have no area of their own where facets overlap (the sphere's
  // slab across its equator, seen from above and below; the overhangs that stack in one slab)
  // and the footprint grows them without taking their union first: the same set (slab.h).
  check_footprint_is_its_definition(
      LayerStack(solids::cone(6, 15, 40).mesh, uniform_layers(15, 0.3)), 2);
  check_footprint_is_its_definition(
      LayerStack(solids::sphere(5, 48, 24, {0, 0, 5}).mesh, uniform_layers(10, 0.35, 0.35)), 2);
  // Profile (rho, z): out, in, out and in again within each 0.4 mm layer, so the slab's
  // facets cover the ground up to three times over, some seen from above, some from below.
  const solids::Solid overhangs = solids::revolve(
      {{0, 0}, {4, 0.05}, {2, 0.15}, {5, 0.25}, {3, 0.35}, {6, 0.45}, {2.5, 0.55}, {5.5, 0.7},
       {1, 0.8}, {0, 0.8}},
      36);
  check_footprint_is_its_definition(LayerStack(overhangs.mesh, uniform_layers(0.8, 0.4)), 2);
  check_footprint_is_its_definition(LayerStack(overhangs.mesh, uniform_layers(0.8, 0.1)), 2);
}

TEST_CASE("empty_slab_has_an_empty_footprint") {
  CHECK(slab_footprint(Slab{}).loops.empty());
  const Mesh nothing;
  LayerStack stack(nothing, uniform_layers(1, 0.2));
  CHECK(slab_of(stack, 0).facets.empty());
  CHECK(slab_footprint(slab_of(stack, 0)).loops.empty());
}

}  // namespace slab_test
