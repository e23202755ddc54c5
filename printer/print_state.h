// The state a G-code stream leaves the printer in, followed command by command: position,
// positioning and extruder modes, feedrate (printer/gcode_interpreter.h's rules, Marlin's),
// heater targets, fan.
//
// Input: commands in the order the printer runs them. Output: what the firmware would hold
// after them, for what a pause must restore (modes, feedrate), what a journal records at
// each layer start (E, Z, temperatures), and the filament a job feeds.
// Units: mm, mm/min (feedrate, F in mm), °C, fan 0-255.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "printer/gcode_interpreter.h"
#include "printer/gcode_line.h"

namespace printer {

// The interpreter's state (position, modes, feedrate, units, retraction, layer), and:
struct PrintState : GcodeState {
  double hotend_target = 0, bed_target = 0;  // °C
  // Whether a command has set each target (M104/M109 S, M140/M190 S): until then the
  // targets above are not the file's, and a printer's own report is the better word.
  bool hotend_target_set = false, bed_target_set = false;
  int fan = 0;                        // 0-255
  double filament_fed = 0;            // mm of filament fed, net of retractions, in total
};

// Applies one command to the state. Commands that do not change it are ignored.
void apply(PrintState& state, const GcodeCommand& command);
void apply(PrintState& state, std::string_view command);

// The commands that put a firmware in `state`'s modes and feedrate (not its position):
// "G90"/"G91", "M82"/"M83", "G1 F<f>".
std::vector<std::string> restore_modes(const PrintState& state);

}  // namespace printer
