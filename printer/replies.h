// What a Marlin-style firmware says back, one line at a time (DESIGN.md §4), in the dialects of
// printer/firmware_dialect.h: Marlin's, Teacup's (whose ok line carries the command's output:
// "ok T:25.0 B:20.0", "ok E: Bad M-code 190", "ok X:0.000,Y:0.000,Z:0.000,E:0.000,F:1500")
// and Repetier's ("Resend:12", "skip 14", "Unknown command:M191", "fatal:...").
//
// Input: one reply line without its line end, as read from the link. Output: its kind and the
// figures it carries (ADVANCED_OK line number and buffer space, the line a resend asks for,
// temperatures in °C, a reported position in mm). classify_reply is total: any bytes give a
// defined Reply, unknown text is `other`. The protocol engine (line_protocol.h) decides what a
// reply means for the lines in flight; this file only reads it.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace printer {

enum class ReplyKind {
  ok,           // "ok", "ok N12 P15 B3" (ADVANCED_OK), "ok 12" (Repetier), "ok T:210 /210 B:60 /60"
  resend,       // "Resend: 12", "Resend:N12", "rs N12", "rs 12"
  skip,         // "skip 14": Repetier not running a line it has already (an ok follows)
  error,        // "Error:checksum mismatch, Last Line: 4", "E: ...": the firmware goes on
  fatal,        // "Error:Printer halted. kill() called!", thermal runaway, MINTEMP, "!!",
                // "fatal:": it stopped
  busy,         // "echo:busy: processing", "busy: paused for user", Teacup's "Waiting for target
                // temp": a long command is running
  wait,         // "wait": idle with an empty buffer
  start,        // "start": the firmware (re)started
  temperature,  // " T:200.2 /200.0 B:65.0 /65.0 @:73" without ok (M155 auto-report, M109 wait)
  position,     // "X:0.00 Y:0.00 Z:0.30 E:1.20 Count X:0 Y:0 Z:0", "X:0.000,Y:0.000,..." (M114)
  echo,         // "echo:...", including "echo:Unknown command: \"X\"" and Repetier's
                // "Unknown command:X"
  other,
};

struct Temperatures {
  std::optional<double> hotend, hotend_target;  // °C, first hotend (T: or T0:)
  std::optional<double> bed, bed_target;        // °C
};

struct ReportedPosition {
  double x = 0, y = 0, z = 0, e = 0;  // mm, logical coordinates as M114 prints them
};

struct Reply {
  ReplyKind kind = ReplyKind::other;
  std::string text;                      // the line, line end and surrounding blanks removed
  std::optional<long> line_number;       // ok N<n> / ok <n> (last line accepted), the line a resend
                                         // asks for, the line a Repetier "skip" names
  std::optional<int> planner_free;       // ADVANCED_OK P<n>
  std::optional<int> queue_free;         // ADVANCED_OK B<n>
  std::optional<Temperatures> temperatures;  // on ok, temperature and busy lines
  std::optional<ReportedPosition> position;  // on position lines and Teacup's ok lines
  bool unknown_command = false;          // echo:Unknown command: "...", Unknown command:...
  // The command refused, on the ok line ("E: Bad M-code 190" of "ok E: Bad M-code 190").
  std::optional<std::string> refusal;
  bool heating_wait = false;             // an M109/M190 report ("... W:5"): the wait runs
};

Reply classify_reply(std::string_view line);

// True for an Error: text after which Marlin stops (kill() or stop()): the job cannot go on.
bool is_fatal_error(std::string_view error_text);

}  // namespace printer
