// The layered part as a mesh: closed, outward, with the volume of its prisms.
#include <doctest/doctest.h>

#include <map>
#include <utility>

#include "geometry/metrics/extruded_layers.h"
#include "geometry/slicing/layer_stack.h"
#include "support/solids.h"

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
  CHECK(geometry::signed_volume(mesh) == doctest::Approx(expected).epsilon(1e-12));
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
  CHECK(geometry::signed_volume(mesh) == doctest::Approx(0.5 * area).epsilon(1e-12));
}

TEST_CASE("extruding_nothing_gives_an_empty_mesh") {
  const std::vector<Layer> layers{{0, 0.2}, {0.2, 0.2}};
  const Region square{{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}};
  CHECK(geometry::extruded_layers(layers, std::vector<Region>{Region{}, square}).faces.empty());
  CHECK(geometry::extruded_layers({}, {}).faces.empty());
}
