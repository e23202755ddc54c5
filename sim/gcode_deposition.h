// The deposition record of a G-code program read straight through, without the serial line,
// the queue or the clock: what a printer that executes every line lays (sim/deposition.h).
// For checks of a G-code file on its own (sim/unsupported_extrusion.h): the same record the
// simulated printer keeps while it prints the file, move for move, since both read the
// lines with printer/gcode_line.h in Marlin's modes.
//
// Read: G0/G1 (X Y Z E F), G90/G91 (both also set E's mode, as Marlin's do), M82/M83, G92,
// G28 (homed axes to 0), M221 S (flow percent). G2/G3 arcs are not read (neither the
// slicers compared here nor mahost write them). A move records when E grows while X or Y
// moves. Any text is read; lines that are not G-code are skipped.
#pragma once

#include <string_view>

#include "sim/deposition.h"

namespace sim {

DepositionRecord deposition_from_gcode(std::string_view program);

}  // namespace sim
