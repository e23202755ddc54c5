// PrintState follows the heater targets the commands set, and knows which ones they set; its
// position and modes are printer/gcode_interpreter.h's (Marlin's rules).
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "printer/print_state.h"

namespace print_state_test {

using printer::apply;
using printer::PrintState;

TEST_CASE("a_heater_target_counts_as_set_only_by_a_command_with_s") {
  PrintState s;
  CHECK_FALSE(s.hotend_target_set);
  CHECK_FALSE(s.bed_target_set);
  apply(s, "M109 R200");  // Marlin's wait-for-cooling form without S sets no S target here
  CHECK_FALSE(s.hotend_target_set);
  apply(s, "M104 S245");
  CHECK(s.hotend_target_set);
  CHECK(s.hotend_target == 245);
  CHECK_FALSE(s.bed_target_set);
  apply(s, "M190 S100");
  CHECK(s.bed_target_set);
  CHECK(s.bed_target == 100);
  apply(s, "M140 S0");  // turning a heater off is setting its target too
  CHECK(s.bed_target_set);
  CHECK(s.bed_target == 0);
}

TEST_CASE("a_bare_g92_leaves_the_position_as_marlin_does") {
  PrintState s;
  apply(s, "G1 X10 Y20 Z0.3 E5");
  apply(s, "G92");  // Marlin 2's G92.cpp sets only the axes given with a value
  CHECK(s.x == 10);
  CHECK(s.y == 20);
  CHECK(s.z == 0.3);
  CHECK(s.e == 5);
}

TEST_CASE("f0_keeps_the_feedrate_a_pause_restores") {
  PrintState s;
  apply(s, "G1 X10 F1800");
  apply(s, "G1 X20 F0");
  CHECK(s.feedrate == 1800);
  CHECK(printer::restore_modes(s).back() == "G1 F1800");
}

TEST_CASE("firmware_retraction_counts_in_the_filament_fed") {
  PrintState s;
  apply(s, "G1 X10 E5");
  apply(s, "G10");  // 3 mm back (Marlin's RETRACT_LENGTH)
  CHECK(s.filament_fed == doctest::Approx(2));
  CHECK(s.e == 5);
  apply(s, "G11");
  CHECK(s.filament_fed == doctest::Approx(5));
}

TEST_CASE("a_file_in_inches_is_restored_in_inches") {
  PrintState s;
  apply(s, "G20");
  apply(s, "G1 X1 F60");
  CHECK(s.x == doctest::Approx(25.4));
  const std::vector<std::string> modes = printer::restore_modes(s);
  REQUIRE(modes.size() == 4);
  CHECK(modes[2] == "G20");
  CHECK(modes[3] == "G1 F60");
}

}  // namespace print_state_test
