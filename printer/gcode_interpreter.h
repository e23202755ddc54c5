// G-code read as Marlin runs it: the one set of rules behind every reader of a program in
// mahost (the print-time estimate, the host's position tracking, the layer finder, the
// simulator's deposition record, the tests' bead reader), so that they agree on every file.
//
// Input: commands (printer/gcode_line.h) in the order the firmware runs them. Output: the
// state they leave (position, modes, units, feedrate, flow, firmware retraction, the layer and
// feature comments) and, per command, the straight moves the firmware's planner is given.
// The rules, each from Marlin 2's source (Marlin/src/...):
//   G0/G1     an axis word moves its axis, absolute or relative by the mode; F above 0 sets the
//             modal feedrate, F0 and below are ignored (gcode/motion/G0_G1.cpp,
//             get_destination_from_command in gcode/gcode.cpp). G2/G3 go straight to their
//             end point: the arc's I J R are not followed (mahost and the slicers compared here
//             write none).
//   G90/G91   every axis absolute/relative, E included: set_relative_mode() assigns all the
//             mode bits, also clearing what M82/M83 set (gcode/gcode.h).
//   M82/M83   E alone absolute/relative (set_e_absolute/set_e_relative, gcode/gcode.h).
//   G20/G21   inches/mm: X Y Z E and F are read times 25.4 after G20 (parser.h,
//             set_input_linear_units and value_axis_units; gcode/units/G20_G21.cpp).
//   G92       sets each axis given with a value to it; an axis without a value ("G92 X") and
//             G92 with no axis change nothing, and E is set directly; G92.1 and G92.9 are
//             ignored, as without CNC_COORDINATE_SYSTEMS and POWER_LOSS_RECOVERY, Marlin's
//             default (gcode/geometry/G92.cpp: only parser.seenval axes; "default: return").
//   G28       homes the axes named, or X, Y and Z when none or all are named; a homed axis is
//             at its home, 0 here (a minimum endstop at the bed's origin); E is not touched
//             (gcode/calibrate/G28.cpp: home_all = homeX == homeY && homeX == homeZ).
//   G10/G11   firmware retraction: G10 pulls the filament back by the retract length at the
//             retract feedrate and raises Z by the retract Z-raise, G11 lowers Z and feeds
//             the length plus the recover extra at the recover feedrate; a second G10 or G11
//             in a row does nothing; the G-code's own X Y Z E stay as they were
//             (feature/fwretract.cpp). M207 S F Z and M208 S F set them (gcode/feature/fwretract/
//             M207-M209.cpp).
//   M221 S    the flow, percent of every later extrusion (gcode/config/M221.cpp).
// Comments: ";LAYER:<n>" (mahost, CuraEngine) starts layer n, ";TYPE:<name>" a feature.
// Units: mm, mm/min for F (as written, times 25.4 after G20), mm/s for a move's feedrate.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>

#include "printer/gcode_line.h"
#include "printer/motion_model.h"

namespace printer {

// Marlin's firmware retraction settings, its defaults (Configuration_adv.h, FWRETRACT).
struct FirmwareRetraction {
  double length = 3;            // mm of filament, G10
  double feedrate = 45;         // mm/s
  double z_raise = 0;           // mm
  double recover_extra = 0;     // mm of filament added on G11
  double recover_feedrate = 8;  // mm/s
};

// What a printer holds after the commands read so far.
struct GcodeState {
  double x = 0, y = 0, z = 0, e = 0;  // the G-code's coordinates, mm
  double feedrate = 0;                // mm/min, the last F above 0 (in mm); 0 before any
  bool relative_xyz = false;          // G91
  bool relative_e = false;            // M83 or G91
  double unit = 1;                    // mm per unit of X Y Z E F: 1 (G21), 25.4 (G20)
  double flow = 100;                  // percent, M221
  bool homed = false;                 // a G28 has run
  FirmwareRetraction retraction;
  bool retracted = false;             // by G10, until G11
  double hop = 0;                     // mm the nozzle stands above z (G10's Z-raise)
  double filament_offset = 0;         // mm: where the filament is, less e (G10, G11)
  long layer = -1;                    // the last ";LAYER:<n>"; -1 before any
  std::string type;                   // the last ";TYPE:<name>"; "" before any
};

// One straight move the planner is given: the nozzle (z with the hop) and the filament (e
// with the retraction), mm.
struct Motion {
  AxisPosition from, to;
  double feedrate = 0;  // mm/s; 0: no F yet (the firmware's default); infinite: axes' maximum
};

// Does the move lay filament: E forward while X or Y moves?
bool lays_filament(const Motion& move);

// What one command did.
struct GcodeStep {
  std::array<Motion, 2> motions;
  std::size_t count = 0;       // motions used
  bool homed = false;          // a G28 ran: the position jumped after the planner drained
  bool position_set = false;   // G28 or G92: the position changed without moving
  bool layer_started = false;  // a ";LAYER:" comment
  bool type_started = false;   // a ";TYPE:" comment
  std::span<const Motion> moves() const { return {motions.data(), count}; }
};

// The words of a G0/G1 as written; absent words keep their axis (or the modal feedrate).
struct MoveWords {
  std::optional<double> x, y, z, e;
  std::optional<double> f;  // per minute
};

// Applies one command to `state`; commands that change nothing here are ignored.
GcodeStep interpret(GcodeState& state, const GcodeCommand& command);
// A G0/G1 of these words.
GcodeStep interpret_move(GcodeState& state, const MoveWords& words);

// Where the planner has the nozzle and filament: the coordinates with the hop and the
// retraction.
AxisPosition machine_position(const GcodeState& state);

}  // namespace printer
