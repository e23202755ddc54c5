#include "printer/print_state.h"

#include <cmath>
#include <string>
#include <vector>

#include <fmt/core.h>

namespace printer {

void apply(PrintState& s, const GcodeCommand& c) {
  const GcodeStep step = interpret(s, c);
  for (const Motion& move : step.moves()) s.filament_fed += move.to.e - move.from.e;
  if (c.letter != 'M') return;
  switch (c.code) {
    case 104: case 109:
      if (const auto t = c.get('S')) {
        s.hotend_target = *t;
        s.hotend_target_set = true;
      }
      break;
    case 140: case 190:
      if (const auto t = c.get('S')) {
        s.bed_target = *t;
        s.bed_target_set = true;
      }
      break;
    case 106: s.fan = static_cast<int>(std::lround(c.get('S').value_or(255))); break;
    case 107: s.fan = 0; break;
    default: break;
  }
}

void apply(PrintState& state, std::string_view command) { apply(state, parse_gcode_line(command)); }

std::vector<std::string> restore_modes(const PrintState& state) {
  std::vector<std::string> commands;
  commands.push_back(state.relative_xyz ? "G91" : "G90");
  commands.push_back(state.relative_e ? "M83" : "M82");
  // A file in inches goes on in inches, its F too.
  if (state.unit != 1) commands.push_back("G20");
  if (state.feedrate > 0) {
    // In inches to the micro-inch: F as the file wrote it, not 25.4's rounding.
    const double f = state.unit == 1 ? state.feedrate
                                     : std::round(state.feedrate / state.unit * 1e6) / 1e6;
    commands.push_back(fmt::format("G1 F{}", f));
  }
  return commands;
}

}  // namespace printer
