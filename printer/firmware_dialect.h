// What differs between the firmwares mahost talks to: one row per dialect, read by the protocol
// engine (printer/line_protocol.h), the job (printer/job.h) and the G-code writer. Every entry
// comes from the firmware's own source (the file is named below) and the simulated printer
// (sim/dialect.h) reproduces exactly this; Teacup's was also checked against its host-side
// simulator (Makefile-SIM) by hand.
//
// The firmware is recognised at connect from its M115 reply (FIRMWARE_NAME:Marlin ...,
// FIRMWARE_NAME:Teacup ..., FIRMWARE_NAME:Repetier_1.0.3 ...); no name at all is `unknown`, for
// which the engine accepts every form below and assumes the least. A printer profile names the
// dialect its G-code is written for (`firmware = "marlin"`).
//
//                    marlin (2.1.x)           teacup (master)            repetier (1.0.x)
// ok means           the command ran (a move: the command ran and a   the line was read and
//                    is in the planner)       movement slot is free      queued, before it runs
// line numbers       exactly last + 1         ignored (checked only      exactly last + 1; one
//                                             with REQUIRE_LINENUMBER:   seen already: "skip N"
//                                             any N >= expected)         and "ok", not run
// checksum           required with N          checked when present       checked when present
// resend request     Error:...Last Line: n    rs N<n> Expected checksum  Error:Wrong checksum, "",
//                    Resend: n+1              <c> (or Expected line      Resend:<n>; again every
//                                             number <n>)                200 ms without input
// ok after resend    yes (2.0.9.x: no)        yes                        yes
// ok with line no.   ADVANCED_OK:             no                         "ok <n>"
//                    ok N<n> P<free> B<free>                             (ACK_WITH_LINENUMBER)
// M105 answer        "ok T:.. /.. B:.. /.."   "T:20.0/0.0 B:20.0/0.0"    "ok", later
//                                             then "ok"                  "T:20.00 /0 B:20.00 /0"
// refusal            echo:Unknown command:    "E: Bad M-code 190"        "ok", then "Unknown
//                    "X", then ok             then "ok"                  command:N5 M113  S1"
// keepalive          echo:busy: processing    "Waiting for target temp"  busy:processing,
//                    (M113 S<s>, default 2)   each second after M116     busy:heating every 2 s
// idle               ("wait" with NO_TIMEOUTS) -                         "wait" each second
// planner (moves)    BLOCK_BUFFER_SIZE 16     MOVEBUFFER_SIZE 8          PRINTLINE_CACHE_SIZE 24
// waits for moves    G4 G28 M400              G4 G28 G92 M0 M2 M84       G4 G28 M400 M109 M190
//                                                                        M116
// heat and wait      M109, M190               M104/M140, M116 (waits at  M109, M190, M116
//                                             the next G0/G1)
// M107 M400 M73      yes yes yes              no no no (M106 S0, G4)     yes yes yes
// M155 (auto temps)  Cap:AUTOREPORT_TEMP      cap:AUTOREPORT_TEMP (its   Cap:AUTOREPORT_TEMP
//                                             lines look like M105's)
// emergency          M108 M112 M410 at once   M112 in order, then silent M112 when read, silent
// lost-ok probe      a line number skipped    a line with a wrong        the unanswered line
//                    (answered "Resend: n")   checksum ("rs N<n>")       again ("skip N" if had)
//
// Sources. Marlin: Marlin/src/gcode/queue.cpp (get_serial_commands, gcode_line_error,
// flush_and_request_resend, RingBuffer::ok_to_send), gcode.cpp (host_keepalive),
// host/M115.cpp (no capability line names ADVANCED_OK: it shows in the ok itself),
// module/planner.h (BLOCK_BUFFER_SIZE). Teacup: mendel.c (banner "start\nok", the ok sent once
// the queue has room, after whatever the command printed), gcode_parse.c and gcode_parse.h
// (REQUIRE_LINENUMBER and REQUIRE_CHECKSUM off), gcode_process.c (commands, refusals, M110 a
// no-op, M112), temp.c and clock.c (M116, "Waiting for target temp", temp_print),
// config/printer.mendel.h (MOVEBUFFER_SIZE, TEMP_HYSTERESIS 10, TEMP_RESIDENCY_TIME 60).
// Repetier: src/ArduinoAVR/Repetier/gcode.cpp (readFromSerial, checkAndPushCommand,
// requestResend, keepAlive), Commands.cpp (printTemperatures, unknown commands, M115),
// Communication.cpp (the strings), Configuration.h (ACK_WITH_LINENUMBER 1, KEEP_ALIVE_INTERVAL
// 2000, WAITING_IDENTIFIER "wait", PRINTLINE_CACHE_SIZE 24), Repetier.h (GCODE_BUFFER_SIZE 1).
//
// The probe must be answered by something that says exactly which lines the firmware has, and
// must never run a line twice:
// - Marlin refuses a line whose number is not its last plus one with "Resend: <last + 1>": a
//   line numbered one past the next ("N<next + 1> M105", never stored or resent) draws exactly
//   that, whatever oks were lost, and runs nothing.
// - Teacup ignores line numbers, so a line sent again would run again (a G91 move doubled, E
//   fed twice) and a skipped number would be taken. But it checks a checksum when there is
//   one, and refuses a wrong one with "rs N<n>", n one past the last numbered line it ran (its
//   N_expected), then "ok": a numbered M105 with a checksum made wrong on purpose runs nothing
//   and says exactly which lines ran, whether the ok or the line itself was lost. (The wrong
//   checksum is the right one XOR 0x55: no change of one byte, a digit into a digit or one bit
//   flipped, makes it right again.)
// - Repetier answers a line it has already with "skip N" and "ok" and does not run it, so the
//   unanswered line sent again is exact: "skip N" if it arrived, run and "ok N" if not.
// - A firmware that does not name itself gets a numbered M105 first and a skipped number if
//   that goes unanswered.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "printer/gcode_line.h"

namespace printer {

enum class Firmware { unknown, marlin, teacup, repetier };

enum class OkMeans { executed, received };
// Where M105's temperatures come: on the ok line, on a line of their own just before the ok
// (the line proves the M105 ran), after the ok (the line proves nothing about the ok), or
// either of the first two (a firmware that does not name itself).
enum class TemperatureReply { on_ok, before_ok, after_ok, on_ok_or_before };
enum class LostOkProbe { next_m105, skipped_number, wrong_checksum, same_line_again };

struct FirmwareDialect {
  Firmware firmware = Firmware::unknown;
  std::string_view name;      // the profile's value: "marlin"; "" for unknown
  std::string_view display;   // for messages: "Marlin"
  OkMeans ok_means = OkMeans::executed;
  TemperatureReply temperatures = TemperatureReply::on_ok_or_before;
  // An ok right after a resend request: where the engine's learning starts
  // (printer/line_protocol.h); unset: not known.
  std::optional<bool> ok_after_resend;
  bool checks_line_numbers = true;  // false: a line sent twice runs twice
  LostOkProbe probe = LostOkProbe::next_m105;
  bool has_m400 = true;       // else G4 P0 waits for the moves
  bool has_m73 = false;       // progress on the display
  bool has_m107 = true;       // else M106 S0
  bool waits_with_m116 = false;  // M104/M140 + M116 instead of M109/M190
  bool emergency_m108_m410 = false;  // takes M108 and M410 (at once with EMERGENCY_PARSER)
  // M155 auto-reports can be used: false where they look like the answer to an M105 the
  // lost-ok probe relies on (Teacup).
  bool autoreport_usable = true;
  // Moves the firmware holds when it acknowledges one more (the host's mirror of its planner,
  // printer/line_protocol.h): Marlin's BLOCK_BUFFER_SIZE 16 keeps one slot free; Teacup's ok
  // waits for a free slot of 8; Repetier's 24 and its one command buffered.
  std::size_t planner_depth = 16;
};

const FirmwareDialect& dialect_of(Firmware firmware);

// The dialect a printer profile names ("marlin", "teacup", "repetier"); nullopt otherwise.
std::optional<Firmware> parse_firmware(std::string_view name);
// The names a profile may give, for messages: "marlin, teacup, repetier".
std::string firmware_names();

// The dialect an M115 FIRMWARE_NAME says (Marlin, Prusa-Firmware and Marlin forks: marlin;
// Teacup and FiveD_on_Arduino: teacup; Repetier_x: repetier); unknown for anything else.
Firmware recognise_firmware(std::string_view firmware_name);

// The start of a print in this dialect: set both heaters, then wait for the bed and the
// hotend (M190 + M109, or M116 for both). A target of 0 is left out.
std::vector<std::string> heat_and_wait(Firmware firmware, double bed, double hotend);

// Whether the firmware's answer to this command comes only once every queued move has run
// (it waits for the planner to empty first): the table's "waits for moves".
bool waits_for_moves(Firmware firmware, const GcodeCommand& command);

// A command as this firmware takes it: the same command, an equivalent in its words
// (Teacup: M107 -> M106 S0, M400 -> G4 P0, M109 S210 -> M104 S210 + M116, M190 -> M140 + M116),
// or nothing when it has no such command (the lines are empty and `missing` is set).
struct FirmwareCommand {
  std::vector<std::string> lines;
  bool missing = false;
};
FirmwareCommand for_firmware(Firmware firmware, std::string_view command);

}  // namespace printer
