// The test solids themselves: closed, outward, and their closed forms agree with each other.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <utility>

#include "geometry/mesh/mesh.h"
#include "geometry/core/polygon.h"
#include "support/solids.h"

namespace solids_test {

using namespace solids;
using geometry::Mesh;
using geometry::Vec3;

namespace {

constexpr double kPi = std::numbers::pi;

struct Named {
  std::string name;
  Solid solid;
  int euler;  // V - E + F: 2 for a sphere-like solid, 0 with one through hole
};

std::vector<Named> all_solids() {
  std::vector<Named> list;
  list.push_back({"cube", cube(10), 2});
  list.push_back({"box", box({-1, 2, 3}, {4, 5, 9}), 2});
  list.push_back({"cylinder", cylinder(5, 12, 24, {1, -2, 3}), 2});
  list.push_back({"tube", tube(3, 5, 8, 16), 0});
  list.push_back({"frustum", frustum(6, 2, 9, 20), 2});
  list.push_back({"inverted frustum", frustum(2, 6, 9, 20), 2});
  list.push_back({"cone", cone(4, 10, 32), 2});
  list.push_back({"sphere", sphere(10, 32, 16, {0, 0, 10}), 2});
  list.push_back({"coarse sphere", sphere(3, 5, 3), 2});
  list.push_back({"torus", torus(10, 3, 36, 12, {0, 0, 3}), 0});
  list.push_back({"bipyramid", bipyramid(5, 6, 0, 4, 10), 2});
  list.push_back({"cube with square hole", cube_with_square_hole(20, 8), 0});
  list.push_back({"cube with round hole", cube_with_round_hole(20, 6, 30), 0});
  list.push_back({"cube with tilted triangle hole",
                  cube_with_hole(20, {{-3, -2}, {7, -1}, {1, 8}}), 0});
  list.push_back({"stepped box", stepped_box({20, 12}, 5, {8, 6}, 7), 2});
  list.push_back({"overhanging stepped box", stepped_box({8, 6}, 5, {20, 12}, 7), 2});
  list.push_back({"diamond prism", diamond_prism(12, 3, 5, 4), 2});
  list.push_back({"notched prism",
                  lying_prism({{0, 0}, {10, 0}, {10, 6}, {7, 6}, {5, 3}, {3, 6}, {0, 6}}, 0, 8), 2});
  list.push_back({"notched cylinder",
                  revolve({{0, 0}, {9, 0}, {9, 10}, {7, 10}, {5, 5}, {3, 10}, {0, 10}}, 24), 2});
  list.push_back({"tube with a rod inside", combine(tube(6, 8, 10, 24), cylinder(3, 10, 24)), 2});
  return list;
}

// Each directed edge once and its reverse once: closed, manifold, consistently oriented.
bool closed_and_consistent(const Mesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& f : mesh.faces) {
    for (int i = 0; i < 3; ++i) ++directed[{f[i], f[(i + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) return false;
    auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end() || reverse->second != 1) return false;
  }
  return true;
}

int euler_characteristic(const Mesh& mesh) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
  std::set<std::uint32_t> used;
  for (const auto& f : mesh.faces) {
    for (int i = 0; i < 3; ++i) {
      used.insert(f[i]);
      edges.insert(std::minmax(f[i], f[(i + 1) % 3]));
    }
  }
  return static_cast<int>(used.size()) - static_cast<int>(edges.size()) +
         static_cast<int>(mesh.faces.size());
}

std::vector<double> vertex_heights(const Mesh& mesh) {
  std::vector<double> z;
  for (const Vec3& v : mesh.vertices) z.push_back(v.z);
  std::sort(z.begin(), z.end());
  z.erase(std::unique(z.begin(), z.end()), z.end());
  return z;
}

}  // namespace

TEST_CASE("solids_are_closed_and_consistently_oriented") {
  for (const auto& [name, solid, euler] : all_solids()) {
    CAPTURE(name);
    CHECK(closed_and_consistent(solid.mesh));
    CHECK(euler_characteristic(solid.mesh) == euler);
  }
}

TEST_CASE("solids_have_no_degenerate_faces") {
  for (const auto& [name, solid, euler] : all_solids()) {
    CAPTURE(name);
    for (const auto& f : solid.mesh.faces) {
      const Vec3 n = geometry::cross(solid.mesh.vertices[f[1]] - solid.mesh.vertices[f[0]],
                                     solid.mesh.vertices[f[2]] - solid.mesh.vertices[f[0]]);
      REQUIRE(std::sqrt(geometry::dot(n, n)) > 1e-9);
    }
  }
}

TEST_CASE("solid_volume_is_the_mesh_volume") {
  for (const auto& [name, solid, euler] : all_solids()) {
    CAPTURE(name);
    CHECK(geometry::signed_volume(solid.mesh) == doctest::Approx(solid.volume).epsilon(1e-12));
  }
}

TEST_CASE("closed_form_volumes_by_hand") {
  CHECK(cube(10).volume == doctest::Approx(1000).epsilon(1e-15));
  // n-gon prism: n/2 r^2 sin(2 pi/n) h; a square of circumradius 1 has area 2.
  CHECK(cylinder(1, 3, 4).volume == doctest::Approx(6).epsilon(1e-14));
  // Hexagonal cone: (3 sqrt3 / 2) r^2 h / 3.
  CHECK(cone(2, 3, 6).volume == doctest::Approx(3 * std::sqrt(3.0) / 2 * 4).epsilon(1e-14));
  // Octahedron of circumradius 1 (square bipyramid of height 1 each side): 4/3.
  CHECK(bipyramid(1, 4, -1, 0, 1).volume == doctest::Approx(4.0 / 3).epsilon(1e-14));
  CHECK(cube_with_square_hole(10, 4).volume == doctest::Approx(840).epsilon(1e-15));
  CHECK(stepped_box({4, 3}, 2, {2, 1}, 5).volume == doctest::Approx(34).epsilon(1e-15));
  // Diamond prism: rhombus area 2 w h times length.
  CHECK(diamond_prism(5, 1, 0, 2).volume == doctest::Approx(20).epsilon(1e-15));
}

// Between two consecutive vertex heights every section area is a quadratic in z, so Simpson's
// rule over each such interval integrates it exactly: the area closed form must integrate to
// the mesh's volume.
TEST_CASE("section_area_integrates_to_volume") {
  for (const auto& [name, solid, euler] : all_solids()) {
    CAPTURE(name);
    const std::vector<double> z = vertex_heights(solid.mesh);
    double integral = 0;
    for (std::size_t i = 0; i + 1 < z.size(); ++i) {
      const double a = z[i], b = z[i + 1], m = 0.5 * (a + b);
      // Open interval: evaluate just inside the ends, the limit values of the quadratic.
      const double e = 1e-9 * (b - a);
      integral += (b - a) / 6 * (solid.area(a + e) + 4 * solid.area(m) + solid.area(b - e));
    }
    CHECK(integral == doctest::Approx(solid.volume).epsilon(1e-7));
  }
}

TEST_CASE("section_region_matches_area_and_perimeter") {
  for (const auto& [name, solid, euler] : all_solids()) {
    CAPTURE(name);
    const std::vector<double> z = vertex_heights(solid.mesh);
    for (std::size_t i = 0; i + 1 < z.size(); ++i) {
      for (double h : {z[i], 0.3 * z[i] + 0.7 * z[i + 1]}) {
        CAPTURE(h);
        const geometry::Region section = solid.section(h);
        CHECK(geometry::area(section) == doctest::Approx(solid.area(h)).epsilon(1e-12));
        CHECK(geometry::perimeter(section) ==
              doctest::Approx(solid.perimeter(h)).epsilon(1e-12));
        for (const auto& loop : section.loops) CHECK(loop.size() >= 3);
      }
    }
    CHECK(solid.section(z.back()).loops.empty());
    CHECK(solid.area(z.back()) == 0);
    CHECK(solid.area(z.front() - 1) == 0);
  }
}

// The flat faces at the top of a solid must tile its last section, none flipped.
TEST_CASE("top_faces_tile_the_top_section") {
  for (const auto& [name, solid, euler] : all_solids()) {
    CAPTURE(name);
    const std::vector<double> z = vertex_heights(solid.mesh);
    const double top = z.back();
    double covered = 0;
    bool any = false;
    for (const auto& f : solid.mesh.faces) {
      const auto& v = solid.mesh.vertices;
      if (v[f[0]].z != top || v[f[1]].z != top || v[f[2]].z != top) continue;
      const Vec3 n = geometry::cross(v[f[1]] - v[f[0]], v[f[2]] - v[f[0]]);
      CHECK(n.z > 0);
      covered += std::abs(n.z) / 2;
      any = true;
    }
    // Just below the top (the limit from below), within the section's linear change over 1e-9.
    const double just_below = top - 1e-9 * (top - z.front());
    if (any) CHECK(covered == doctest::Approx(solid.area(just_below)).epsilon(1e-7));
  }
}

TEST_CASE("sphere_section_between_rings_is_linear_ngon") {
  // 4 rings: ring heights R cos(pi k/4); between z = 0 and z = R/sqrt2 the circumradius runs
  // from R to R/sqrt2 linearly.
  const double r = 2;
  const Solid s = sphere(r, 8, 4);
  const double z1 = r * std::cos(kPi / 4), rho1 = r * std::sin(kPi / 4);
  const double z = 0.25 * z1, rho = r + 0.25 * (rho1 - r);
  CHECK(s.area(z) == doctest::Approx(regular_polygon_area(8, rho)).epsilon(1e-14));
  CHECK(s.perimeter(z) == doctest::Approx(16 * rho * std::sin(kPi / 8)).epsilon(1e-14));
  CHECK(s.area(r) == 0);          // top pole: empty
  CHECK(s.area(-r) == 0);         // bottom pole: a vanishing section
  CHECK(s.section(-r).loops.empty());
}

TEST_CASE("notch_tip_on_the_plane_leaves_no_slit") {
  const Solid prism = lying_prism({{0, 0}, {10, 0}, {10, 6}, {7, 6}, {5, 3}, {3, 6}, {0, 6}}, 0, 8);
  CHECK(prism.section(3).loops.size() == 1);
  CHECK(prism.area(3) == doctest::Approx(80).epsilon(1e-15));
  CHECK(prism.perimeter(3) == doctest::Approx(36).epsilon(1e-15));
  CHECK(prism.section(4.5).loops.size() == 2);  // 8 x 4 on the left, 8 x 4 on the right
  CHECK(prism.area(4.5) == doctest::Approx(64).epsilon(1e-15));
}

TEST_CASE("torus_section_is_annulus") {
  const Solid t = torus(10, 3, 24, 8);
  const geometry::Region at_equator = t.section(0);
  REQUIRE(at_equator.loops.size() == 2);
  CHECK(geometry::signed_area(at_equator.loops[0]) > 0);
  CHECK(geometry::signed_area(at_equator.loops[1]) < 0);
  CHECK(t.area(0) == doctest::Approx(regular_polygon_area(24, 13) - regular_polygon_area(24, 7))
                         .epsilon(1e-14));
}

}  // namespace solids_test
