// The unsupported-extrusion check on deposition records built bead by bead, and on G-code read
// straight through (gcode_deposition).
#include "sim/unsupported_extrusion.h"

#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "printer/bead_model.h"
#include "sim/gcode_deposition.h"

namespace unsupported_extrusion_test {

using geometry::Vec2;

namespace {

constexpr double kWidth = 0.45, kHeight = 0.2, kFilament = 1.75;

// A layer's extrusions: each a polyline laid as one extrusion at z.
void lay(sim::DepositionRecord& record, double z, const std::vector<Vec2>& line, double width = kWidth) {
  for (std::size_t i = 1; i < line.size(); ++i) {
    const Vec2 d = line[i] - line[i - 1];
    const double length = std::hypot(d.x, d.y);
    record.add(z, line[i - 1], line[i], printer::filament_for_bead(width, kHeight, length, kFilament), 30);
  }
}

sim::SupportCheckOptions options(double bridge = 10, double gap = 0) {
  sim::SupportCheckOptions o;
  o.filament_diameter = kFilament;
  o.bridge_length = bridge;
  o.contact_gap = gap;
  return o;
}

double z_of(int layer) { return kHeight * (layer + 1); }

}  // namespace

TEST_CASE("beads_stacked_on_beads_are_supported") {
  sim::DepositionRecord record;
  for (int k = 0; k < 5; ++k) lay(record, z_of(k), {{0, 0}, {20, 0}, {20, 10}, {0, 10}, {0, 0}});
  const sim::SupportCheck check = sim::check_unsupported_extrusion(record, options());
  CHECK(check.unsupported_mm == 0);
  CHECK(check.extruded_mm == doctest::Approx(5 * 60));
  CHECK(check.unsupported_per_layer.size() == 5);
}

TEST_CASE("a_line_reaching_past_the_one_below_is_unsupported_past_its_end") {
  sim::DepositionRecord record;
  lay(record, z_of(0), {{0, 0}, {10, 0}});
  lay(record, z_of(1), {{0, 0}, {15, 0}});
  const sim::SupportCheck check = sim::check_unsupported_extrusion(record, options());
  // The bead below ends at x = 10 (square-cut); the tolerance lets 25 um more rest on it.
  CHECK(check.unsupported_mm == doctest::Approx(5 - 0.025).epsilon(1e-3));
  REQUIRE(check.stretches.size() == 1);
  CHECK(check.stretches[0].layer == 1);
  CHECK_FALSE(check.stretches[0].anchored);
  CHECK_FALSE(check.stretches[0].between);  // beyond everything below: in the open
  CHECK(check.between_mm == 0);
}

TEST_CASE("a_bridge_held_at_both_ends_within_the_bridge_length_is_supported") {
  // Two pillars, their tops 8 mm apart, and a line across.
  sim::DepositionRecord record;
  lay(record, z_of(0), {{0, -2}, {0, 2}});
  lay(record, z_of(0), {{9, -2}, {9, 2}});
  lay(record, z_of(1), {{0, 0}, {9, 0}});
  CHECK(sim::check_unsupported_extrusion(record, options(10)).unsupported_mm == 0);
  const sim::SupportCheck short_bridges = sim::check_unsupported_extrusion(record, options(5));
  // 9 mm less the half beads the pillars carry, less the tolerance at each end.
  CHECK(short_bridges.unsupported_mm == doctest::Approx(9 - kWidth - 0.05).epsilon(1e-3));
  REQUIRE(short_bridges.stretches.size() == 1);
  CHECK(short_bridges.stretches[0].anchored);
}

TEST_CASE("a_bead_over_a_gap_of_up_to_half_a_bead_rests_on_both_sides") {
  for (const double gap : {0.2, 0.5}) {
    CAPTURE(gap);
    sim::DepositionRecord record;
    lay(record, z_of(0), {{0, 0}, {20, 0}});
    lay(record, z_of(0), {{0, kWidth + gap}, {20, kWidth + gap}});
    // Within the lines' length: at their square-cut ends the closing rounds off.
    lay(record, z_of(1), {{1, (kWidth + gap) / 2}, {19, (kWidth + gap) / 2}});
    const double unsupported = sim::check_unsupported_extrusion(record, options()).unsupported_mm;
    if (gap < kWidth / 2) {
      CHECK(unsupported == 0);
    } else {
      CHECK(unsupported == doctest::Approx(18).epsilon(1e-3));
    }
  }
}

TEST_CASE("across_the_contact_gap_a_bead_rests_on_the_layer_two_below") {
  // Support top at layer 0, nothing at layer 1 under the part's line at layer 2.
  sim::DepositionRecord record;
  lay(record, z_of(0), {{0, 0}, {20, 0}});
  lay(record, z_of(0), {{30, 0}, {40, 0}});
  lay(record, z_of(1), {{30, 0}, {40, 0}});
  lay(record, z_of(2), {{0, 0}, {20, 0}});
  lay(record, z_of(2), {{30, 0}, {40, 0}});
  CHECK(sim::check_unsupported_extrusion(record, options(10, 0)).unsupported_mm == doctest::Approx(20).epsilon(0.01));
  CHECK(sim::check_unsupported_extrusion(record, options(10, 0.2)).unsupported_mm == 0);
  // Two layers of air (0.4 mm) are more than a gap of 0.2 rounded up to a layer allows.
  sim::DepositionRecord far;
  lay(far, z_of(0), {{0, 0}, {20, 0}});
  lay(far, z_of(0), {{30, 0}, {40, 0}});
  lay(far, z_of(1), {{30, 0}, {40, 0}});
  lay(far, z_of(2), {{30, 0}, {40, 0}});
  lay(far, z_of(3), {{0, 0}, {20, 0}});
  lay(far, z_of(3), {{30, 0}, {40, 0}});
  CHECK(sim::check_unsupported_extrusion(far, options(10, 0.2)).unsupported_mm == doctest::Approx(20).epsilon(0.01));
}

TEST_CASE("the_first_layer_rests_on_the_bed_and_across_a_gap_the_second_too") {
  sim::DepositionRecord record;
  lay(record, z_of(0), {{0, 0}, {50, 0}});
  const sim::SupportCheck check = sim::check_unsupported_extrusion(record, options());
  CHECK(check.unsupported_mm == 0);
  CHECK(check.extruded_mm == doctest::Approx(50));
  // Layer 1 over nothing but the bed, 0.2 mm below it.
  lay(record, z_of(1), {{60, 0}, {70, 0}});
  CHECK(sim::check_unsupported_extrusion(record, options(10, 0)).unsupported_mm == doctest::Approx(10));
  CHECK(sim::check_unsupported_extrusion(record, options(10, 0.2)).unsupported_mm == 0);
}

TEST_CASE("a_line_end_among_sparse_lines_below_is_counted_between_them") {
  // Lines 2.5 mm apart below; above, across them, a line that ends between two of them.
  sim::DepositionRecord record;
  for (int i = 0; i < 8; ++i) lay(record, z_of(0), {{0, 2.5 * i}, {20, 2.5 * i}});
  lay(record, z_of(1), {{10, 0}, {10, 8.75}});
  const sim::SupportCheck check = sim::check_unsupported_extrusion(record, options());
  // From the line at y = 7.5 (its bead to 7.725, and the tolerance) to the end at 8.75.
  CHECK(check.unsupported_mm == doctest::Approx(8.75 - 7.5 - kWidth / 2 - 0.025).epsilon(1e-3));
  CHECK(check.between_mm == check.unsupported_mm);
}

TEST_CASE("summary_says_how_much_of_how_much_and_where") {
  sim::DepositionRecord record;
  lay(record, z_of(0), {{0, 0}, {100, 0}});
  const sim::SupportCheckOptions o = options(10, 0.2);
  CHECK(sim::unsupported_summary(sim::check_unsupported_extrusion(record, o), o) ==
        "unsupported extrusion: 0.0 mm of 0.1 m (0.00%; bridges up to 10 mm, contact gap 0.2 mm)");
  // (Layer 1 could sag onto the bed across the gap: the overhang is on layer 2.)
  lay(record, z_of(1), {{0, 0}, {100, 0}});
  lay(record, z_of(2), {{0, 0}, {110, 0}});
  CHECK(sim::unsupported_summary(sim::check_unsupported_extrusion(record, o), o) ==
        "unsupported extrusion: 10.0 mm of 0.3 m (3.22%: 10.0 mm in the open, 0.0 mm between "
        "sparse lines below; bridges up to 10 mm, contact gap 0.2 mm)");
}

TEST_CASE("gcode_read_straight_through_records_what_the_sim_records") {
  // Absolute E, then relative E after M83; a travel, a retraction, a G92 reset.
  const std::string program =
      "G28\nG90\nM82\nG92 E0\nG1 Z0.2 F600\nG1 X10 Y0 F3000\nG1 X20 Y0 E0.5\n"
      "G1 E0.4\nG0 X20 Y10\nG1 E0.5\nM83\nG1 X10 Y10 E0.5\nG92 E0\nG1 Z0.4\nG1 X20 Y10 E0.5\n";
  const sim::DepositionRecord record = sim::deposition_from_gcode(program);
  REQUIRE(record.moves.size() == 3);
  CHECK(record.layer_z.size() == 2);
  CHECK(record.moves[0].start.x == 10);
  CHECK(record.moves[0].end.x == 20);
  CHECK(record.moves[0].e == doctest::Approx(0.5));
  CHECK(record.moves[1].end.x == 10);
  CHECK(record.moves[1].e == doctest::Approx(0.5));
  CHECK(record.moves[2].layer == 1);
  CHECK(record.moves[2].z == doctest::Approx(0.4));
}

}  // namespace unsupported_extrusion_test
