// The print-time estimate reads G-code as Marlin does: modal feedrate, relative modes, G92,
// homing, dwell and limit changes, each timed against hand-computed trapezoids.
#include <cmath>

#include <doctest/doctest.h>

#include "printer/print_time.h"

namespace print_time_test {

using namespace printer;

namespace {

MotionLimits plain_limits() {
  MotionLimits limits;
  limits.max_speed = {1000, 1000, 1000, 1000};
  limits.max_acceleration = {1e6, 1e6, 1e6, 1e6};
  limits.print_acceleration = limits.travel_acceleration = limits.retract_acceleration = 1000;
  return limits;
}

// A move from rest to rest reaching cruise speed v: two ramps of v/a and the cruise.
double rest_to_rest(double d, double v, double a) { return 2 * v / a + (d - v * v / a) / v; }

}  // namespace

TEST_CASE("feedrate_is_in_mm_per_minute_and_modal") {
  // Two moves out and back (a reversal: each stops), both at F3000 = 50 mm/s.
  const double t = estimate_print_time("G1 X100 F3000\nG1 X0\n", plain_limits());
  CHECK(t == doctest::Approx(2 * rest_to_rest(100, 50, 1000)).epsilon(1e-12));
}

TEST_CASE("default_feedrate_is_marlins_25_mm_per_s") {
  CHECK(estimate_print_time("G0 X100\n", plain_limits()) ==
        doctest::Approx(rest_to_rest(100, 25, 1000)).epsilon(1e-12));
}

TEST_CASE("relative_moves_add_to_the_position") {
  // G91: X10 four times is a 40 mm straight move in four collinear pieces.
  const double t = estimate_print_time("G91\nG1 X10 F3000\nG1 X10\nG1 X10\nG1 X10\n", plain_limits());
  CHECK(t == doctest::Approx(rest_to_rest(40, 50, 1000)).epsilon(1e-12));
}

TEST_CASE("g92_sets_position_without_motion") {
  const double t = estimate_print_time("G92 X50\nG1 X100 F3000\n", plain_limits());
  CHECK(t == doctest::Approx(rest_to_rest(50, 50, 1000)).epsilon(1e-12));
}

TEST_CASE("m83_makes_e_relative_and_g90_makes_it_absolute_again") {
  PrintClock clock(plain_limits());
  clock.line("M83");
  clock.line("G1 E2 F1200");
  clock.line("G1 E2");
  CHECK(clock.position().e == 4);
  clock.line("G90");
  CHECK_FALSE(clock.relative_e());
  clock.line("G1 E1");
  CHECK(clock.position().e == 1);
}

TEST_CASE("homing_drains_and_zeroes_the_named_axes") {
  PrintClock clock(plain_limits());
  clock.line("G1 X100 Y20 Z5 F6000");
  clock.line("G28 X");
  CHECK(clock.position().x == 0);
  CHECK(clock.position().y == 20);
  CHECK(clock.moves_queued() == 1);
  CHECK(clock.moves_final() == 1);  // drained before homing
  clock.line("G28");
  CHECK(clock.position().z == 0);
}

TEST_CASE("firmware_retraction_moves_the_filament_at_marlins_feedrates") {
  // G10: 3 mm back at 45 mm/s; G11: 3 mm forward at 8 mm/s (Marlin's defaults), each an
  // E-only move at the retract acceleration; the position the G-code sees stays.
  PrintClock clock(plain_limits());
  clock.line("G10");
  clock.line("G11");
  CHECK(clock.finish() ==
        doctest::Approx(rest_to_rest(3, 45, 1000) + rest_to_rest(3, 8, 1000)).epsilon(1e-12));
  CHECK(clock.position().e == 0);
}

TEST_CASE("g20_moves_and_feedrates_are_in_inches") {
  // 2 in at 60 in/min: 50.8 mm at 25.4 mm/s.
  const double t = estimate_print_time("G20\nG1 X2 F60\n", plain_limits());
  CHECK(t == doctest::Approx(rest_to_rest(50.8, 25.4, 1000)).epsilon(1e-12));
}

TEST_CASE("dwell_adds_its_time") {
  CHECK(estimate_print_time("G4 P500\nG4 S2\n", plain_limits()) == doctest::Approx(2.5));
}

TEST_CASE("a_dwell_of_p_and_s_waits_s_as_marlin_and_the_simulator_do") {
  // G4.cpp: S replaces P. The estimate waited both (3.5 s).
  CHECK(estimate_print_time("G4 P1500 S2\n", plain_limits()) == doctest::Approx(2));
}

TEST_CASE("m204_changes_acceleration_for_later_moves") {
  const double t = estimate_print_time("M204 T500\nG0 X100 F3000\n", plain_limits());
  CHECK(t == doctest::Approx(rest_to_rest(100, 50, 500)).epsilon(1e-12));
  const double p = estimate_print_time("M204 P250\nG1 X100 E5 F3000\n", plain_limits());
  CHECK(p == doctest::Approx(rest_to_rest(100, 50, 250)).epsilon(1e-12));
}

TEST_CASE("m203_caps_axis_speed") {
  const double t = estimate_print_time("M203 X20\nG0 X100 F3000\n", plain_limits());
  CHECK(t == doctest::Approx(rest_to_rest(100, 20, 1000)).epsilon(1e-12));
}

TEST_CASE("m205_s_raises_slow_moves_to_the_minimum_feedrate") {
  // F60 = 1 mm/s, raised to M205 S10's 10 mm/s as the simulated printer does; the estimate
  // ignored M205 S.
  const double t = estimate_print_time("M205 S10\nG0 X100 F60\n", plain_limits());
  CHECK(t == doctest::Approx(rest_to_rest(100, 10, 1000)).epsilon(1e-12));
}

TEST_CASE("arcs_take_the_time_of_their_chords") {
  // A full circle of radius 50 at 50 mm/s: 315 chords of 0.997 mm; the planner goes round
  // near 50 mm/s, so about the 314.16 mm circumference / 50 mm/s, more than the nothing a
  // straight line to the start took.
  const double t = estimate_print_time("G1 X50 F3000\nG2 X50 Y0 I-50 J0\n", plain_limits());
  const double line = rest_to_rest(50, 50, 1000);
  CHECK(t - line > 2 * M_PI * 50 / 50);
  CHECK(t - line < 2 * M_PI * 50 / 50 + 0.2);
}

TEST_CASE("comments_and_unknown_commands_take_no_time") {
  CHECK(estimate_print_time(";LAYER:0\nM106 S255\nM117 hello\n\n   ; indented\n", plain_limits()) == 0);
}

TEST_CASE("moves_become_final_a_window_later") {
  PrintClock clock(plain_limits(), 2);
  clock.line("G1 X10 F3000");
  clock.line("G1 X10");  // no motion: not a move
  clock.line("G1 X20");
  CHECK(clock.moves_queued() == 2);
  CHECK(clock.moves_final() == 0);
  clock.line("G1 X30");
  CHECK(clock.moves_final() == 1);
  CHECK(clock.elapsed() > 0);
  clock.finish();
  CHECK(clock.moves_final() == 3);
  CHECK(clock.elapsed() == doctest::Approx(rest_to_rest(30, 50, 1000)).epsilon(1e-12));
}

}  // namespace print_time_test
