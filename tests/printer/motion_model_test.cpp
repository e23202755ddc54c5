// The motion model against trapezoids, triangles and junctions worked out by hand.
#include <cmath>
#include <numbers>

#include <doctest/doctest.h>

#include "printer/motion_model.h"

namespace motion_model_test {

using printer::AxisPosition;
using printer::MotionLimits;
using printer::MotionModel;

namespace {

// Generous axis limits so that only the quantity under test binds.
MotionLimits plain_limits(double acceleration) {
  MotionLimits limits;
  limits.max_speed = {1000, 1000, 1000, 1000};
  limits.max_acceleration = {1e6, 1e6, 1e6, 1e6};
  limits.print_acceleration = acceleration;
  limits.travel_acceleration = acceleration;
  limits.retract_acceleration = acceleration;
  limits.junction_deviation = 0.013;
  return limits;
}

// Time of a move from v0 to v1 through cruise speed v over distance d at acceleration a,
// when it does reach v: two ramps and a cruise.
double trapezoid(double d, double v, double a, double v0, double v1) {
  const double ramp_up = (v * v - v0 * v0) / (2 * a), ramp_down = (v * v - v1 * v1) / (2 * a);
  return (v - v0) / a + (v - v1) / a + (d - ramp_up - ramp_down) / v;
}

}  // namespace

TEST_CASE("long_move_is_a_trapezoid") {
  // 100 mm at 50 mm/s, 1000 mm/s^2: 0.05 s and 1.25 mm to speed up, the same to stop,
  // 97.5 mm at 50 mm/s = 1.95 s; 2.05 s in all.
  MotionModel model(plain_limits(1000));
  model.push({100, 0, 0, 0}, 50);
  CHECK(model.flush() == doctest::Approx(2.05).epsilon(1e-12));
  CHECK(model.total_time() == doctest::Approx(2.05).epsilon(1e-12));
  CHECK(model.pending() == 0);
}

TEST_CASE("short_move_is_a_triangle") {
  // 1 mm asking for 100 mm/s at 1000 mm/s^2: it would need 5 mm to reach speed, so it peaks
  // halfway at sqrt(a d) and takes 2 sqrt(d / a).
  MotionModel model(plain_limits(1000));
  model.push({0, 1, 0, 0}, 100);
  CHECK(model.flush() == doctest::Approx(2 * std::sqrt(1.0 / 1000)).epsilon(1e-12));
}

TEST_CASE("collinear_moves_join_at_full_speed") {
  // Two 50 mm moves in the same direction take as long as one 100 mm move.
  MotionModel model(plain_limits(1000));
  model.push({50, 0, 0, 0}, 50);
  model.push({100, 0, 0, 0}, 50);
  CHECK(model.flush() == doctest::Approx(2.05).epsilon(1e-9));
}

TEST_CASE("right_angle_corner_slows_to_junction_deviation_speed") {
  // 50 mm along X, then 50 mm along Y, at 50 mm/s, 1000 mm/s^2, junction deviation 0.013 mm:
  // cos_theta = 0, s = sin 45 deg, v_j^2 = a * jd * s / (1 - s) = 31.38..., v_j = 5.60 mm/s.
  MotionModel model(plain_limits(1000));
  model.push({50, 0, 0, 0}, 50);
  model.push({50, 50, 0, 0}, 50);
  const double s = std::sqrt(0.5);
  const double vj = std::sqrt(1000 * 0.013 * s / (1 - s));
  const double expected = 2 * trapezoid(50, 50, 1000, 0, vj);
  CHECK(model.flush() == doctest::Approx(expected).epsilon(1e-12));
  CHECK(vj == doctest::Approx(5.6022).epsilon(1e-4));
}

TEST_CASE("reversal_stops_dead") {
  // Out and back: the junction speed is zero, each leg is a trapezoid from rest to rest.
  MotionModel model(plain_limits(1000));
  model.push({20, 0, 0, 0}, 50);
  model.push({0, 0, 0, 0}, 50);
  CHECK(model.flush() == doctest::Approx(2 * trapezoid(20, 50, 1000, 0, 0)).epsilon(1e-12));
}

TEST_CASE("axis_speed_limit_caps_nominal_speed") {
  // A Z move asked for 50 mm/s on an axis limited to 10 mm/s and 100 mm/s^2:
  // 0.1 s and 0.5 mm to reach 10 mm/s, the same to stop, 9 mm cruise = 0.9 s: 1.1 s.
  MotionLimits limits = plain_limits(1000);
  limits.max_speed[2] = 10;
  limits.max_acceleration[2] = 100;
  MotionModel model(limits);
  model.push({0, 0, 10, 0}, 50);
  CHECK(model.flush() == doctest::Approx(1.1).epsilon(1e-12));
}

TEST_CASE("diagonal_move_is_held_by_its_fastest_axis") {
  // (30, 40) at 200 mm/s: X would run at 120 mm/s; with X limited to 100 the move cruises at
  // 200 * 100 / 120. Y, limited to 900 mm/s^2, sees 0.8 * 1000 = 800: the acceleration stays.
  MotionLimits limits = plain_limits(1000);
  limits.max_speed[0] = 100;
  limits.max_acceleration[1] = 900;
  MotionModel model(limits);
  model.push({30, 40, 0, 0}, 200);
  const double v = 200.0 * 100.0 / 120.0;
  CHECK(model.flush() == doctest::Approx(trapezoid(50, v, 1000, 0, 0)).epsilon(1e-12));
}

TEST_CASE("axis_acceleration_limit_caps_move_acceleration") {
  // (30, 40) with Y limited to 400 mm/s^2: the move's acceleration is 400 / 0.8 = 500.
  MotionLimits limits = plain_limits(1000);
  limits.max_acceleration[1] = 400;
  MotionModel model(limits);
  model.push({30, 40, 0, 0}, 50);
  CHECK(model.flush() == doctest::Approx(trapezoid(50, 50, 500, 0, 0)).epsilon(1e-12));
}

TEST_CASE("extruding_move_uses_print_acceleration_and_extruder_speed_limit") {
  // 10 mm of X extruding 20 mm of filament at 50 mm/s: E would run at 100 mm/s, its limit 60
  // holds the move to 30 mm/s; the print acceleration (500) applies, not the travel one.
  MotionLimits limits = plain_limits(1000);
  limits.print_acceleration = 500;
  limits.max_speed[3] = 60;
  MotionModel model(limits);
  model.push({10, 0, 0, 20}, 50);
  CHECK(model.flush() == doctest::Approx(trapezoid(10, 30, 500, 0, 0)).epsilon(1e-12));
}

TEST_CASE("retraction_uses_retract_acceleration") {
  // E alone, -2 mm at 40 mm/s, 3000 mm/s^2: the length of the move is |E|.
  MotionLimits limits = plain_limits(1000);
  limits.retract_acceleration = 3000;
  MotionModel model(limits);
  model.set_position({5, 5, 0.2, 10});
  model.push({5, 5, 0.2, 8}, 40);
  CHECK(model.flush() == doctest::Approx(trapezoid(2, 40, 3000, 0, 0)).epsilon(1e-12));
  CHECK(model.position().e == 8);
}

TEST_CASE("short_segments_of_a_curve_are_held_to_arc_speed") {
  // Two 0.5 mm segments turning by 40 degrees, junction deviation large (0.1 mm) so that the
  // arc limit binds: v_j^2 = a * length / angle = 1000 * 0.5 / (40 deg in rad).
  MotionLimits limits = plain_limits(1000);
  limits.junction_deviation = 0.1;
  MotionModel model(limits);
  const double angle = 40.0 * std::numbers::pi / 180.0;
  model.push({0.5, 0, 0, 0}, 100);
  model.push({0.5 + 0.5 * std::cos(angle), 0.5 * std::sin(angle), 0, 0}, 100);
  const double vj_sqr = 1000 * 0.5 / angle;
  // Junction deviation alone would allow more: s = cos 20 deg.
  const double s = std::cos(angle / 2);
  REQUIRE(1000 * 0.1 * s / (1 - s) > vj_sqr);
  // Each segment is a triangle between rest and v_j: peak^2 = v_j^2 / 2 + a d.
  const double peak = std::sqrt(vj_sqr / 2 + 1000 * 0.5);
  const double one = (peak - 0) / 1000 + (peak - std::sqrt(vj_sqr)) / 1000;
  CHECK(model.flush() == doctest::Approx(2 * one).epsilon(1e-12));
}

TEST_CASE("a_short_segments_gentle_turn_is_held_by_junction_deviation_where_the_arc_allows_more") {
  // Two 0.9 mm segments turning by 30 degrees, junction deviation 0.013 mm: v_j^2 = a * 0.013
  // * s / (1 - s), s = cos 15 deg, about 368 (mm/s)^2, under the arc's a * 0.9 / (30 deg in
  // rad), about 1719.
  MotionModel model(plain_limits(1000));
  const double angle = 30.0 * std::numbers::pi / 180.0;
  model.push({0.9, 0, 0, 0}, 100);
  model.push({0.9 + 0.9 * std::cos(angle), 0.9 * std::sin(angle), 0, 0}, 100);
  const double s = std::cos(angle / 2);
  const double vj_sqr = 1000 * 0.013 * s / (1 - s);
  REQUIRE(1000 * 0.9 / angle > vj_sqr);
  // Each segment is a triangle between rest and v_j: peak^2 = v_j^2 / 2 + a d.
  const double peak = std::sqrt(vj_sqr / 2 + 1000 * 0.9);
  const double one = peak / 1000 + (peak - std::sqrt(vj_sqr)) / 1000;
  CHECK(model.flush() == doctest::Approx(2 * one).epsilon(1e-12));
  CHECK(model.blocks() == 2);
}

TEST_CASE("full_lookahead_equals_one_long_move") {
  // Ten collinear 1 mm moves at 100 mm/s, 1000 mm/s^2, all in the window: one 10 mm triangle
  // peaking at exactly 100 mm/s, 2 * 10 / 100 = 0.2 s.
  MotionModel model(plain_limits(1000), 16);
  for (int i = 1; i <= 10; ++i) CHECK(model.push({double(i), 0, 0, 0}, 100) == 0);
  CHECK(model.pending() == 10);
  CHECK(model.flush() == doctest::Approx(0.2).epsilon(1e-12));
}

TEST_CASE("short_lookahead_must_be_able_to_stop_in_the_window") {
  // The same ten moves with one move of look-ahead: each exit must allow a stop within the
  // next 1 mm, v^2 <= 2 a d = 2000. The first move ramps 0 -> sqrt(2000); the middle eight go
  // sqrt(2000) -> sqrt(3000) -> sqrt(2000); the last ramps down to rest.
  MotionModel model(plain_limits(1000), 1);
  double finalized = 0;
  CHECK(model.push({1, 0, 0, 0}, 100) == 0);
  CHECK(model.pending() == 1);
  for (int i = 2; i <= 10; ++i) {
    const double seconds = model.push({double(i), 0, 0, 0}, 100);
    CHECK(seconds > 0);
    CHECK(model.pending() == 1);
    finalized += seconds;
  }
  const double v2 = std::sqrt(2000.0), v3 = std::sqrt(3000.0);
  const double ramp = v2 / 1000;
  const double middle = 2 * (v3 - v2) / 1000;
  CHECK(finalized == doctest::Approx(ramp + 8 * middle).epsilon(1e-12));
  CHECK(model.flush() == doctest::Approx(ramp).epsilon(1e-12));
  CHECK(model.total_time() == doctest::Approx(2 * ramp + 8 * middle).epsilon(1e-12));
}

TEST_CASE("moves_finalize_when_they_leave_the_window") {
  MotionModel model(plain_limits(1000), 3);
  for (int i = 1; i <= 3; ++i) CHECK(model.push({10.0 * i, 0, 0, 0}, 50) == 0);
  CHECK(model.pending() == 3);
  CHECK(model.total_time() == 0);
  CHECK(model.push({40, 0, 0, 0}, 50) > 0);
  CHECK(model.pending() == 3);
  model.flush();
  // 40 mm straight: one trapezoid whatever the window, since 3 moves (30 mm) can always stop.
  CHECK(model.total_time() == doctest::Approx(trapezoid(40, 50, 1000, 0, 0)).epsilon(1e-12));
}

TEST_CASE("zero_length_move_takes_no_time") {
  MotionModel model(plain_limits(1000));
  model.set_position({3, 4, 5, 6});
  CHECK(model.push({3, 4, 5, 6}, 50) == 0);
  CHECK(model.pending() == 0);
  CHECK(model.blocks() == 0);
  CHECK(model.flush() == 0);
  CHECK(model.total_time() == 0);
}

TEST_CASE("flush_drains_so_next_move_starts_from_rest") {
  // Two collinear moves separated by a flush (as M400 does) are two separate trapezoids.
  MotionModel model(plain_limits(1000));
  model.push({50, 0, 0, 0}, 50);
  model.flush();
  model.push({100, 0, 0, 0}, 50);
  model.flush();
  CHECK(model.total_time() == doctest::Approx(2 * trapezoid(50, 50, 1000, 0, 0)).epsilon(1e-12));
}

TEST_CASE("set_position_moves_without_time") {
  MotionModel model(plain_limits(1000));
  model.set_position({10, 20, 0.3, 0});
  CHECK(model.position().x == 10);
  model.push({10, 30, 0.3, 0}, 50);
  CHECK(model.flush() == doctest::Approx(trapezoid(10, 50, 1000, 0, 0)).epsilon(1e-12));
}

TEST_CASE("non_positive_feedrate_runs_at_axis_limit") {
  MotionLimits limits = plain_limits(1000);
  limits.max_speed[0] = 40;
  MotionModel model(limits);
  model.push({100, 0, 0, 0}, 0);
  CHECK(model.flush() == doctest::Approx(trapezoid(100, 40, 1000, 0, 0)).epsilon(1e-12));
}

TEST_CASE("limits_change_applies_to_later_moves") {
  MotionModel model(plain_limits(1000));
  model.push({100, 0, 0, 0}, 50);
  model.flush();
  MotionLimits slower = model.limits();
  slower.travel_acceleration = 500;
  model.set_limits(slower);
  CHECK(model.limits().travel_acceleration == 500);
  model.push({0, 0, 0, 0}, 50);
  CHECK(model.flush() == doctest::Approx(trapezoid(100, 50, 500, 0, 0)).epsilon(1e-12));
}

}  // namespace motion_model_test
