// The layered part as a mesh: closed, outward, with the volume of its prisms.
#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <utility>

#include <unistd.h>

#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"
#include "geometry/metrics/extruded_layers.h"
#include "geometry/slicing/layer_stack.h"
#include "support/solids.h"

namespace extruded_layers_test {

using geometry::Layer;
using geometry::Region;

namespace {

// Every directed edge must be matched by the same edge in the other direction, once:
// a closed, consistently oriented surface.
bool closed_and_oriented(const geometry::Mesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k) ++edges[{f[k], f[(k + 1) % 3]}];
  for (const auto& [edge, count] : edges) {
    if (count != 1) return false;
    const auto back = edges.find({edge.second, edge.first});
    if (back == edges.end() || back->second != 1) return false;
  }
  return !mesh.faces.empty();
}

}  // namespace

TEST_CASE("extruded_tube_layers_are_closed_with_the_prisms_volume") {
  const solids::Solid tube = solids::tube(2, 5, 3, 32);
  const geometry::LayerStack stack(tube.mesh, geometry::uniform_layers(3, 0.5));
  std::vector<Region> regions;
  double expected = 0;
  for (std::size_t i = 0; i < stack.size(); ++i) {
    regions.push_back(stack.mid(i));
    expected += geometry::area(regions.back()) * stack.layers()[i].thickness();
  }
  const geometry::Mesh mesh = geometry::extruded_layers(stack.layers(), regions);
  CHECK(closed_and_oriented(mesh));
  // The regions on the exporter's grid (a few nanometres), and z as float32: 1e-6 relative.
  CHECK(geometry::signed_volume(mesh) == doctest::Approx(expected).epsilon(1e-6));
  CHECK(geometry::signed_volume(mesh) == doctest::Approx(tube.volume).epsilon(1e-6));
}

TEST_CASE("extruded_islands_and_holes_keep_their_topology") {
  // Two islands, one with a hole with an island inside it.
  const Region region{{{{0, 0}, {10, 0}, {10, 10}, {0, 10}},
                       {{2, 2}, {2, 8}, {8, 8}, {8, 2}},
                       {{4, 4}, {6, 4}, {6, 6}, {4, 6}},
                       {{12, 0}, {14, 0}, {14, 2}, {12, 2}}}};
  const std::vector<Layer> layers{{0, 0.2}, {0.2, 0.5}};
  const std::vector<Region> regions{region, region};
  const geometry::Mesh mesh = geometry::extruded_layers(layers, regions);
  CHECK(closed_and_oriented(mesh));
  const double area = 100 - 36 + 4 + 4;
  CHECK(geometry::area(region) == doctest::Approx(area));
  CHECK(geometry::signed_volume(mesh) == doctest::Approx(0.5 * area).epsilon(1e-6));
}

TEST_CASE("extruding_nothing_gives_an_empty_mesh") {
  const std::vector<Layer> layers{{0, 0.2}, {0.2, 0.2}};
  const Region square{{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}};
  CHECK(geometry::extruded_layers(layers, std::vector<Region>{Region{}, square}).faces.empty());
  CHECK(geometry::extruded_layers({}, {}).faces.empty());
}

// ---------------------------------------------------------------------------------------
// As a file: the STL a user exports, read back and repaired as `mahost info` does. A valid
// solid needs no repair at all: no open or non-manifold edge, no degenerate facet, no vertex
// to split, no facet to turn.

namespace {

struct Readback {
  geometry::RepairReport report;
  double volume = 0;
};

Readback read_back(const geometry::Mesh& mesh, const std::string& name) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("extruded-" + std::to_string(::getpid()) + "-" + name + ".stl"))
                               .string();
  geometry::write_stl_binary(path, mesh);
  Readback result;
  const geometry::Mesh repaired = geometry::repair(geometry::read_stl(path), &result.report);
  result.volume = geometry::signed_volume(repaired);
  std::filesystem::remove(path);
  return result;
}

void check_valid_solid(const geometry::Mesh& mesh, double expected_volume, const std::string& name,
                       double volume_epsilon = 1e-6) {
  const Readback r = read_back(mesh, name);
  INFO(name << ": " << r.report.summary());
  CHECK(r.report.closed);
  CHECK(r.report.open_edges_before == 0);
  CHECK(r.report.non_manifold_edges == 0);
  CHECK(r.report.degenerate_faces_dropped == 0);
  CHECK(r.report.duplicate_faces_dropped == 0);
  CHECK(r.report.non_manifold_vertices_split == 0);
  CHECK(r.report.faces_reoriented == 0);
  CHECK_FALSE(r.report.anything_repaired());
  // Outward: the volume is positive, and what the prisms hold.
  CHECK(r.volume == doctest::Approx(expected_volume).epsilon(volume_epsilon));
  CHECK(geometry::signed_volume(mesh) == doctest::Approx(expected_volume).epsilon(volume_epsilon));
}

geometry::Loop circle(double radius, int n, double turn = 0, geometry::Vec2 centre = {}) {
  geometry::Loop loop;
  for (int k = 0; k < n; ++k) {
    const double a = turn + 2 * std::numbers::pi * k / n;
    loop.push_back({centre.x + radius * std::cos(a), centre.y + radius * std::sin(a)});
  }
  return loop;
}

double prisms_volume(const std::vector<Layer>& layers, const std::vector<Region>& regions) {
  double volume = 0;
  for (std::size_t i = 0; i < layers.size(); ++i) volume += geometry::area(regions[i]) * layers[i].thickness();
  return volume;
}

}  // namespace

TEST_CASE("layers_sharing_a_wall_edge_make_one_manifold_solid") {
  // The same square on three layers of mixed thicknesses, then a smaller one on two: walls
  // go on from layer to layer along the shared edges, and the step's top faces up.
  const Region big{{{{0, 0}, {10, 0}, {10, 10}, {0, 10}}}};
  const Region small{{{{0, 0}, {4, 0}, {4, 4}, {0, 4}}}};
  const std::vector<double> tops{0.3, 0.45, 0.85, 1.0, 1.4};
  const std::vector<Layer> layers = geometry::layers_from_tops(tops);
  const std::vector<Region> regions{big, big, big, small, small};
  const geometry::Mesh mesh = geometry::extruded_layers(layers, regions);
  // Closed form: 100 mm^2 x 0.85 mm + 16 mm^2 x 0.55 mm.
  check_valid_solid(mesh, 100 * 0.85 + 16 * 0.55, "stepped");
  // No face inside the solid: the horizontal faces are the bottom (100 mm^2), the step's top
  // (84) and the small square's top (16), 200 mm^2 in all.
  double horizontal = 0;
  for (const auto& f : mesh.faces) {
    const geometry::Vec3 a = mesh.vertices[f[0]], b = mesh.vertices[f[1]], c = mesh.vertices[f[2]];
    const geometry::Vec3 n = geometry::cross(b - a, c - a);
    if (std::abs(n.x) + std::abs(n.y) < 1e-12) horizontal += std::abs(n.z) / 2;
  }
  CHECK(horizontal == doctest::Approx(200).epsilon(1e-9));
}

TEST_CASE("crossing_contours_of_neighbouring_layers_make_one_manifold_solid") {
  // Consecutive layers as 97-gons of slightly different radius and turn: their outlines cross
  // each other everywhere, in coordinates that are not float32 (what a contour strategy gives
  // on a curved surface). Layers from 0.15 to 0.4 mm thick.
  std::vector<double> tops;
  std::vector<Region> regions;
  double z = 0;
  for (int i = 0; i < 24; ++i) {
    z += 0.15 + 0.05 * (i % 6);
    tops.push_back(z);
    const double r = 10.0 + 0.003 * std::sin(0.7 * i) + 1e-7 * i;
    regions.push_back(Region{{circle(r, 97, 0.011 * i, {0.1234567, -0.7654321}),
                              // a hole that wanders, reversed (clockwise)
                              [&] {
                                geometry::Loop hole = circle(3 + 0.002 * i, 41, -0.03 * i, {1.0 + 1e-3 * i, 0.5});
                                std::reverse(hole.begin(), hole.end());
                                return hole;
                              }()}});
  }
  const std::vector<Layer> layers = geometry::layers_from_tops(tops);
  const geometry::Mesh mesh = geometry::extruded_layers(layers, regions);
  check_valid_solid(mesh, prisms_volume(layers, regions), "crossing");
}

TEST_CASE("sphere_sections_on_a_variable_stack_export_watertight") {
  // The mid sections of a sphere of radius 10 on layers thinning towards the poles (0.4 mm
  // at the equator, 0.15 mm near the poles): islands appear and vanish at the ends.
  const solids::Solid ball = solids::sphere(10, 96, 48, {0, 0, 10});
  std::vector<double> tops;
  for (double z = 0; z < 20 - 1e-9;) {
    const double t = std::abs(z - 10) > 7 ? 0.15 : std::abs(z - 10) > 4 ? 0.25 : 0.4;
    z = std::min(20.0, z + t);
    tops.push_back(z);
  }
  const geometry::LayerStack stack(ball.mesh, geometry::layers_from_tops(tops));
  std::vector<Region> regions;
  for (std::size_t i = 0; i < stack.size(); ++i) regions.push_back(stack.mid(i));
  const geometry::Mesh mesh = geometry::extruded_layers(stack.layers(), regions);
  check_valid_solid(mesh, prisms_volume(stack.layers(), regions), "sphere");
}

TEST_CASE("a_corner_rounded_onto_the_grid_leaves_no_wall_against_itself") {
  // A piece of the vase's outline (tests/bench/models/vase.scad, optimal-height's section at
  // z 17.000012 mm, planned adaptive at 0.3 mm), closed by a point inside: pairs of vertices a
  // few nanometres apart. With two squares touching at a corner beside it, the region is
  // cleaned with rounded corners, whose arcs of nanometre steps, rounded onto the 1.9 nm grid
  // of a part this size, sent a route out to a vertex and straight back: the wall along it lay
  // twice, back to back (two duplicate facets and four non-manifold edges when read back, as
  // `mahost info` found in the vase's export).
  const geometry::Loop outline{{-2.2747044894725486, 9.0113785591146147}, {-2.2747102649675166, 9.011372908134458},
                               {-2.5042845477454803, 8.7767187518635392}, {-2.5042894003366731, 8.7767133387066707},
                               {-2.6965946112480337, 8.552548921203682},  {-2.6966016129648547, 8.5525508793235918},
                               {-1.5, 8}};
  const Region region{{outline, {{5, 5}, {6, 5}, {6, 6}, {5, 6}}, {{6, 6}, {7, 6}, {7, 7}, {6, 7}}}};
  const std::vector<Layer> layers{{16.8, 17.2}};
  const std::vector<Region> regions{region};
  // The squares' touch closed by half a micrometre is a neck of a few square micrometres.
  check_valid_solid(geometry::extruded_layers(layers, regions), prisms_volume(layers, regions),
                    "rounded-corner", 1e-5);
}

TEST_CASE("a_gap_between_layers_leaves_two_closed_solids") {
  const Region square{{{{0, 0}, {2, 0}, {2, 2}, {0, 2}}}};
  const std::vector<Layer> layers{{0, 0.2}, {0.2, 0.4}, {0.4, 0.6}};
  const geometry::Mesh mesh =
      geometry::extruded_layers(layers, std::vector<Region>{square, Region{}, square});
  check_valid_solid(mesh, 2 * 4 * 0.2, "gap");
}

}  // namespace extruded_layers_test
