// The deposition record, its beads, the printed region and the printed part (sim/deposition.h,
// sim/printed_part.h) against closed forms.
#include <doctest/doctest.h>

#include <map>
#include <utility>

#include "geometry/mesh/mesh.h"
#include "geometry/core/polygon.h"
#include "printer/bead_model.h"
#include "sim/deposition.h"
#include "sim/printed_part.h"

namespace deposition_test {

namespace {

// A square loop of four beads of width w around (0,0)-(20,20) at height z, layer height h.
void square(sim::DepositionRecord& record, double z, double h, double w) {
  const double e = printer::filament_for_bead(w, h, 20, 1.75);
  const geometry::Vec2 c[] = {{0, 0}, {20, 0}, {20, 20}, {0, 20}};
  for (int i = 0; i < 4; ++i) record.add(z, c[i], c[(i + 1) % 4], e, 30);
}

// Every edge of a closed, consistently oriented mesh is used once in each direction.
bool closed(const geometry::Mesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const auto& f : mesh.faces) {
    for (int i = 0; i < 3; ++i) ++edges[{f[static_cast<std::size_t>(i)], f[static_cast<std::size_t>((i + 1) % 3)]}];
  }
  for (const auto& [edge, count] : edges) {
    const auto back = edges.find({edge.second, edge.first});
    if (count != 1 || back == edges.end() || back->second != 1) return false;
  }
  return !mesh.faces.empty();
}

}  // namespace

TEST_CASE("layers_are_z_levels_in_order_whenever_they_come") {
  sim::DepositionRecord record;
  record.add(0.2, {0, 0}, {1, 0}, 0.1, 20);
  record.add(0.4, {0, 0}, {1, 0}, 0.1, 20);
  record.add(0.3, {0, 0}, {1, 0}, 0.1, 20);     // a level between: layers above renumber
  record.add(0.2004, {0, 0}, {1, 0}, 0.1, 20);  // within half a micrometre: the same layer
  REQUIRE(record.layer_z.size() == 3);
  CHECK(record.moves[0].layer == 0);
  CHECK(record.moves[1].layer == 2);
  CHECK(record.moves[2].layer == 1);
  CHECK(record.moves[3].layer == 0);
  CHECK(record.layer_height(0) == doctest::Approx(0.2));
  CHECK(record.layer_height(2) == doctest::Approx(0.1));
  CHECK(record.filament_used() == doctest::Approx(0.4));
}

TEST_CASE("bead_width_inverts_the_bead_model") {
  sim::DepositionRecord record;
  record.add(0.2, {5, 5}, {15, 5}, printer::filament_for_bead(0.45, 0.2, 10, 1.75), 30);
  const auto layers = sim::bead_polygons(record, 1.75);
  REQUIRE(layers.size() == 1);
  REQUIRE(layers[0].beads.size() == 1);
  CHECK(layers[0].beads[0].width == doctest::Approx(0.45));
  CHECK(geometry::signed_area(layers[0].beads[0].outline) == doctest::Approx(10 * 0.45));
  CHECK(layers[0].beads[0].outline[0].y == doctest::Approx(5 - 0.225));
}

TEST_CASE("printed_region_of_a_square_loop_is_its_beads_union") {
  // Four 20 x w rectangles: 80 w, less the four w/2 x w/2 overlaps inside the corners.
  sim::DepositionRecord record;
  square(record, 0.2, 0.2, 0.5);
  const auto layers = sim::bead_polygons(record, 1.75);
  REQUIRE(layers.size() == 1);
  const geometry::Region region = sim::printed_region(layers[0]);
  CHECK(region.loops.size() == 2);  // outline and hole
  CHECK(geometry::area(region) == doctest::Approx(80 * 0.5 - 0.25).epsilon(1e-6));
}

TEST_CASE("printed_part_is_closed_shells_of_area_times_height") {
  sim::DepositionRecord record;
  square(record, 0.3, 0.3, 0.5);
  square(record, 0.5, 0.2, 0.5);
  const geometry::Mesh part = sim::printed_part(record, 1.75);
  CHECK(closed(part));
  const double area = 80 * 0.5 - 0.25;
  CHECK(geometry::signed_volume(part) == doctest::Approx(area * 0.3 + area * 0.2).epsilon(1e-6));
  CHECK(sim::printed_part(sim::DepositionRecord{}, 1.75).faces.empty());
}

TEST_CASE("beads_of_a_variable_stack_are_as_wide_as_laid_at_each_layers_height") {
  // Layers 0.3, 0.15, 0.4 mm thick (tops 0.3, 0.45, 0.85): each square laid with the filament
  // of a 0.45 mm bead at its own height reads back 0.45 mm wide.
  sim::DepositionRecord record;
  const double tops[] = {0.3, 0.45, 0.85}, heights[] = {0.3, 0.15, 0.4};
  for (int i = 0; i < 3; ++i) square(record, tops[i], heights[i], 0.45);
  const auto layers = sim::bead_polygons(record, 1.75);
  REQUIRE(layers.size() == 3);
  for (int i = 0; i < 3; ++i) {
    CAPTURE(i);
    CHECK(layers[i].height == doctest::Approx(heights[i]));
    for (const sim::Bead& bead : layers[i].beads) CHECK(bead.width == doctest::Approx(0.45));
  }
}

}  // namespace deposition_test
