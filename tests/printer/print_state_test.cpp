// PrintState follows the heater targets the commands set, and knows which ones they set.
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

}  // namespace print_state_test
