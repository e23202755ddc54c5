// The layer stack: layer bounds, and cross-sections by its face index against slice_mesh,
// brute force and the closed forms of the test solids.
#include "geometry/slicing/layer_stack.h"

#include <doctest/doctest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "geometry/core/error.h"
#include "geometry/slicing/slicer.h"
#include "support/solids.h"

namespace layer_stack_test {

using namespace solids;
using geometry::Layer;
using geometry::LayerStack;
using geometry::Region;

namespace {

bool same_region(const Region& a, const Region& b) {
  if (a.loops.size() != b.loops.size()) return false;
  for (std::size_t i = 0; i < a.loops.size(); ++i) {
    if (a.loops[i] != b.loops[i]) return false;
  }
  return true;
}

std::vector<Solid> some_solids() {
  std::vector<Solid> list;
  list.push_back(sphere(12, 40, 20, {0, 0, 12}));
  list.push_back(torus(20, 6, 48, 16, {0, 0, 6}));
  list.push_back(cube_with_round_hole(20, 7, 36));
  list.push_back(combine(tube(6, 8, 10, 24), cylinder(3, 10, 24)));
  list.push_back(stepped_box({8, 6}, 5, {20, 12}, 7));
  list.push_back(bipyramid(5, 7, 0, 4, 10));
  return list;
}

// Heights of every kind: random ones, all vertex heights, and outside the part.
std::vector<double> many_heights(const geometry::Mesh& mesh, std::size_t count) {
  const auto box = geometry::bounding_box(mesh);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> uniform(box.min.z - 1, box.max.z + 1);
  std::vector<double> heights;
  for (std::size_t i = 0; i < count; ++i) heights.push_back(uniform(random));
  for (const auto& v : mesh.vertices) heights.push_back(v.z);
  heights.push_back(box.min.z);
  heights.push_back(box.max.z);
  return heights;
}

}  // namespace

TEST_CASE("uniform_layers_50mm_at_015_gives_334_layers_ending_at_50_1") {
  const auto layers = geometry::uniform_layers(50, 0.15);
  REQUIRE(layers.size() == 334);
  CHECK(layers.front().z_lo == 0);
  CHECK(layers.front().z_hi == doctest::Approx(0.15).epsilon(1e-15));
  CHECK(layers.back().z_hi == doctest::Approx(50.1).epsilon(1e-14));
  for (std::size_t i = 1; i < layers.size(); ++i) {
    CHECK(layers[i].z_lo == layers[i - 1].z_hi);  // contiguous, bit for bit
    CHECK(layers[i].thickness() == doctest::Approx(0.15).epsilon(1e-9));
  }
}

TEST_CASE("uniform_layers_stop_at_the_layer_that_reaches_the_top") {
  CHECK(geometry::uniform_layers(30, 0.15).size() == 200);  // exact multiple: no extra layer
  CHECK(geometry::uniform_layers(30.01, 0.15).size() == 201);
  CHECK(geometry::uniform_layers(0.1, 0.2).size() == 1);
  const auto first_thick = geometry::uniform_layers(10, 0.2, 0.3);
  REQUIRE(first_thick.size() == 50);  // 0.3, then 49 layers of 0.2 reach 10.1
  CHECK(first_thick[0].z_hi == 0.3);
  CHECK(first_thick[1].z_lo == 0.3);
  CHECK(first_thick.back().z_hi == doctest::Approx(10.1).epsilon(1e-14));
  CHECK(first_thick[1].z_mid() == doctest::Approx(0.4).epsilon(1e-15));
}

TEST_CASE("uniform_layers_of_non_positive_sizes_are_empty") {
  CHECK(geometry::uniform_layers(0, 0.2).empty());
  CHECK(geometry::uniform_layers(-5, 0.2).empty());
  CHECK(geometry::uniform_layers(10, 0).empty());
  CHECK(geometry::uniform_layers(10, -0.2).empty());
  CHECK(geometry::uniform_layers(10, 0.2, -0.1).empty());
  CHECK(geometry::uniform_layers(std::numeric_limits<double>::quiet_NaN(), 0.2).empty());
  CHECK(geometry::uniform_layers(10, std::numeric_limits<double>::infinity()).empty());
}

TEST_CASE("layers_from_tops_start_at_the_bed") {
  const std::vector<double> tops{0.3, 0.45, 0.7, 1.0};
  const auto layers = geometry::layers_from_tops(tops);
  REQUIRE(layers.size() == 4);
  CHECK(layers[0].z_lo == 0);
  CHECK(layers[0].z_hi == 0.3);
  CHECK(layers[2].z_lo == 0.45);
  CHECK(layers[2].z_hi == 0.7);
  CHECK(geometry::layers_from_tops(std::vector<double>{}).empty());
}

TEST_CASE("layers_from_tops_refuses_unordered_or_non_positive_tops") {
  CHECK_THROWS_AS(geometry::layers_from_tops(std::vector<double>{0.2, 0.2}), geometry::InputError);
  CHECK_THROWS_AS(geometry::layers_from_tops(std::vector<double>{0.4, 0.3}), geometry::InputError);
  CHECK_THROWS_AS(geometry::layers_from_tops(std::vector<double>{0, 0.3}), geometry::InputError);
  CHECK_THROWS_AS(geometry::layers_from_tops(std::vector<double>{-1}), geometry::InputError);
  CHECK_THROWS_AS(
      geometry::layers_from_tops(std::vector<double>{0.2, std::numeric_limits<double>::quiet_NaN()}),
      geometry::InputError);
  try {
    geometry::layers_from_tops(std::vector<double>{0.2, 0.5, 0.4});
  } catch (const geometry::InputError& e) {
    const std::string message = e.what();
    CHECK(message.find("top 3") != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("cross_section_agrees_with_slice_mesh") {
  for (const Solid& solid : some_solids()) {
    const LayerStack stack(solid.mesh, {});
    const std::vector<double> heights = many_heights(solid.mesh, 200);
    const auto sections = geometry::slice_mesh(solid.mesh, heights);
    for (std::size_t i = 0; i < heights.size(); ++i) {
      CAPTURE(heights[i]);
      CHECK(same_region(stack.cross_section(heights[i]), sections[i]));
    }
  }
}

TEST_CASE("cross_section_matches_closed_form") {
  for (const Solid& solid : some_solids()) {
    const LayerStack stack(solid.mesh, {});
    for (double z : many_heights(solid.mesh, 100)) {
      CAPTURE(z);
      const Region got = stack.cross_section(z);
      CHECK(geometry::area(got) ==
            doctest::Approx(solid.area(z)).epsilon(1e-9).scale(std::max(1.0, solid.area(z))));
      CHECK(geometry::perimeter(got) == doctest::Approx(solid.perimeter(z)).epsilon(1e-9));
      CHECK(got.loops.size() == solid.section(z).loops.size());
    }
  }
}

TEST_CASE("lower_mid_upper_are_sections_at_layer_bounds") {
  const Solid c = cone(10, 10, 32);
  const LayerStack stack(c.mesh, geometry::uniform_layers(10, 2.5));
  REQUIRE(stack.size() == 4);
  CHECK(geometry::area(stack.lower(1)) == doctest::Approx(c.area(2.5)).epsilon(1e-12));
  CHECK(geometry::area(stack.mid(1)) == doctest::Approx(c.area(3.75)).epsilon(1e-12));
  CHECK(geometry::area(stack.upper(1)) == doctest::Approx(c.area(5)).epsilon(1e-12));
  CHECK(stack.upper(3).loops.empty());  // the apex
  CHECK(geometry::area(stack.lower(0)) == doctest::Approx(regular_polygon_area(32, 10)));
}

TEST_CASE("faces_between_equals_brute_force") {
  for (const Solid& solid : some_solids()) {
    const LayerStack stack(solid.mesh, {});
    const auto heights = many_heights(solid.mesh, 60);
    for (std::size_t i = 0; i + 1 < heights.size(); i += 2) {
      const double lo = std::min(heights[i], heights[i + 1]);
      const double hi = std::max(heights[i], heights[i + 1]);
      std::vector<std::uint32_t> want;
      for (std::uint32_t f = 0; f < solid.mesh.faces.size(); ++f) {
        const auto& face = solid.mesh.faces[f];
        const auto& v = solid.mesh.vertices;
        const double a = v[face[0]].z, b = v[face[1]].z, c = v[face[2]].z;
        if (std::min({a, b, c}) <= hi && std::max({a, b, c}) >= lo) want.push_back(f);
      }
      CAPTURE(lo);
      CAPTURE(hi);
      CHECK(stack.faces_between(lo, hi) == want);
      CHECK(stack.faces_between(lo, lo).size() <= want.size());
    }
    CHECK(stack.faces_between(1, 0).empty());
  }
}

TEST_CASE("faces_between_a_horizontal_face_includes_it") {
  const Solid c = cube(10);
  const LayerStack stack(c.mesh, {});
  CHECK(stack.faces_between(10, 10).size() == 2 + 8);  // the top and the sides touching it
  CHECK(stack.faces_between(10.5, 11).empty());
  CHECK(stack.faces_between(-1, 20).size() == 12);
}

TEST_CASE("vertex_heights_between_are_sorted_and_distinct") {
  const Solid s = sphere(10, 16, 8, {0, 0, 10});
  const LayerStack stack(s.mesh, {});
  const auto all = stack.vertex_heights_between(-1, 21);
  REQUIRE(all.size() == 9);  // two poles and seven rings
  CHECK(std::is_sorted(all.begin(), all.end()));
  CHECK(all.front() == 0);
  CHECK(all.back() == 20);
  const double ring = 10 - 10 * std::cos(std::acos(-1.0) / 8);  // lowest ring above the pole
  const auto low = stack.vertex_heights_between(0, ring);  // closed interval
  REQUIRE(low.size() == 2);
  CHECK(low[1] == doctest::Approx(ring).epsilon(1e-14));
  CHECK(stack.vertex_heights_between(0.01, ring - 0.01).empty());
  CHECK(stack.vertex_heights_between(5, 4).empty());
}

TEST_CASE("concurrent_cross_sections_equal_sequential_ones") {
  const Solid t = torus(20, 6, 96, 32, {0, 0, 6});
  const LayerStack stack(t.mesh, {});
  const auto heights = many_heights(t.mesh, 2000);
  std::vector<Region> sequential;
  for (double z : heights) sequential.push_back(stack.cross_section(z));
  std::vector<Region> parallel(heights.size());
  tbb::parallel_for(std::size_t{0}, heights.size(),
                    [&](std::size_t i) { parallel[i] = stack.cross_section(heights[i]); });
  for (std::size_t i = 0; i < heights.size(); ++i) CHECK(same_region(parallel[i], sequential[i]));
}

TEST_CASE("empty_mesh_stack_is_empty_everywhere") {
  const geometry::Mesh empty;
  const LayerStack stack(empty, geometry::uniform_layers(1, 0.5));
  CHECK(stack.size() == 2);
  CHECK(stack.cross_section(0.2).loops.empty());
  CHECK(stack.faces_between(0, 1).empty());
  CHECK(stack.vertex_heights_between(0, 1).empty());
  CHECK(stack.cross_section(std::numeric_limits<double>::quiet_NaN()).loops.empty());
}

TEST_CASE("layer_stack_moves_keep_the_index") {
  const Solid c = cylinder(4, 8, 20);
  LayerStack a(c.mesh, geometry::uniform_layers(8, 1));
  LayerStack b = std::move(a);
  CHECK(b.size() == 8);
  CHECK(geometry::area(b.mid(3)) == doctest::Approx(regular_polygon_area(20, 4)).epsilon(1e-12));
}

}  // namespace layer_stack_test
