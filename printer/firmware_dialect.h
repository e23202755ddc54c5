// What differs between the firmwares mahost talks to (issue 14): one row per dialect, read by
// the protocol engine (printer/line_protocol.h), the job (printer/job.h) and the G-code writer.
//
// The firmware is recognised at connect from its M115 reply (FIRMWARE_NAME:Marlin ...,
// FIRMWARE_NAME:Teacup ..., FIRMWARE_NAME:Repetier_1.0.3 ...); no name at all is `unknown`,
// for which the engine accepts every form below and assumes the least. A printer profile names
// the dialect its G-code is written for (`firmware = "marlin"`).
//
//                     marlin                  teacup                     repetier
// ok means            command executed        line read (ok first,       line queued (ok first,
//                     (a move: in planner)    output on the ok line)     output after it)
// M105's temperatures on the ok: "ok T:.."    on the ok: "ok T:25.0"     a "T:.." line after ok
// resend request      "Resend: N"             "rs N<n> Expected ..."     "Resend:N"
// ok after resend     1.1 yes, 2.x no (learnt) no                        yes
// refusal             echo:Unknown command    "ok E: Bad M-code 190"     "Unknown command:.."
// errors              Error:, !!              E:                         Error:, fatal:
// line numbers        exactly last + 1        any >= last + 1            exactly last + 1
// M114                X:0.00 Y:0.00 .. Count  X:0.000,Y:0.000,..,F:1500  X:0.00 Y:0.00 ..
// heat and wait       M109, M190              M104 / M140 + M116         M109, M190 (and M116)
// M110 M115 M400 M73  yes yes yes yes         no-op yes no no            yes yes yes no
// M107, M155          yes, Cap:AUTOREPORT     no (M106 S0), no           yes, no
// emergency commands  M108 M410 M112 at once  M112 in order, no reply    M112 when read
// keepalive           busy: every 2 s         none                       none ("wait" when idle)
// lost-ok probe       a number skipped        the oldest line again      the oldest line again
//
// A probe must be answered by something that says exactly which lines the firmware has.
// Marlin refuses a line whose number is not its last plus one with "Resend: <last + 1>": a
// line numbered one past the next ("N<next + 1> M105", never stored or resent) draws exactly
// that, whatever oks or lines were lost, and runs nothing. (A numbered M105 in the stream is
// answered too, but its "ok T:" cannot say which of two M105s it answers once one answer is
// lost: the host credited the older, was one behind for good and probed for ever; and Marlin
// 2.1 drops a repeat of its last line without a word, so the line itself cannot be resent.)
// Teacup takes any higher number, so there a skipped number, or an M105, would silently skip
// a lost line; and Repetier's ok comes when a line is queued, before the M105's answer, so an
// M105's bare ok would be taken for the lost one. Sending the unanswered line again is exact
// on both: if it had arrived the firmware asks for the next one ("rs N<next>", "Resend:<n>"),
// if not it runs it now and says ok. A firmware that does not name itself gets a numbered M105
// first and a skipped number if that goes unanswered.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace printer {

enum class Firmware { unknown, marlin, teacup, repetier };

enum class OkMeans { executed, received };
enum class TemperatureReply { on_ok, after_ok, on_ok_or_before };
enum class LostOkProbe { next_m105, skipped_number, same_line_again };

struct FirmwareDialect {
  Firmware firmware = Firmware::unknown;
  std::string_view name;      // the profile's value: "marlin"; "" for unknown
  std::string_view display;   // for messages: "Marlin"
  OkMeans ok_means = OkMeans::executed;
  TemperatureReply temperatures = TemperatureReply::on_ok_or_before;
  std::optional<bool> ok_after_resend;  // unset: learnt from the first resends
  LostOkProbe probe = LostOkProbe::next_m105;
  bool has_m400 = true;       // else G4 P0 waits for the moves
  bool has_m73 = false;       // progress on the display
  bool has_m107 = true;       // else M106 S0
  bool waits_with_m116 = false;  // M104/M140 + M116 instead of M109/M190
  bool emergency_m108_m410 = false;  // takes M108 and M410 (at once with EMERGENCY_PARSER)
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

}  // namespace printer
