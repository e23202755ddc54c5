// Pausing a print at a layer boundary and getting back onto the part (DESIGN.md §4).
//
// pause_print: let the queued moves finish (M400), read where the nozzle is (M114), retract,
// lift Z, park; the heaters stay at their targets. resume_print: re-heat if the temperature
// fell, move X/Y at the lifted Z and only then down to Z (coming down onto the part from the
// side could hit it), un-retract, restore E with G92 and the extruder mode, positioning mode
// and feedrate, so the next line of the file runs exactly as it would have.
// recover_print: the same after the host or the link died (`mahost resume`): re-heat, lift,
// home X and Y only (homing Z would drive the nozzle into the part), tell a printer that lost
// its Z where it is (z_forgotten), and restore E, modes, feedrate and fan from the journal.
// cancel_print: the safe end of a cancelled job once the lines in flight are done: heaters and
// fan off, retract, lift 10 mm (to the build height at most), park, motors off.
//
// In a file in inches (G20) the moves above are sent between G21 and G20 (pause.cpp in_inches);
// a cancel leaves the printer in mm.
// Positions come from the G-code stream (exact to the file's decimals) when M114 agrees with
// them to 0.01 mm (Marlin prints M114 to two decimals), and from M114 otherwise.
// Units: mm, mm/min, °C.
#pragma once

#include <chrono>

#include "printer/line_protocol.h"
#include "printer/print_state.h"

namespace printer {

struct PauseOptions {
  double retract = 1.0;            // filament pulled back while paused, mm (0: none)
  double lift = 5.0;               // how far the nozzle rises off the part, mm
  double park_x = 5, park_y = 5;   // where it waits, mm (a bed corner; parts sit centred)
  double max_z = 0;                // build height, mm; the lift stops there (0: unknown)
  double travel_feedrate = 6000;   // mm/min
  double z_feedrate = 600;         // mm/min
  double retract_feedrate = 1800;  // mm/min
  double reheat_margin = 5;        // resume waits for heating when this far below target, °C
};

struct PausePoint {
  PrintState state;          // the stream's state at the pause, position resolved as above
  bool reported = false;     // M114 answered
  double lifted_z = 0;       // where the nozzle waits, mm
  // Link time when the printer's queue had run empty (M400 answered): the print stood still
  // from here; the moves before were still printing the part.
  std::chrono::nanoseconds stopped_at{0};
};

PausePoint pause_print(LineProtocol& protocol, const PrintState& state, const PauseOptions& options);
void resume_print(LineProtocol& protocol, const PausePoint& point, const PauseOptions& options);
void recover_print(LineProtocol& protocol, const PrintState& at_resume, bool z_lost,
                   const PauseOptions& options);

// Whether a printer found again after an interruption has lost its Z, by its own report
// (M114 after connect) against the journal. The journal holds the state at the start of the
// interrupted layer, and the nozzle stood at that Z or above it when the job stopped (printing
// that layer, or lifted); a printer that reset counts from 0 again (Marlin, Teacup and
// Repetier all power on at 0,0,0 unhomed), so a reported Z below the journal's, by more than
// M114's two decimals, means it lost it. No report counts as lost too: setting Z from the
// journal then puts the nozzle a layer too high at worst, never into the part, where trusting
// a Z that was reset to 0 prints in the air. Whether the board reset is not read from its
// `start` banner, which a late flush of the port can throw away.
bool z_forgotten(const std::optional<ReportedPosition>& reported, const PrintState& journal);
// Where the printer is (LineProtocol::query_position), in mm: after G21 when `state` is in
// inches (Repetier reports M114 in the current units). The printer is left in mm.
std::optional<ReportedPosition> position_in_mm(LineProtocol& protocol, const PrintState& state);
void cancel_print(LineProtocol& protocol, const PrintState& state, const PauseOptions& options);

// The heating commands resume sends: M190/M109 when the last report is `reheat_margin` or
// more below the target (or there is none), nothing when it is near; on a firmware that waits
// with M116 (Teacup), the targets and one M116.
std::vector<std::string> reheat_commands(Firmware firmware, const PrintState& state,
                                         const std::optional<Temperatures>& reported,
                                         double reheat_margin);

}  // namespace printer
