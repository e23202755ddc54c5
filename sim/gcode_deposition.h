// The deposition record of a G-code program read straight through, without the serial line,
// the queue or the clock: what a printer that executes every line lays (sim/deposition.h).
// For checks of a G-code file on its own (sim/unsupported_extrusion.h): the same record the
// simulated printer keeps while it prints the file, move for move, since both read the
// lines with printer/gcode_line.h in Marlin's modes.
//
// Read by printer/gcode_interpreter.h's rules (Marlin's: modes, units, G92, G28, firmware
// retraction, M221 flow). A move records when E grows while X or Y moves, its filament times
// the flow. Any text is read; lines that are not G-code are skipped.
#pragma once

#include <string_view>

#include "sim/deposition.h"

namespace sim {

DepositionRecord deposition_from_gcode(std::string_view program);

}  // namespace sim
