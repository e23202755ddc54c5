// The record of a simulated print, as a file: what `mahost sim --record out.json` writes for
// tests and users to compare with what was planned.
//
// JSON object:
//   "firmware":    the emulated configuration: "name" its dialect (marlin, teacup, repetier),
//                  queue, planner, RX buffer, ADVANCED_OK, ...
//   "faults":      the fault spec in effect ("" for none)
//   "state", "stop_reason": running/halted/disconnected and why
//   "sim_time":    the simulator's clock at the end, s; "motion_time": seconds of motion;
//                  "planner_starved": seconds the head stood waiting for the host's next move
//   "counters":    lines, commands, resends, errors, faults_injected, overflows, ...,
//                  longest_idle (s)
//   "lost_ok_waits": per ok the faults dropped, the idle wait it caused (Printer::lost_ok_waits), s
//   "commands":    the executed-command log, in execution order
//   "moves":       the deposition record: {"layer","z","x0","y0","x1","y1","e","f"} each
//                  (mm, mm of filament, mm/s)
//   "layers":      per layer {"z","height","beads":[[[x,y] x4], ...]} (sim/deposition.h)
// Units: mm, s.
#pragma once

#include <string>

#include "sim/printer.h"

namespace sim {

// Writes the record of `printer` to `path`. Throws printer::ConfigError naming the path when
// it cannot be written.
void write_record_json(const Printer& printer, const std::string& path);

// Writes the printed part (sim/printed_part.h) as a binary STL; geometry::InputError naming
// the path when it cannot be written.
void write_printed_stl(const Printer& printer, const std::string& path);

}  // namespace sim
