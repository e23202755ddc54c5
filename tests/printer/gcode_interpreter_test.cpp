// printer/gcode_interpreter: one test per rule, each against what Marlin 2's source does
// (the files are named in gcode_interpreter.h).
#include <cmath>
#include <limits>
#include <string_view>

#include <doctest/doctest.h>

#include "printer/gcode_interpreter.h"

namespace gcode_interpreter_test {

using namespace printer;

namespace {

GcodeStep run(GcodeState& state, std::string_view line) {
  return interpret(state, parse_gcode_line(line));
}

// The state after a program, one command a line.
GcodeState after(std::string_view program) {
  GcodeState state;
  while (!program.empty()) {
    const std::size_t end = program.find('\n');
    run(state, program.substr(0, end));
    if (end == std::string_view::npos) break;
    program.remove_prefix(end + 1);
  }
  return state;
}

}  // namespace

TEST_CASE("axis_words_move_their_axes_absolute_by_default_and_relative_after_g91") {
  GcodeState s;
  const GcodeStep first = run(s, "G1 X10 Y5 Z0.3 E1");
  REQUIRE(first.count == 1);
  CHECK(first.motions[0].from.x == 0);
  CHECK(first.motions[0].to.x == 10);
  CHECK(first.motions[0].to.e == 1);
  run(s, "G1 X20");  // Y, Z and E keep theirs
  CHECK(s.x == 20);
  CHECK(s.y == 5);
  CHECK(s.z == 0.3);
  CHECK(s.e == 1);
  run(s, "G91");
  run(s, "G1 X-5 E2");
  CHECK(s.x == 15);
  CHECK(s.e == 3);
}

TEST_CASE("f_above_zero_is_the_modal_feedrate_f0_and_below_are_ignored") {
  GcodeState s;
  CHECK(run(s, "G1 X1").motions[0].feedrate == 0);  // none yet: the firmware's default
  CHECK(run(s, "G1 X2 F3000").motions[0].feedrate == 50);
  CHECK(run(s, "G1 X3").motions[0].feedrate == 50);
  run(s, "G1 X4 F0");
  run(s, "G1 X5 F-60");
  CHECK(s.feedrate == 3000);
}

TEST_CASE("g2_and_g3_go_straight_to_their_end_point") {
  GcodeState s;
  const GcodeStep arc = run(s, "G2 X10 Y0 I5 J0 E1 F600");
  REQUIRE(arc.count == 1);
  CHECK(arc.motions[0].to.x == 10);
  CHECK(arc.motions[0].to.e == 1);
  CHECK(lays_filament(arc.motions[0]));
}

TEST_CASE("g90_and_g91_set_every_axis_e_included_over_m82_and_m83") {
  GcodeState s = after("M83\nG90");
  CHECK_FALSE(s.relative_e);
  s = after("M82\nG91");
  CHECK(s.relative_e);
  CHECK(s.relative_xyz);
}

TEST_CASE("m82_and_m83_set_e_alone") {
  GcodeState s = after("G91\nM82");
  CHECK(s.relative_xyz);
  CHECK_FALSE(s.relative_e);
  s = after("M83\nG1 X10 E1\nG1 X20 E1");
  CHECK_FALSE(s.relative_xyz);
  CHECK(s.x == 20);
  CHECK(s.e == 2);
}

TEST_CASE("g20_reads_x_y_z_e_and_f_in_inches_until_g21") {
  GcodeState s;
  run(s, "G20");
  const GcodeStep move = run(s, "G1 X1 Y2 Z0.5 E0.1 F60");
  CHECK(s.x == doctest::Approx(25.4));
  CHECK(s.y == doctest::Approx(50.8));
  CHECK(s.z == doctest::Approx(12.7));
  CHECK(s.e == doctest::Approx(2.54));
  CHECK(move.motions[0].feedrate == doctest::Approx(25.4));  // 60 in/min = 25.4 mm/s
  run(s, "G92 X0.5");  // G92 too is in the current units
  CHECK(s.x == doctest::Approx(12.7));
  run(s, "G21");
  run(s, "G1 X1");
  CHECK(s.x == 1);
}

TEST_CASE("g92_sets_the_axes_given_and_a_bare_g92_changes_nothing") {
  GcodeState s = after("G1 X10 Y20 Z3 E5\nG92 E0");
  CHECK(s.e == 0);
  CHECK(s.x == 10);
  const GcodeStep bare = run(s, "G92");
  CHECK(bare.count == 0);
  CHECK(s.x == 10);
  CHECK(s.y == 20);
  CHECK(s.z == 3);
  run(s, "G92 X0 Z1");
  CHECK(s.x == 0);
  CHECK(s.y == 20);
  CHECK(s.z == 1);
  // An axis without a value is not set (parser.seenval); G92.1 and G92.9 are not G92.
  run(s, "G92 Y Z");
  CHECK(s.y == 20);
  CHECK(s.z == 1);
  run(s, "G92.1 X5");
  run(s, "G92.9 X5");
  CHECK(s.x == 0);
}

TEST_CASE("g28_homes_the_axes_named_or_all_three_and_leaves_e") {
  GcodeState s = after("G1 X10 Y20 Z3 E5\nG28 X");
  CHECK(s.x == 0);
  CHECK(s.y == 20);
  CHECK(s.z == 3);
  CHECK(s.homed);
  s = after("G1 X10 Y20 Z3 E5\nG28 X Y");
  CHECK(s.z == 3);
  s = after("G1 X10 Y20 Z3 E5\nG28 X Y Z");
  CHECK((s.x == 0 && s.y == 0 && s.z == 0));
  s = after("G1 X10 Y20 Z3 E5\nG28");
  CHECK((s.x == 0 && s.y == 0 && s.z == 0));
  CHECK(s.e == 5);
  const GcodeStep home = run(s, "G28 Z");
  CHECK(home.homed);
  CHECK(home.position_set);
  CHECK(home.count == 0);
}

TEST_CASE("g10_pulls_the_filament_back_once_and_g11_feeds_it_and_the_extra") {
  GcodeState s = after("M208 S0.2\nG1 X10 E5");
  const GcodeStep pull = run(s, "G10");
  REQUIRE(pull.count == 1);
  CHECK(pull.motions[0].to.e - pull.motions[0].from.e == doctest::Approx(-3));
  CHECK(pull.motions[0].feedrate == 45);
  CHECK(run(s, "G10").count == 0);  // a second G10 in a row does nothing
  CHECK(s.e == 5);                  // the G-code's own E stays
  const GcodeStep feed = run(s, "G11");
  REQUIRE(feed.count == 1);
  CHECK(feed.motions[0].to.e - feed.motions[0].from.e == doctest::Approx(3.2));
  CHECK(feed.motions[0].feedrate == 8);
  CHECK(run(s, "G11").count == 0);
  // An absolute E after it feeds what it says from the G-code's E.
  const GcodeStep next = run(s, "G1 X20 E6");
  CHECK(next.motions[0].to.e - next.motions[0].from.e == doctest::Approx(1));
}

TEST_CASE("g10_raises_z_by_m207s_z_raise_and_g11_lowers_it") {
  GcodeState s = after("M207 S1.5 F1800 Z0.4\nG1 Z0.3");
  const GcodeStep pull = run(s, "G10");
  REQUIRE(pull.count == 2);
  CHECK(pull.motions[0].to.e == doctest::Approx(-1.5));
  CHECK(pull.motions[0].feedrate == 30);  // F1800 mm/min
  CHECK(pull.motions[1].to.z == doctest::Approx(0.7));
  CHECK(std::isinf(pull.motions[1].feedrate));  // the Z axis's maximum
  CHECK(s.z == 0.3);
  const GcodeStep travel = run(s, "G0 X10");
  CHECK(travel.motions[0].to.z == doctest::Approx(0.7));  // travels raised
  const GcodeStep feed = run(s, "G11");
  REQUIRE(feed.count == 2);
  CHECK(feed.motions[0].to.z == doctest::Approx(0.3));
  CHECK(feed.motions[1].to.e == doctest::Approx(0));
}

TEST_CASE("m221_sets_the_flow_percent") {
  CHECK(after("M221 S95").flow == 95);
  CHECK(after("M221 S95\nM221").flow == 95);
  CHECK(after("M221 S0").flow == 0);
}

TEST_CASE("layer_and_type_comments_start_a_layer_and_a_feature") {
  GcodeState s;
  CHECK(s.layer == -1);
  const GcodeStep layer = run(s, ";LAYER:3");
  CHECK(layer.layer_started);
  CHECK(s.layer == 3);
  const GcodeStep type = run(s, ";TYPE:WALL-OUTER");
  CHECK(type.type_started);
  CHECK(s.type == "WALL-OUTER");
  CHECK_FALSE(run(s, ";LAYER:x").layer_started);  // no number, no layer
  CHECK(s.layer == 3);
  CHECK_FALSE(run(s, "; generated by mahost").layer_started);
}

}  // namespace gcode_interpreter_test
