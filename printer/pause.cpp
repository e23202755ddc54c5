#include "printer/pause.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

namespace printer {

namespace {

// How far a cancel lifts the nozzle off the part, mm (the build height permitting).
constexpr double kCancelLift = 10;

// M114 prints two decimals: the stream's own value is the exact one when they agree.
double resolve(double from_stream, double reported) {
  return std::abs(from_stream - reported) <= 0.011 ? from_stream : reported;
}

void send_all(LineProtocol& protocol, const std::vector<std::string>& commands) {
  for (const std::string& c : commands) protocol.send(c);
}

std::string mm(double value) { return fmt::format("{:.5f}", value); }

// Whether the printer reads the file's inches (G20). The host's own moves are written in mm
// (PrintState holds mm), so in an inch file they go between G21 and G20: Marlin reads G20/G21
// only built with INCH_MODE_SUPPORT and takes G21 as a no-op without it (Marlin/src/gcode/
// gcode.cpp, units/G20_G21.cpp); Teacup (gcode_parse.c) and Repetier (Commands.cpp, Printer.cpp
// convertToMM) read both. Repetier also reports M114 in inches after G20 (Commands.cpp
// printCurrentPosition), so a position is asked for after G21 too.
bool in_inches(const PrintState& s) { return s.unit != 1; }

// `lift` above z, stopping at the build height when it is known, never below z.
double lifted(double z, double lift, double max_z) {
  return max_z > 0 ? std::max(z, std::min(z + lift, max_z)) : z + lift;
}

// Retract (relative E), lift to `z`, park: leaving the part.
std::vector<std::string> leave_part(double z, const PauseOptions& options) {
  std::vector<std::string> commands{"G90", "M83"};
  if (options.retract > 0) {
    commands.push_back(fmt::format("G1 E-{} F{}", mm(options.retract), options.retract_feedrate));
  }
  commands.push_back(fmt::format("G1 Z{} F{}", mm(z), options.z_feedrate));
  commands.push_back(fmt::format("G1 X{} Y{} F{}", mm(options.park_x), mm(options.park_y),
                                 options.travel_feedrate));
  return commands;
}

// Back onto the part from above it: X/Y at the lifted Z, then down to Z, un-retract, and the
// stream's E, modes and feedrate, so the next line of the file runs as it would have.
std::vector<std::string> return_to_part(const PrintState& s, const PauseOptions& options) {
  std::vector<std::string> commands{
      "G90",
      fmt::format("G1 X{} Y{} F{}", mm(s.x), mm(s.y), options.travel_feedrate),
      fmt::format("G1 Z{} F{}", mm(s.z), options.z_feedrate),
      "M83",
  };
  if (options.retract > 0) {
    commands.push_back(fmt::format("G1 E{} F{}", mm(options.retract), options.retract_feedrate));
  }
  commands.push_back(fmt::format("G92 E{}", mm(s.e)));
  for (std::string& c : restore_modes(s)) commands.push_back(std::move(c));
  return commands;
}

}  // namespace

std::vector<std::string> reheat_commands(Firmware firmware, const PrintState& state,
                                         const std::optional<Temperatures>& reported,
                                         double reheat_margin) {
  auto cold = [&](const std::optional<double>& current, double target) {
    return target > 0 && (!current || *current < target - reheat_margin);
  };
  const double bed = cold(reported ? reported->bed : std::nullopt, state.bed_target) ? state.bed_target : 0;
  const double hotend =
      cold(reported ? reported->hotend : std::nullopt, state.hotend_target) ? state.hotend_target : 0;
  // Teacup has no M190 or M109: it sets the targets and waits for both with M116.
  if (dialect_of(firmware).waits_with_m116) return heat_and_wait(firmware, bed, hotend);
  std::vector<std::string> commands;
  if (bed > 0) commands.push_back(fmt::format("M190 S{}", bed));
  if (hotend > 0) commands.push_back(fmt::format("M109 S{}", hotend));
  return commands;
}

std::optional<ReportedPosition> position_in_mm(LineProtocol& protocol, const PrintState& state) {
  if (in_inches(state)) protocol.send("G21");
  return protocol.query_position();
}

PausePoint pause_print(LineProtocol& protocol, const PrintState& state, const PauseOptions& options) {
  PausePoint point;
  point.state = state;
  if (const auto reported = position_in_mm(protocol, state)) {
    point.reported = true;
    point.state.x = resolve(state.x, reported->x);
    point.state.y = resolve(state.y, reported->y);
    point.state.z = resolve(state.z, reported->z);
    point.state.e = resolve(state.e, reported->e);
  }
  point.stopped_at = protocol.link().now();
  point.lifted_z = lifted(point.state.z, options.lift, options.max_z);
  std::vector<std::string> commands = leave_part(point.lifted_z, options);
  // Waiting in the file's units, which the job's tunes are written in.
  if (in_inches(state)) commands.push_back("G20");
  send_all(protocol, commands);
  protocol.wait_acknowledged();
  return point;
}

void resume_print(LineProtocol& protocol, const PausePoint& point, const PauseOptions& options) {
  const PrintState& s = point.state;
  protocol.send("M105");
  protocol.wait_acknowledged();
  send_all(protocol, reheat_commands(protocol.firmware().firmware, s, protocol.temperatures(), options.reheat_margin));
  if (in_inches(s)) protocol.send("G21");  // restore_modes ends the return with G20
  send_all(protocol, return_to_part(s, options));
}

bool z_forgotten(const std::optional<ReportedPosition>& reported, const PrintState& journal) {
  return !reported || reported->z < journal.z - 0.011;
}

void recover_print(LineProtocol& protocol, const PrintState& s, bool z_lost, const PauseOptions& options) {
  protocol.send("M105");
  protocol.wait_acknowledged();
  std::vector<std::string> commands;
  // Heat while lifting and homing; wait only once the nozzle is off the part.
  if (s.bed_target > 0) commands.push_back(fmt::format("M140 S{}", s.bed_target));
  if (s.hotend_target > 0) commands.push_back(fmt::format("M104 S{}", s.hotend_target));
  // A printer that kept the file's inches reads the lift and return in mm; one that reset
  // reads mm anyway. restore_modes ends the return with G20.
  if (in_inches(s)) commands.push_back("G21");
  // A printer that lost Z: Z did not move (its motors hold or were off), so the journal's Z is
  // where the nozzle is, to within the layer that was being printed.
  if (z_lost) commands.push_back(fmt::format("G92 Z{}", mm(s.z)));
  commands.push_back("G91");
  commands.push_back(fmt::format("G1 Z{} F{}", mm(options.lift), options.z_feedrate));
  commands.push_back("G90");
  commands.push_back("G28 X Y");
  send_all(protocol, commands);
  protocol.wait_acknowledged();
  send_all(protocol, reheat_commands(protocol.firmware().firmware, s, protocol.temperatures(), 0.0));
  commands = return_to_part(s, options);
  commands.push_back(s.fan > 0                        ? fmt::format("M106 S{}", s.fan)
                     : protocol.dialect().has_m107 ? "M107"
                                                   : "M106 S0");
  send_all(protocol, commands);
}

void cancel_print(LineProtocol& protocol, const PrintState& state, const PauseOptions& options) {
  protocol.wait_acknowledged();
  std::vector<std::string> commands{"M104 S0", "M140 S0",
                                    protocol.dialect().has_m107 ? "M107" : "M106 S0"};
  // The job is over: the printer is left in mm, its units at power-on.
  if (in_inches(state)) commands.push_back("G21");
  for (std::string& c : leave_part(lifted(state.z, kCancelLift, options.max_z), options)) {
    commands.push_back(std::move(c));
  }
  commands.push_back("M84");
  send_all(protocol, commands);
  protocol.wait_acknowledged();
}

}  // namespace printer
