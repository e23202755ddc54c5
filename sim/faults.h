// Faults the simulated printer injects, each seeded and reproducible (DESIGN.md §4).
//
// A fault spec is a comma-separated list of key=value pairs, e.g.
//   "corrupt=0.01,drop-ok=0.01,dup-ok=0.005,resend=0.01,delay=50ms,disconnect-at-line=5000,
//    disconnect-at-time=60s,halt-at-line=300,runaway-at-line=200,seed=42"
// Probabilities are in [0, 1]; times take a unit (ms, s, min); lines count the lines the
// firmware accepted into its command queue since power-on, starting at 1.
//
// What each fault does (and why it is shaped so):
// - corrupt=p: each byte the host sends is, with probability p, changed before the firmware
//   reads it, as on a noisy serial line: a digit into another digit (the line still reads as
//   G-code, with a number changed: a coordinate, a line number, the checksum), any other byte
//   by one flipped bit. At most one byte per line is changed, and never into or out of a line
//   end, ';', '*', backspace or NUL, nor the 'N' that starts a line: a change of one byte is
//   always caught by the XOR checksum (two changes could cancel; a flipped 'N' makes an
//   unchecked line), so every corruption is detected and answered with a resend request.
//   Unnumbered lines carry no checksum, so the firmware runs them as they arrive, changed or
//   not; use from-line to keep a host's unnumbered handshake out of reach.
// - drop-ok=p: an `ok` for an executed command is not sent.
// - drop-blocking-ok=N: the oks of the first N commands that block the firmware until they
//   end (G4, G28, M0/M1, M109, M190, M116, M400) are not sent: the worst time to lose one,
//   since silence is expected while they run.
// - dup-ok=p: an `ok` is sent twice.
// - late-ok-at-line=N: the ok of line N is held back until the firmware's next resend
//   request, and sent right after it (after its own ok, where the firmware sends one): an ok
//   that comes late, after the request, for a line before the one asked for. Its place in
//   the stream is the worst for a host that learns from the ok after a request.
// - resend=p: a numbered line that arrived intact is answered as if its checksum were wrong
//   (Error:checksum mismatch, Resend) and not executed: the host must send it again.
// - delay=T: every reply leaves T later than it would (order kept).
// - disconnect-at-line=N / disconnect-at-time=T: the link vanishes when line N is accepted or
//   at sim time T (SimLink throws printer::LinkError; `mahost sim` closes the terminal).
// - halt-at-line=N: kill() when line N is executed: "Error:Printer halted. kill() called!".
// - freeze-at-line=N: the link stalls once line N is accepted: the port stays open, but the
//   firmware reads nothing more (M112 included) and says nothing more, as a hung USB-serial
//   bridge or a board locked up. What is queued still runs.
// - runaway-at-line=N: the hotend heater fails when line N is executed; Marlin's thermal
//   protection then stops the printer once the temperature has stayed more than the
//   hysteresis below its target for the protection period.
// - from-line=N: the faults above given as a probability or a delay (corrupt, drop-ok,
//   dup-ok, resend, delay) start only once the firmware has accepted the numbered line N (the
//   host's numbering) since its last reset, so that a host's connection handshake and its
//   M110 get through: a host that loses its M110 loses line 0 for good (printcore does).
// - seed=S: the seed of every random choice above (default 1).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace sim {

struct FaultSpec {
  double corrupt = 0;
  double drop_ok = 0;
  std::uint64_t drop_blocking_ok = 0;
  double dup_ok = 0;
  std::optional<std::uint64_t> late_ok_at_line;
  double resend = 0;
  double delay = 0;  // s
  std::optional<std::uint64_t> disconnect_at_line;
  std::optional<double> disconnect_at_time;  // s on the sim clock
  std::optional<std::uint64_t> halt_at_line;
  std::optional<std::uint64_t> freeze_at_line;
  std::optional<std::uint64_t> runaway_at_line;
  std::optional<long> from_line;
  std::uint64_t seed = 1;

  bool any() const;
};

// Parses a fault spec. Throws printer::ConfigError naming the key and what is allowed for an
// unknown key, a missing '=', a value out of range or without its unit. "" gives no faults.
FaultSpec parse_fault_spec(std::string_view spec);

// The spec in the form parse_fault_spec reads ("" when there are no faults).
std::string to_string(const FaultSpec& faults);

}  // namespace sim
