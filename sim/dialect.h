// The firmware dialects the simulated printer speaks (`mahost sim --dialect NAME`), each rebuilt
// from that firmware's own source; printer/firmware_dialect.h has the table of what differs,
// with the file each behaviour comes from. sim/printer.cpp cites the same files where it acts.
//
// marlin    Marlin 2.1.x (MarlinFirmware/Marlin), Marlin/src/gcode/queue.cpp and the handlers.
// teacup    Teacup (Traumflug/Teacup_Firmware, master), mendel.c, gcode_parse.c,
//           gcode_process.c, temp.c, clock.c, config/printer.mendel.h.
// repetier  Repetier-Firmware 1.0.x (repetier/Repetier-Firmware, src/ArduinoAVR/Repetier),
//           gcode.cpp, Commands.cpp, Communication.cpp, Configuration.h, Repetier.h.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "printer/gcode_interpreter.h"
#include "printer/gcode_line.h"

namespace sim {

enum class Dialect { marlin, teacup, repetier };

std::optional<Dialect> parse_dialect(std::string_view name);
std::string_view to_string(Dialect dialect);
std::string dialect_names();  // "marlin, teacup, repetier"

// When a command's ok goes: once it has run (Marlin: a move once in the planner; Teacup: once
// it has run and a movement queue slot is free), or once the line is queued, before it runs
// (Repetier).
enum class OkAt { done, queued };

// How a numbered line's number is checked.
enum class LineNumbers {
  exact,     // last + 1, M110 excepted (Marlin, Repetier)
  ignored,   // never looked at (Teacup without REQUIRE_LINENUMBER, its default)
  at_least,  // any number from the expected one up (Teacup with REQUIRE_LINENUMBER)
};

struct DialectTraits {
  OkAt ok_at = OkAt::done;
  // Commands read ahead of the one running: Marlin's BUFSIZE comes from the Config; Teacup
  // parses and runs one line at a time (mendel.c), Repetier keeps one (GCODE_BUFFER_SIZE 1,
  // Repetier.h). 0: the Config's.
  int queue_depth = 0;
  // Moves held before a new one must wait: 0: the Config's (Marlin's BLOCK_BUFFER_SIZE).
  // Teacup's ok waits for a free slot of MOVEBUFFER_SIZE 8 (mendel.c, printer.mendel.h), so
  // at most 7 stand queued when it acknowledges; Repetier's PRINTLINE_CACHE_SIZE is 24.
  int planner_depth = 0;
  bool busy_keepalive = false;      // Marlin's "echo:busy: processing" every busy_interval
  bool emergency_parser = false;    // may act on M108/M112/M410 as they arrive
  bool reports_while_heating = false;  // a temperature line each second in M109/M190
  bool wait_report_field = false;   // ... with Marlin's " W:<s>"
  bool position_after_homing = false;  // G28 ends with a position report
  bool says_wait_when_idle = false; // Repetier: "wait" each second without input
  std::optional<bool> ok_after_resend;  // fixed by the dialect; unset: the Config decides
};
const DialectTraits& traits(Dialect dialect);

// Where the firmware reads G-code otherwise than Marlin (printer/gcode_interpreter.h):
// Teacup's E relative while G91 or M83 holds and its G92 of bare axes; Repetier's E likewise.
printer::GcodeRules gcode_rules(Dialect dialect);

// What the firmware prints after power-on or reset.
std::vector<std::string> boot_banner(Dialect dialect, std::string_view marlin_version);
// The FIRMWARE_NAME line of M115 (each dialect's capability lines are the printer's to add).
std::string firmware_report(Dialect dialect, std::string_view marlin_version);
// Whether the firmware has this command (G, M or T word); the rest draw unknown_reply.
bool knows(Dialect dialect, const printer::GcodeCommand& command);
// The refusal of a command it does not have (`text` without line number, `line_number` the
// line's N): "echo:Unknown command: \"X\"", "E: Bad M-code 190" (Teacup), "Unknown
// command:N12 M113  S1" (Repetier prints the line as it parsed it).
std::string unknown_reply(Dialect dialect, std::string_view text, const printer::GcodeCommand& command,
                          std::optional<long> line_number);
// M114's answer; `feedrate` mm/s, `steps` X Y Z steps per mm for Marlin's Count.
struct HeadPosition {
  double x = 0, y = 0, z = 0, e = 0;
  bool inches = false;  // after G20: Repetier reports in inches (Commands.cpp printCurrentPosition)
};
std::string position_reply(Dialect dialect, HeadPosition p, double feedrate,
                           const double (&steps)[3]);

// Temperatures as each firmware prints them (°C; power as 0..255 PWM where printed).
struct HeaterReadings {
  double hotend = 0, hotend_target = 0, bed = 0, bed_target = 0;
  int hotend_power = 0, bed_power = 0;
};
// Teacup's temp_print with REPORT_TARGET_TEMPS (temp.c; printer.mendel.h): quarter degrees,
// "T:20.0/0.0 B:60.25/60.0".
std::string teacup_temperatures(const HeaterReadings& r);
// Repetier's printTemperatures (Commands.cpp): "T:20.00 /0 B:20.00 /0 B@:0 @:0".
std::string repetier_temperatures(const HeaterReadings& r);

}  // namespace sim
