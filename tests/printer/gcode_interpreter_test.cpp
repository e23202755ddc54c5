// printer/gcode_interpreter: one test per rule, each against what Marlin 2's source does
// (the files are named in gcode_interpreter.h).
#include <algorithm>
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

// The greatest distance of a chord's end from the circle about (cx, cy) of radius r, mm. The
// chords' ends drift inside the circle by theta^4 / 24 of the radius a chord (theta: the
// chord's angle), up to 0.0006 mm on radius 10 at 72 a turn, put right every 25th.
double off_circle(const GcodeStep& step, double cx, double cy, double r) {
  double worst = 0;
  for (const Motion& m : step.moves()) {
    worst = std::max(worst, std::abs(std::hypot(m.to.x - cx, m.to.y - cy) - r));
  }
  return worst;
}

TEST_CASE("g2_cuts_a_half_circle_about_i_j_into_72_chords_a_turn_at_its_feedrate") {
  GcodeState s;
  const GcodeStep arc = run(s, "G2 X10 Y0 I5 J0 E1 F600");
  // 5 pi mm of arc: 15 whole 1 mm chords, fewer than MIN_CIRCLE_SEGMENTS' 36 for half a turn.
  REQUIRE(arc.moves().size() == 36);
  CHECK(off_circle(arc, 5, 0, 5) < 1e-3);
  // The 25th chord ends where cos and sin put it, exactly on the circle.
  CHECK(std::hypot(arc.moves()[24].to.x - 5, arc.moves()[24].to.y) == doctest::Approx(5).epsilon(1e-12));
  CHECK(std::hypot(arc.moves()[23].to.x - 5, arc.moves()[23].to.y) < 5 - 1e-5);
  CHECK(arc.moves()[17].to.x == doctest::Approx(5).epsilon(1e-3));  // clockwise from (0, 0):
  CHECK(arc.moves()[17].to.y == doctest::Approx(5).epsilon(1e-3));  // over the top
  for (const Motion& m : arc.moves()) {
    CHECK(m.to.e - m.from.e == doctest::Approx(1.0 / 36));
    CHECK(m.feedrate == 10);
    CHECK(lays_filament(m));
  }
  CHECK(arc.moves().back().to.x == 10);
  CHECK(arc.moves().back().to.y == 0);
  CHECK(s.x == 10);
  CHECK(s.e == 1);
  const GcodeStep under = run(s, "G2 X0 Y0 I-5 J0");  // clockwise from (10, 0): under
  REQUIRE(under.moves().size() == 36);
  CHECK(under.moves()[17].to.y == doctest::Approx(-5).epsilon(1e-3));
}

TEST_CASE("an_arc_turns_the_way_its_g_says_the_long_way_round_if_need_be") {
  GcodeState s;
  // From (0, 0) about (5, 0) to (5, 5): clockwise a quarter turn, counter-clockwise three.
  const GcodeStep quarter = run(s, "G2 X5 Y5 I5");
  CHECK(quarter.moves().size() == 18);  // ceil(72 / 4)
  s = GcodeState{};
  const GcodeStep three = run(s, "G3 X5 Y5 I5");
  CHECK(three.moves().size() == 54);
  CHECK(off_circle(three, 5, 0, 5) < 1e-3);
  CHECK(three.moves()[17].to.y == doctest::Approx(-5).epsilon(1e-3));  // under the bottom first
}

TEST_CASE("r_puts_the_centre_on_the_chords_bisector_a_negative_r_on_the_long_side") {
  GcodeState s;
  // From (0, 0) to (10, 0) on radius 6: the centre is sqrt(11) from the chord's middle, below
  // it for a clockwise arc the short way (112.9 degrees: 23 chords, ceil(72 x 112.9 / 360)),
  // above it for R-6, the long way (247.1 degrees: 50 chords).
  const double h = std::sqrt(11.0);
  const GcodeStep short_way = run(s, "G2 X10 Y0 R6");
  CHECK(short_way.moves().size() == 23);
  CHECK(off_circle(short_way, 5, -h, 6) < 1e-3);
  CHECK(short_way.moves()[11].to.y > 2);
  s = GcodeState{};
  const GcodeStep long_way = run(s, "G2 X10 Y0 R-6");
  CHECK(long_way.moves().size() == 50);
  CHECK(off_circle(long_way, 5, h, 6) < 1e-3);
  s = GcodeState{};
  // R wins over I and J.
  CHECK(off_circle(run(s, "G2 X10 Y0 R6 I3 J3"), 5, -h, 6) < 1e-3);
}

TEST_CASE("an_arc_back_to_its_start_is_a_full_circle_of_1_mm_chords_at_least_72") {
  GcodeState s;
  const GcodeStep small = run(s, "G2 I5");  // 31.4 mm: the minimum of 72 chords
  CHECK(small.moves().size() == 72);
  CHECK(off_circle(small, 5, 0, 5) < 1e-3);
  CHECK(s.x == 0);
  // 314.16 mm: 314 chords would be over 1 mm (MAX_ARC_SEGMENT_MM), so 315.
  CHECK(run(s, "G3 I50").moves().size() == 315);
  // 0.063 mm: 72 chords would be under 0.1 mm (MIN_ARC_SEGMENT_MM), and fewer than one
  // fits: one chord, from the start to the start.
  CHECK(run(s, "G2 I0.01").moves().size() == 1);
}

TEST_CASE("z_and_e_change_evenly_along_an_arc") {
  GcodeState s = after("G1 Z1 E1");
  const GcodeStep helix = run(s, "G2 X10 I5 Z2 E3");
  REQUIRE(helix.moves().size() == 36);
  for (const Motion& m : helix.moves()) {
    CHECK(m.to.z - m.from.z == doctest::Approx(1.0 / 36));
    CHECK(m.to.e - m.from.e == doctest::Approx(2.0 / 36));
  }
  CHECK(s.z == 2);
}

TEST_CASE("an_arc_reads_its_words_in_the_current_modes_and_units") {
  GcodeState s = after("G1 X10\nG91");
  run(s, "G2 X10 I5");  // relative: to X 20 about X 15
  CHECK(s.x == 20);
  s = after("G20");
  const GcodeStep inches = run(s, "G2 X1 I0.5");
  CHECK(off_circle(inches, 12.7, 0, 12.7) < 1e-3);
  CHECK(s.x == doctest::Approx(25.4));
}

TEST_CASE("an_arc_without_a_centre_does_not_move_and_takes_its_f") {
  GcodeState s;
  GcodeStep none = run(s, "G2 X10 Y10 F600");
  CHECK(none.bad_arc);
  CHECK(none.moves().empty());
  CHECK(s.x == 0);
  CHECK(s.feedrate == 600);
  none = run(s, "G3 X10 R0 I5");  // R with a value is the form used; R0 is no centre
  CHECK(none.bad_arc);
  CHECK(s.x == 0);
  // An end equal to the start cannot be reached by R.
  CHECK(run(s, "G2 X0 Y0 R5").bad_arc);
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

TEST_CASE("with_teacups_rule_e_is_relative_while_g91_or_m83_holds") {
  GcodeState s;
  s.rules.e_relative_while_g91 = true;
  run(s, "M83");
  run(s, "G90");  // leaves M83's choice
  run(s, "G1 E1");
  run(s, "G1 E1");
  CHECK(s.e == 2);
  run(s, "M82");
  run(s, "G91");  // E relative again while G91 holds, M82 or not
  run(s, "G1 E1");
  CHECK(s.e == 3);
  run(s, "G90");
  run(s, "G1 E1");
  CHECK(s.e == 1);
}

TEST_CASE("with_teacups_rule_g92_reads_a_bare_axis_as_0_and_no_axis_as_all_four") {
  GcodeState s;
  s.rules.g92_bare_axis_is_zero = true;
  run(s, "G1 X10 Y20 Z3 E5");
  run(s, "G92 X Y7");
  CHECK(s.x == 0);
  CHECK(s.y == 7);
  CHECK(s.z == 3);
  CHECK(s.e == 5);
  run(s, "G92");
  CHECK(s.y == 0);
  CHECK(s.z == 0);
  CHECK(s.e == 0);
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

TEST_CASE("m201_to_m205_set_the_planners_limits_and_ignore_0_and_below") {
  const MotionLimits boot;
  CHECK_FALSE(motion_limits_after(boot, parse_gcode_line("M106 S255")));
  MotionLimits l = *motion_limits_after(boot, parse_gcode_line("M201 X500 Y0 E-3"));
  CHECK(l.max_acceleration[0] == 500);
  CHECK(l.max_acceleration[1] == boot.max_acceleration[1]);
  CHECK(l.max_acceleration[3] == boot.max_acceleration[3]);
  l = *motion_limits_after(l, parse_gcode_line("M203 Z5"));
  CHECK(l.max_speed[2] == 5);
  l = *motion_limits_after(l, parse_gcode_line("M204 S800 R2000"));
  CHECK(l.print_acceleration == 800);
  CHECK(l.travel_acceleration == 800);
  CHECK(l.retract_acceleration == 2000);
  l = *motion_limits_after(l, parse_gcode_line("M204 P600 T1200"));
  CHECK(l.print_acceleration == 600);
  CHECK(l.travel_acceleration == 1200);
  l = *motion_limits_after(l, parse_gcode_line("M205 J0.02 S10"));
  CHECK(l.junction_deviation == 0.02);
  CHECK(l.min_feedrate == 10);
  l = *motion_limits_after(l, parse_gcode_line("M205 J0 S0"));
  CHECK(l.junction_deviation == 0.02);
  CHECK(l.min_feedrate == 0);
}

TEST_CASE("g4_dwells_p_milliseconds_or_s_seconds_s_over_p") {
  CHECK(dwell_seconds(parse_gcode_line("G4 P250")) == 0.25);
  CHECK(dwell_seconds(parse_gcode_line("G4 S3")) == 3);
  CHECK(dwell_seconds(parse_gcode_line("G4 P250 S3")) == 3);
  CHECK(dwell_seconds(parse_gcode_line("G4")) == 0);
  CHECK(dwell_seconds(parse_gcode_line("G4 S-1")) == 0);
  CHECK_FALSE(dwell_seconds(parse_gcode_line("M400")));
}

}  // namespace gcode_interpreter_test
