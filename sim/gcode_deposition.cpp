#include "sim/gcode_deposition.h"

#include "printer/gcode_interpreter.h"
#include "printer/gcode_line.h"

namespace sim {

DepositionRecord deposition_from_gcode(std::string_view program) {
  DepositionRecord record;
  printer::GcodeState state;
  while (!program.empty()) {
    const std::size_t end = program.find('\n');
    const std::string_view line = program.substr(0, end);
    program.remove_prefix(end == std::string_view::npos ? program.size() : end + 1);
    const printer::GcodeStep step = printer::interpret(state, printer::parse_gcode_line(line));
    for (const printer::Motion& move : step.moves()) {
      if (!printer::lays_filament(move)) continue;
      const double fed = (move.to.e - move.from.e) * state.flow / 100;
      if (fed > 0) {
        record.add(move.to.z, {move.from.x, move.from.y}, {move.to.x, move.to.y}, fed,
                   move.feedrate);
      }
    }
  }
  return record;
}

}  // namespace sim
