// The heater model (sim/heater.h) against its closed forms.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "sim/heater.h"

namespace heater_test {

namespace {
sim::HeaterConstants hotend() { return {120, 4, 1, 10}; }  // ceiling 20 + 480 = 500 °C
}  // namespace

TEST_CASE("heater_rises_exponentially_toward_its_ceiling_then_holds") {
  sim::Heater heater(hotend(), 20);
  heater.set_target(210);
  heater.advance_to(30);
  CHECK(heater.temperature() == doctest::Approx(500 - 480 * std::exp(-30.0 / 120)));
  CHECK(heater.power() == 127);
  const double reach = 120 * std::log(480.0 / 290.0);
  CHECK(heater.time_reaching(210) == doctest::Approx(reach));
  CHECK(heater.time_reaching(200) == doctest::Approx(120 * std::log(480.0 / 300.0)));
  heater.advance_to(reach + 100);
  CHECK(heater.temperature() == 210);
  CHECK(heater.power() == std::lround(127 * 190.0 / 480.0));
}

TEST_CASE("heater_cools_to_a_lower_target_and_holds_it") {
  sim::Heater heater(hotend(), 20);
  heater.set_target(210);
  heater.advance_to(200);
  heater.set_target(110);
  CHECK(heater.power() == 0);
  const double reach = heater.time() + 120 * std::log(190.0 / 90.0);
  CHECK(heater.time_reaching(110) == doctest::Approx(reach));
  heater.advance_to(reach + 50);
  CHECK(heater.temperature() == 110);
}

TEST_CASE("heater_off_decays_to_ambient_and_never_reaches_it") {
  sim::Heater heater(hotend(), 20);
  heater.set_target(100);
  heater.advance_to(100);
  heater.set_target(0);
  const double t0 = heater.time(), start = heater.temperature();
  heater.advance_to(t0 + 60);
  CHECK(heater.temperature() == doctest::Approx(20 + (start - 20) * std::exp(-0.5)));
  CHECK(heater.time_reaching(20) == std::numeric_limits<double>::infinity());
}

TEST_CASE("target_above_the_ceiling_is_never_reached") {
  sim::Heater heater(hotend(), 20);
  heater.set_target(600);
  CHECK(heater.time_reaching(600) == std::numeric_limits<double>::infinity());
  heater.advance_to(10000);
  CHECK(heater.temperature() == doctest::Approx(500));
}

TEST_CASE("failed_heater_falls_whatever_its_target") {
  sim::Heater heater(hotend(), 20);
  heater.set_target(200);
  heater.advance_to(300);
  heater.fail();
  CHECK(heater.power() == 0);
  CHECK(heater.time_reaching(196) == doctest::Approx(300 + 120 * std::log(180.0 / 176.0)));
  CHECK(heater.time_reaching(200.5) == std::numeric_limits<double>::infinity());
}

}  // namespace heater_test
