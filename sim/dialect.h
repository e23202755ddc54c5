// The firmware dialects the simulated printer speaks (`mahost sim --dialect NAME`), each as
// that firmware's own source prints it, so the host is tested against more than Marlin:
//
// marlin    Marlin 2.0.9 (Marlin/src/gcode/queue.cpp and the G-code handlers): ok when a command
//           is done, "Error:...Last Line: n" + "Resend: n+1" (+ ok with ok_after_resend),
//           "echo:Unknown command", busy keepalive, M115 capabilities, EMERGENCY_PARSER.
// teacup    Teacup (gcode_parse.c, gcode_process.c, mendel.c): "Start" and "ok" at boot; "ok "
//           is written as a line is read and run, the command's output on the same line ("ok T:25.0
//           B:20.0", "ok E: Bad M-code 190", "ok X:0.000,Y:0.000,Z:0.000,E:0.000,F:1500");
//           any line number from the expected one up is taken; "rs N<n> Expected checksum
//           <cs>" / "rs N<n> Expected line number <n>" without ok; no M109, M190, M107, M400,
//           M73; waits for temperatures with M116; no keepalive, no emergency parser (M112
//           freezes it without a word).
// repetier  Repetier-Firmware 1.0 (gcode.cpp, Communication.cpp): ok when a line is queued,
//           the command's output after it (M105's "T:... B:..." line); "Resend:n" + "ok",
//           then "skip N" + "ok" for lines sent before the request; "Unknown command:X";
//           temperatures each second while M109/M190 wait; "wait" when idle and empty.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "printer/gcode_line.h"

namespace sim {

enum class Dialect { marlin, teacup, repetier };

std::optional<Dialect> parse_dialect(std::string_view name);
std::string_view to_string(Dialect dialect);
std::string dialect_names();  // "marlin, teacup, repetier"

// When a command's ok goes: when it is done (Marlin: a move once in the planner), when it
// starts (Teacup: "ok " is written as it reads the line and runs it, the output after it on
// the same line; it reads no further meanwhile), or when the line is queued (Repetier).
enum class OkAt { done, start, queued };

struct DialectTraits {
  OkAt ok_at = OkAt::done;
  bool output_on_ok_line = false;   // Teacup: "ok <output>"
  bool one_line_at_a_time = false;  // Teacup: no command queue, a line is read once the last ran
  bool takes_skipped_numbers = false;  // Teacup: any N >= expected is taken
  bool requires_checksum = true;    // Marlin refuses "N<n> cmd" without "*<cs>"
  bool busy_keepalive = false;      // "echo:busy: processing" every busy_interval
  bool emergency_parser = false;    // may act on M108/M112/M410 as they arrive
  bool reports_while_heating = false;  // a temperature line each second in M109/M190
  bool wait_report_field = false;   // ... with Marlin's " W:<s>"
  bool position_after_homing = false;  // G28 ends with a position report
  bool says_wait_when_idle = false; // "wait" each second when idle with an empty buffer
  bool skips_after_resend = false;  // Repetier: "skip N" + ok for lines in flight
  std::optional<bool> ok_after_resend;  // fixed by the dialect; unset: the Config decides
};
const DialectTraits& traits(Dialect dialect);

// What the firmware prints after power-on or reset.
std::vector<std::string> boot_banner(Dialect dialect, std::string_view marlin_version);
// The FIRMWARE_NAME line of M115 (Marlin's capability lines are the printer's to add).
std::string firmware_report(Dialect dialect, std::string_view marlin_version);
// Whether the firmware has this command (G, M or T word); the rest draw unknown_reply.
bool knows(Dialect dialect, const printer::GcodeCommand& command);
// The refusal of a command it does not have: "echo:Unknown command: \"X\"", "E: Bad M-code
// 190" (Teacup, on the ok line), "Unknown command:X".
std::string unknown_reply(Dialect dialect, std::string_view text, const printer::GcodeCommand& command);
// A line refused for its number or checksum: the lines the firmware prints (Marlin's
// "Error:<what>n" first), `expected` being the line it wants next.
std::vector<std::string> resend_request(Dialect dialect, std::string_view marlin_error,
                                        long expected, int checksum);
// M114's answer; `feedrate` mm/s, `steps` X Y Z steps per mm for Marlin's Count.
struct HeadPosition {
  double x = 0, y = 0, z = 0, e = 0;
};
std::string position_reply(Dialect dialect, HeadPosition p, double feedrate,
                           const double (&steps)[3]);
// Teacup's M105 answer, for its ok line: "T:25.0 B:20.0" (Marlin and Repetier print the
// fields of Heaters::states()).
std::string teacup_temperatures(double hotend, double bed);

}  // namespace sim
