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
//             get_destination_from_command in gcode/gcode.cpp).
//   G2/G3     an arc in XY, clockwise/counter-clockwise, cut into chords as Marlin 2.1's
//             plan_arc does with its default configuration (gcode/motion/G2_G3.cpp;
//             Configuration_adv.h: MIN_ARC_SEGMENT_MM 0.1, MAX_ARC_SEGMENT_MM 1,
//             MIN_CIRCLE_SEGMENTS 72, N_ARC_CORRECTION 25; no ARC_SEGMENTS_PER_SEC,
//             ARC_P_CIRCLES or CNC_WORKSPACE_PLANES). The centre is I J from the start, or
//             from R (a negative R the longer way round); R wins over I J. Z and E change
//             evenly along it. The end at the start (within 1e-6 mm) is a full circle of at
//             least 72 chords; other arcs have 1 mm chords, at least 72 per turn. Without a
//             centre (no I J R, or all 0) nothing moves and Marlin answers "Error:G2/G3 bad
//             parameters"; F is still taken. An arc of no angle, or of under 0.0001 mm and
//             not rising, does not move.
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
// Other firmware differ from Marlin in a few rules, chosen in GcodeRules (the simulated
// printer's dialects, sim/dialect.h, pick them); the rest of the table holds for them too.
// Units: mm, mm/min for F (as written, times 25.4 after G20), mm/s for a move's feedrate.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

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

// Where a firmware reads G-code otherwise than Marlin; the defaults are Marlin's rules.
struct GcodeRules {
  // E is relative while G91 or M83 holds, either: G90/G91 leave M82/M83's choice alone
  // (Teacup's gcode_process.c: e_relative = option_all_relative || option_e_relative;
  // Repetier's Printer.cpp setDestinationStepsFromGCode: relativeCoordinateMode ||
  // relativeExtruderCoordinateMode). Marlin: G90/G91 set E's mode too.
  bool e_relative_while_g91 = false;
  // G92 as Teacup's gcode_process.c case 92: an axis written without a value is set to 0
  // (gcode_parse.c reads "X" as X0), and G92 with no axis sets X, Y, Z and E to 0.
  bool g92_bare_axis_is_zero = false;
};

// What a printer holds after the commands read so far.
struct GcodeState {
  GcodeRules rules;
  double x = 0, y = 0, z = 0, e = 0;  // the G-code's coordinates, mm
  double feedrate = 0;                // mm/min, the last F above 0 (in mm); 0 before any
  bool relative_xyz = false;          // G91
  bool relative_e = false;            // M83 or G91 (with e_relative_while_g91: M83 alone)
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
  std::array<Motion, 2> motions;  // a G0/G1's move, G10/G11's one or two
  std::size_t count = 0;       // motions used
  std::vector<Motion> chords;  // a G2/G3's moves, in order (then count is 0)
  bool homed = false;          // a G28 ran: the position jumped after the planner drained
  bool position_set = false;   // G28 or G92: the position changed without moving
  bool bad_arc = false;        // a G2/G3 without a centre: "Error:G2/G3 bad parameters"
  bool layer_started = false;  // a ";LAYER:" comment
  bool type_started = false;   // a ";TYPE:" comment
  // Every move the planner is given, in order.
  std::span<const Motion> moves() const {
    return chords.empty() ? std::span<const Motion>{motions.data(), count} : std::span<const Motion>{chords};
  }
};

// The words of a G0/G1 as written; absent words keep their axis (or the modal feedrate).
struct MoveWords {
  std::optional<double> x, y, z, e;
  std::optional<double> f;  // per minute
};

// Applies one command to `state`; commands that change nothing here are ignored.
GcodeStep interpret(GcodeState& state, const GcodeCommand& command);
// Whether a G0-G3's E is relative in the state's modes and rules.
bool e_is_relative(const GcodeState& state);
// A G0/G1 of these words.
GcodeStep interpret_move(GcodeState& state, const MoveWords& words);
// Its one motion alone, for a reader of moves only (the print clock, once per move).
Motion move_motion(GcodeState& state, const MoveWords& words);

// Where the planner has the nozzle and filament: the coordinates with the hop and the
// retraction.
AxisPosition machine_position(const GcodeState& state);

// The axes a G28 homes, X Y Z: those named, or all three when none or all are named
// (gcode/calibrate/G28.cpp).
std::array<bool, 3> homed_axes(const GcodeCommand& g28);

// G4's dwell: P milliseconds or S seconds, S over P (gcode/motion/G4.cpp), 0 for none or
// below 0; nullopt for any other command. The firmware first drains the planner.
std::optional<double> dwell_seconds(const GcodeCommand& command);

// The planner's limits as M201 (X Y Z E acceleration, mm/s^2), M203 (X Y Z E speed, mm/s),
// M204 (S print and travel, P print, R retract, T travel acceleration), M205 (J junction
// deviation, S minimum feedrate) leave them; a value of 0 or below is ignored, but M205 S0
// is taken (gcode/config/M200-M205.cpp). nullopt for any other command.
std::optional<MotionLimits> motion_limits_after(const MotionLimits& limits, const GcodeCommand& command);

}  // namespace printer
