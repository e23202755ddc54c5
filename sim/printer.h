// sim::Printer: a Marlin 2.x-style firmware emulator behind a byte stream (DESIGN.md §4).
//
// The host side writes bytes with receive() and takes the firmware's replies with
// take_output(); time passes only through run_until()/run_until_output(), on the simulator's
// own clock (seconds from power-on), so whoever drives it decides how fast time goes: SimLink
// (in-process) jumps the clock, the pty front end follows the wall clock.
//
// What it emulates, each as Marlin 2.1 does it (Marlin/src/gcode/queue.cpp and friends), or
// as Teacup or Repetier do where Config::dialect says so (sim/dialect.h,
// printer/firmware_dialect.h has the table):
// - serial input: bytes arrive at the baud rate into an RX buffer of rx_buffer_size bytes;
//   the firmware reads them only while its command queue (queue_depth) has room, so a host
//   that does not wait for `ok` fills the RX buffer, and bytes arriving then are lost
//   (counted in Counters::overflow_bytes), as Marlin drops them;
// - lines end at \n or \r; ';' starts a comment; a backspace erases; a line longer than
//   max_cmd_size - 1 characters is cut there; `N<n> ... *<cs>` is checked in Marlin's order
//   (line number, then checksum, then a missing checksum); each error prints
//   "Error:<what>, Last Line: <n>", discards what is in the RX buffer, then "Resend: <n+1>"
//   and (ok_after_resend, 2.1.x) "ok"; unnumbered lines are not checked;
// - `ok` when a command has been executed, which for a move means "entered the planner", so
//   the planner (planner_depth moves) and the command queue fill before `ok`s slow down;
// - M112, M108 and M410 act when their line is read, ahead of the queue;
// - replies: M105, M114, M115, M155, busy keepalive, unknown commands, `start`, kill().
// Faults (sim/faults.h) are injected on top, from their seed.
//
// The parts, one concern each: the wire both ways (sim/wire.h), the RX buffer and line
// assembly (sim/serial_line.h), the command queue (sim/command_queue.h), motion and deposition
// (sim/motion.h), the heaters and their waits (sim/heaters.h), and where faults fire
// (sim/fault_injector.h); printer.cpp runs the commands and ties the parts together.
//
// Commands it runs: G0-G3 (arcs in 1 mm chords), G4, G28 (homing moves through the motion
// model, from where the head is; it powers on at 0,0,0), G90/G91 (both also set E, as
// Marlin's do), G92, M0/M1 (until M108 or S/P), M17/M18/M84, M82/M83, M104/M109, M140/M190,
// M105, M106/M107, M108, M110, M112, M113, M114, M115, M155, M201/M203/M204/M205 (the motion
// model's limits), M220/M221, M400, M410, M999, T0; M73, M75-M77, M111, M117, M300 are
// accepted and do nothing here, and so is G21 (Marlin's stock configuration, without
// INCH_MODE_SUPPORT, has only millimetres and takes G21 without a word: gcode.cpp). Anything
// else is an unknown command, G20 too (Teacup and Repetier take G20 and G21).
// Not modelled: software endstops (moves are not clamped to a bed), where inside a move
// M410 stops the head (the sim keeps the commanded position), PID overshoot (heaters follow
// sim/heater.h's closed form), the planner running dry when a host feeds it too slowly (moves
// keep their look-ahead speeds; the clock only waits for them to arrive).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sim/config.h"
#include "sim/deposition.h"

namespace sim {

struct Counters {
  std::uint64_t bytes_received = 0;   // bytes that reached the firmware's RX buffer
  std::uint64_t bytes_sent = 0;       // bytes of replies
  std::uint64_t lines = 0;            // lines accepted into the command queue
  std::uint64_t commands = 0;         // commands executed
  std::uint64_t resends = 0;          // "Resend:" requests sent
  std::uint64_t errors = 0;           // rejected lines (checksum, line number, no checksum)
  std::uint64_t faults_injected = 0;  // every fault that fired, of any kind
  std::uint64_t overflows = 0;        // times bytes were lost to a full RX buffer
  std::uint64_t overflow_bytes = 0;   // bytes lost that way
  std::uint64_t long_lines = 0;       // lines cut at max_cmd_size
  std::uint64_t unknown_commands = 0;
  std::uint64_t resets = 0;           // power-ons and resets, the first included
  // The longest the firmware sat idle (nothing queued, running or arriving) before the host
  // sent its next byte, s: the longest silence a host left it in (the end of the job aside).
  double longest_idle = 0;
};

enum class PrinterState {
  running,       // accepting commands
  booting,       // after a reset, until `start`
  halted,        // kill() was called: nothing is read until a reset
  disconnected,  // a disconnect fault fired: the link is gone until reconnect
};

class Printer {
 public:
  explicit Printer(Config config = {});
  ~Printer();
  Printer(Printer&&) noexcept;
  Printer& operator=(Printer&&) noexcept;

  // Bytes from the host, sent at now(). They reach the firmware at the baud rate; bytes sent
  // while disconnected or halted are lost.
  void receive(std::string_view bytes);

  // Runs the firmware until sim time `t`; with t == now() it acts on what is due now (bytes
  // just received). No effect for t < now().
  void run_until(double t);
  // Runs until a reply has reached the host or until `t`, whichever is first; returns true
  // when a reply is ready (now() is then the time it arrived).
  bool run_until_output(double t);
  // Replies that have reached the host by now(), oldest first.
  std::string take_output();

  // Power cycle or a reset by DTR: the firmware restarts (queue, line numbers, position,
  // temperatures, modes) and says `start` after boot_time. The deposition record, the
  // command log and the counters survive: they describe what happened, not firmware state.
  void reset();
  // The link comes back after a disconnect fault; the board resets with it.
  void reconnect();

  // Sim time, s since power-on.
  double now() const;
  // When the firmware next does something on its own (a command finishes, a report is due,
  // a byte arrives); +infinity when it waits for the host.
  double next_event_time() const;
  PrinterState state() const;
  // Nothing to do until the host sends more: no command queued or running, no input pending.
  // (Moves may still be running out in the planner: their `ok`s have been sent.)
  bool idle() const;
  // Why the printer stopped or the link went, for messages ("thermal runaway", "kill()").
  const std::string& stop_reason() const;

  // Commands in the order executed, without line number, checksum or comment ("G1 X10 Y5").
  const std::vector<std::string>& executed_commands() const;
  // For each ok the faults dropped, how long the firmware then sat idle until the host sent
  // its next byte, s (0 when the host sent on before it ran out of work): the time a lost ok
  // cost.
  const std::vector<double>& lost_ok_waits() const;
  const DepositionRecord& deposition() const;
  const Counters& counters() const;
  const Config& config() const;

  // Seconds of motion planned so far and the time the last planned move ends; finish()
  // lets queued moves run out (as the firmware does when the host stops sending).
  double motion_time() const;
  double motion_end_time() const;
  // Seconds the head stood still mid-print because the next move had not arrived (the planner
  // ran empty; sim/motion.h).
  double planner_starved() const;
  void finish();

  // Live state, for reports and tests.
  struct Position {
    double x = 0, y = 0, z = 0, e = 0;
  };
  Position position() const;
  double hotend_temperature() const;
  double bed_temperature() const;
  double hotend_target() const;
  double bed_target() const;

 private:
  struct Firmware;
  std::unique_ptr<Firmware> firmware_;
};

}  // namespace sim
