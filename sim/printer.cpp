#include "sim/printer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include <fmt/core.h>

#include "printer/gcode_line.h"
#include "sim/command_queue.h"
#include "sim/dialect.h"
#include "sim/fault_injector.h"
#include "sim/heaters.h"
#include "sim/motion.h"
#include "sim/serial_line.h"
#include "sim/wire.h"

namespace sim {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr std::string_view kVersion = "2.1.2";

// Teacup's M116 (config/printer.mendel.h): every heater with a target within
// TEMP_HYSTERESIS 10 °C of it for TEMP_RESIDENCY_TIME 60 s.
constexpr double kTeacupHysteresis = 10, kTeacupResidency = 60;
// Repetier's timers (gcode.cpp readFromSerial, Configuration.h): a resend request is repeated
// after 200 ms without input; "wait" after 1 s; "busy:" every KEEP_ALIVE_INTERVAL 2 s.
constexpr double kRepetierResendRepeat = 0.2, kRepetierWait = 1.0, kRepetierKeepalive = 2.0;
// Lines Repetier skips after a resend request before it asks again (requestResend: 14).
constexpr int kRepetierSkips = 14;

// What the command executing waits for before its ok.
enum class Wait { none, planner, motion, hotend, bed, user, teacup_temperatures };

Config checked(Config config) {
  const DialectTraits& t = traits(config.dialect);
  if (t.queue_depth > 0) config.queue_depth = t.queue_depth;
  if (t.planner_depth > 0) config.planner_depth = t.planner_depth;
  config.queue_depth = std::max(config.queue_depth, 1);
  config.planner_depth = std::max(config.planner_depth, 1);
  config.rx_buffer_size = std::max(config.rx_buffer_size, 1);
  config.max_cmd_size = std::max(config.max_cmd_size, 2);
  return config;
}

}  // namespace

// The firmware: reads lines from the wire, queues and runs commands and says what Marlin
// says. Each concern is a part of its own (sim/wire.h, serial_line.h, command_queue.h,
// motion.h, heaters.h, fault_injector.h); this is what ties them together, in Marlin's order.
struct Printer::Firmware {
  Config cfg;
  const DialectTraits& talk;  // how this firmware's dialect speaks (sim/dialect.h)
  double now = 0;
  PrinterState state = PrinterState::booting;
  std::string stop_reason;
  Counters counters;
  std::vector<std::string> log;
  DepositionRecord record;
  FaultInjector faults;

  HostWire wire;
  SerialReceiver receiver;
  ReplyWire replies;
  long last_n = 0;
  CommandQueue queue;

  // The command executing (the queue's front while `executing`).
  bool executing = false;
  bool report_position_after = false;  // G28
  bool ok_with_temperatures = false;   // M105
  Wait wait = Wait::none;
  double done_at = 0;
  double next_busy = kInfinity;
  double next_wait_report = kInfinity;
  double last_activity = 0;  // for NO_TIMEOUTS' "wait"

  Motion motion;
  Heaters heaters;
  int fan = 0;
  double autoreport_interval = 0, next_autoreport = kInfinity;
  double busy_interval = 2;
  double boot_done = 0;
  // Repetier (gcode.cpp): waitingForResend, -1 when not waiting; when input last came.
  int waiting_for_resend = -1;
  double last_input = 0;
  // Teacup (temp.c): M116 set the flag; the next G0/G1 waits (temp_wait) until every heater is
  // settled; clock.c says "Waiting for target temp" each second meanwhile.
  bool teacup_wait_for_temp = false;
  double next_teacup_tick = kInfinity;
  std::optional<printer::GcodeCommand> teacup_waiting_move;

  // The firmware waiting for the host: since when (-1: busy), and whether the faults dropped
  // an ok since it last heard from the host (the wait it causes is then a lost ok's).
  double idle_since = -1;
  bool ok_lost = false;
  bool frozen = false;  // fault freeze-at-line: nothing read, nothing said, until a reset
  std::optional<std::string> late_ok;  // fault late-ok-at-line: held until the next request
  std::vector<double> lost_ok_waits;

  explicit Firmware(Config config)
      : cfg(checked(std::move(config))),
        talk(traits(cfg.dialect)),
        faults(cfg.faults),
        wire(cfg.baud),
        receiver(cfg.rx_buffer_size, cfg.max_cmd_size, cfg.dialect == Dialect::teacup),
        replies(cfg.baud),
        queue(cfg.queue_depth),
        motion(cfg, record, 0),
        heaters(cfg, 0) {
    power_on();
  }

  // ---- power and reset -------------------------------------------------------------------

  void power_on() {
    ++counters.resets;
    state = PrinterState::booting;
    stop_reason.clear();
    boot_done = now + std::max(cfg.boot_time, 0.0);
    wire.clear(now);
    receiver = SerialReceiver(cfg.rx_buffer_size, cfg.max_cmd_size, cfg.dialect == Dialect::teacup);
    last_n = 0;
    waiting_for_resend = -1;
    teacup_wait_for_temp = false;
    next_teacup_tick = kInfinity;
    teacup_waiting_move.reset();
    faults.power_on();
    frozen = false;
    late_ok.reset();
    queue.clear();
    executing = false;
    wait = Wait::none;
    next_busy = next_wait_report = kInfinity;
    replies.clear(now);
    motion = Motion(cfg, record, now);
    heaters = Heaters(cfg, now);
    fan = 0;
    autoreport_interval = 0;
    next_autoreport = kInfinity;
    busy_interval = cfg.busy_interval;
    last_activity = last_input = now;
    if (cfg.boot_time <= 0) finish_boot();
  }

  void finish_boot() {
    state = PrinterState::running;
    for (std::string& line : boot_banner(cfg.dialect, kVersion)) emit(std::move(line));
    last_activity = last_input = now;
  }

  // ---- output ----------------------------------------------------------------------------

  void emit(std::string text) {
    if (state == PrinterState::disconnected || frozen) return;
    counters.bytes_sent += replies.send(now + faults.reply_delay(), std::move(text));
  }

  // Whether this ok is lost to a fault; `blocked`: the command blocked the firmware.
  bool ok_dropped(bool blocked) {
    const bool dropped = faults.drop_ok() || (blocked && faults.drop_blocking_ok());
    if (!dropped) return false;
    ++counters.faults_injected;
    ok_lost = true;
    return true;
  }

  // A command's ok. Marlin (queue.cpp RingBuffer::ok_to_send): with ADVANCED_OK "ok N<n>
  // P<planner free> B<queue free>", the command still counted in the queue; M105 prints its
  // own "ok T:..." instead (temperature.cpp). Repetier (gcode.cpp checkAndPushCommand):
  // "ok <n>" with ACK_WITH_LINENUMBER. Teacup (mendel.c): "ok".
  void send_ok(const QueuedCommand& command, bool with_temperatures, bool blocked) {
    if (ok_dropped(blocked)) return;
    std::string ok = "ok";
    if (with_temperatures) {
      ok += heaters.states();
    } else if (cfg.dialect == Dialect::marlin && cfg.advanced_ok) {
      if (command.line_number) ok += fmt::format(" N{}", *command.line_number);
      ok += fmt::format(" P{} B{}", motion.planner_free(), queue.free());
    } else if (cfg.dialect == Dialect::repetier && cfg.repetier_ack_with_linenumber) {
      ok += fmt::format(" {}", command.line_number.value_or(last_n));
    }
    if (faults.ok_late_at(command.index)) {  // fault late-ok-at-line: after the next request
      ++counters.faults_injected;
      late_ok = ok;
      return;
    }
    const bool twice = faults.duplicate_ok();
    emit(ok);
    if (twice) {
      ++counters.faults_injected;
      emit(ok);
    }
  }

  // ---- serial input ----------------------------------------------------------------------

  void receive(std::string_view bytes) {
    if (state == PrinterState::disconnected || bytes.empty()) return;
    std::string sent(bytes);
    counters.faults_injected += static_cast<std::uint64_t>(faults.corrupt(sent));
    wire.send(now, std::move(sent), emergency_parser());
  }

  bool emergency_parser() const { return cfg.emergency_parser && talk.emergency_parser; }

  // A byte from the host reached the firmware: the wait for it, if the firmware was idle, ends.
  void heard_from_host() {
    if (idle_since >= 0) {
      const double waited = now - idle_since;
      counters.longest_idle = std::max(counters.longest_idle, waited);
      if (ok_lost) lost_ok_waits.push_back(waited);
      idle_since = -1;
    } else if (ok_lost) {
      lost_ok_waits.push_back(0);  // the host sent on before the firmware ran dry
    }
    ok_lost = false;
  }

  // Bytes that have arrived by now go to the firmware: read at once while the queue has
  // room (Marlin's loop keeps up), else into the RX buffer, else lost. The byte that
  // completes an emergency command acts as it arrives; bytes that arrived in the same instant
  // before it are read and their commands run first, so that a stream arriving at once keeps
  // its order. Returns true when it stopped at such a byte (there is more to deliver now).
  bool deliver() {
    std::size_t delivered = 0;
    while (const auto arrived = wire.peek(now)) {
      if (arrived->emergency != Emergency::none && delivered > 0) return true;
      wire.pop();
      if (delivered == 0) heard_from_host();
      last_input = now;
      const std::uint64_t clears = wire.clears();
      arrive(arrived->byte);
      if (wire.clears() != clears) return false;  // the line it ended disconnected the link
      ++delivered;
      if (arrived->emergency != Emergency::none) {
        if (state == PrinterState::running && !frozen) emergency(arrived->emergency);
        if (wire.clears() != clears) return false;
      }
    }
    return false;
  }

  void arrive(char c) {
    if (state == PrinterState::booting || state == PrinterState::halted || frozen) return;
    if (!receiver.has_buffered() && !queue.full() && state == PrinterState::running) {
      ++counters.bytes_received;
      read_char(c);
      return;
    }
    switch (receiver.buffer(c)) {
      case SerialReceiver::Buffered::kept: ++counters.bytes_received; break;
      case SerialReceiver::Buffered::lost_first: ++counters.overflows; [[fallthrough]];
      case SerialReceiver::Buffered::lost: ++counters.overflow_bytes; break;
    }
  }

  // Reads the RX buffer while the queue has room.
  void read_rx() {
    while (receiver.has_buffered() && !queue.full() && state == PrinterState::running) {
      read_char(receiver.take_buffered());
    }
  }

  // Marlin's get_serial_commands for one character.
  void read_char(char c) {
    bool cut = false;
    const std::optional<std::string> raw = receiver.read(c, cut);
    if (cut) ++counters.long_lines;
    if (raw) line_done(*raw);
  }

  void line_done(const std::string& raw) {
    switch (cfg.dialect) {
      case Dialect::marlin: return marlin_line(raw);
      case Dialect::teacup: return teacup_line(raw);
      case Dialect::repetier: return repetier_line(raw);
    }
  }

  // queue.cpp GCodeQueue::get_serial_commands: a line starting with N must be last_N + 1
  // (M110 excepted) and carry a matching checksum; unnumbered lines are not checked.
  void marlin_line(const std::string& raw) {
    const LineCheck check = check_line(raw, last_n);
    std::optional<long> number;
    if (check.verdict != LineVerdict::unnumbered) {
      if (check.verdict != LineVerdict::accepted) return marlin_line_error(check.verdict);
      if (faults.spurious_resend()) {
        ++counters.faults_injected;
        return marlin_line_error(LineVerdict::checksum_mismatch);
      }
      last_n = check.number;
      number = check.number;
      faults.line_accepted(check.number);
    }
    QueuedCommand queued{command_text(raw), number, ++counters.lines};
    if (!emergency_parser() && !number) {
      // queue.cpp's early check of unnumbered lines (EMERGENCY_PARSER disabled).
      if (queued.text.starts_with("M108")) emergency(Emergency::m108);
      if (queued.text.starts_with("M112")) emergency(Emergency::m112);
      if (queued.text.starts_with("M410")) emergency(Emergency::m410);
      if (state != PrinterState::running) return;
    }
    enqueue(std::move(queued));
  }

  // queue.cpp gcode_line_error: "Error:<what>, Last Line: <n>", the RX buffer emptied, then
  // flush_and_request_resend: "Resend: <n + 1>" and, in 2.1.x, "ok".
  void marlin_line_error(LineVerdict verdict) {
    ++counters.errors;
    ++counters.resends;
    emit(fmt::format("Error:{}{}", error_text(verdict), last_n));
    receiver.discard_buffered();
    emit(fmt::format("Resend: {}", last_n + 1));
    if (cfg.ok_after_resend) emit("ok");
    release_late_ok();
  }

  // The ok held back by late-ok-at-line, once a resend request has gone.
  void release_late_ok() {
    if (late_ok) emit(*std::exchange(late_ok, std::nullopt));
  }

  // gcode_parse.c gcode_parse_char at the line end: without REQUIRE_LINENUMBER the number is
  // never looked at; with it, N must be at least the expected one (or the line an M110). A
  // checksum, when there is one, must match. A refused line prints "rs N<expected> ..." and
  // still draws its ok from the main loop (mendel.c). N_expected follows the last numbered
  // line processed.
  void teacup_line(const std::string& raw) {
    const TeacupLine line = read_teacup_line(raw);
    const long expected = last_n + 1;
    const bool numbered_right =
        !cfg.teacup_require_linenumber || line.m110 || (line.number && *line.number >= expected);
    if (!numbered_right) {
      return teacup_refuse(fmt::format("rs N{} Expected line number {}", expected, expected));
    }
    if (!line.checksum_ok || (line.number && faults.spurious_resend() && ++counters.faults_injected)) {
      return teacup_refuse(fmt::format("rs N{} Expected checksum {}", expected, line.computed));
    }
    if (line.number) {
      last_n = *line.number;
      faults.line_accepted(*line.number);
    }
    enqueue(QueuedCommand{command_text(raw), line.number, ++counters.lines});
  }

  void teacup_refuse(std::string request) {
    ++counters.errors;
    ++counters.resends;
    emit(std::move(request));
    emit("ok");
    release_late_ok();
  }

  // gcode.cpp readFromSerial / parseAscii / checkAndPushCommand: a wrong checksum asks for the
  // line again; M110 and M112 are taken at once; a number at or a little below the last one
  // draws "skip", one above while a resend is awaited too, any other gap a resend request.
  void repetier_line(const std::string& raw) {
    const RepetierLine line = repetier_checked(raw);
    if (!line.checksum_ok) {
      emit("Error:Wrong checksum");
      return repetier_request_resend();
    }
    const std::string text = command_text(raw);
    const printer::GcodeCommand c = printer::parse_gcode_line(text);
    if (c.is('M', 110)) {
      last_n = line.number.value_or(last_n);
      emit("ok");
      waiting_for_resend = -1;
      return;
    }
    if (c.is('M', 112)) {  // Commands::emergencyStop: heaters off, then nothing more
      log.push_back("M112");
      ++counters.commands;
      kill("kill() by M112", false);
      return;
    }
    if (line.number && *line.number != last_n + 1) {
      if (static_cast<std::uint16_t>(last_n - *line.number) < 40) {
        emit(fmt::format("skip {}", *line.number));  // "we have seen that line already"
        emit("ok");
      } else if (waiting_for_resend < 0) {
        emit(fmt::format("Error:expected line {} got {}", last_n + 1, *line.number));
        repetier_request_resend();
      } else {
        --waiting_for_resend;
        emit(fmt::format("skip {}", *line.number));
        emit("ok");
      }
      return;
    }
    if (line.number) {
      last_n = *line.number;
      faults.line_accepted(*line.number);
    }
    waiting_for_resend = -1;
    enqueue(QueuedCommand{text, line.number, ++counters.lines});
  }

  RepetierLine repetier_checked(const std::string& raw) {
    RepetierLine line = read_repetier_line(raw);
    if (line.checksum_ok && line.number && *line.number == last_n + 1 && faults.spurious_resend()) {
      ++counters.faults_injected;
      line.checksum_ok = false;
    }
    return line;
  }

  // gcode.cpp requestResend: the serial input flushed, an empty line, "Resend:<n>", "ok".
  void repetier_request_resend() {
    ++counters.errors;
    ++counters.resends;
    receiver.discard_buffered();
    receiver.drop_line();
    waiting_for_resend = kRepetierSkips;
    emit("");
    emit(fmt::format("Resend:{}", last_n + 1));
    emit("ok");
    release_late_ok();
    last_input = now;
  }

  // A line accepted into the command queue (Repetier acknowledges it here).
  void enqueue(QueuedCommand queued) {
    last_activity = now;
    if (talk.ok_at == OkAt::queued) send_ok(queued, false, blocks_repetier(queued.text));
    queue.push(std::move(queued));
    if (faults.freezes_at_line(counters.lines)) frozen = true;  // fault freeze-at-line
    if (faults.disconnects_at_line(counters.lines)) {
      disconnect(fmt::format("disconnected at line {} (fault disconnect-at-line)", counters.lines));
    }
  }

  // Repetier commands that block the firmware once they run (for drop-blocking-ok).
  static bool blocks_repetier(const std::string& text) {
    const printer::GcodeCommand c = printer::parse_gcode_line(text);
    return c.is('G', 4) || c.is('G', 28) || c.is('M', 109) || c.is('M', 190) || c.is('M', 116) ||
           c.is('M', 400);
  }

  void emergency(Emergency e) {
    switch (e) {
      case Emergency::m108:
        if (executing && (wait == Wait::hotend || wait == Wait::bed || wait == Wait::user)) {
          done_at = now;
        }
        break;
      case Emergency::m112:
        log.push_back("M112");
        ++counters.commands;
        kill("kill() by M112");
        break;
      case Emergency::m410:
        motion.quickstop(now);
        break;
      case Emergency::none:
        break;
    }
  }

  // ---- faults and stops ------------------------------------------------------------------

  // `say`: Marlin says so; Teacup freezes and Repetier resets without a word.
  void kill(std::string reason, bool say = true) {
    heaters.all_off();
    if (say) emit("Error:Printer halted. kill() called!");
    if (state != PrinterState::disconnected) state = PrinterState::halted;
    stop_reason = std::move(reason);
    queue.clear();
    executing = false;
    wait = Wait::none;
    receiver.discard_buffered();
    receiver.drop_line();
    next_busy = next_wait_report = next_autoreport = kInfinity;
    motion.quickstop(now);
  }

  void disconnect(std::string reason) {
    ++counters.faults_injected;
    state = PrinterState::disconnected;
    stop_reason = std::move(reason);
    wire.clear(now);
    receiver.discard_buffered();
    replies.clear(now);
  }

  void thermal_runaway() {
    stop_reason = "thermal runaway (fault runaway-at-line)";
    emit("Error:Thermal Runaway, system stopped! Heater_ID: 0");
    kill("thermal runaway (fault runaway-at-line)");
  }

  // ---- heaters ---------------------------------------------------------------------------

  // M109/M190: wait_for_hotend / wait_for_bed. Reports at once and every second; done when
  // within the window for the residency time and at the target.
  void heat_wait(Heaters::Which which, bool wait_for_cooling) {
    heating_report(which);
    next_wait_report = now + 1;
    done_at = heaters.start_wait(which, wait_for_cooling, now);
    wait = which == Heaters::Which::hotend ? Wait::hotend : Wait::bed;
  }

  // The report a heating wait prints each second: Marlin's with "W:", Repetier's auto-report.
  void heating_report(Heaters::Which which) {
    if (!talk.reports_while_heating) return;
    emit(talk.wait_report_field ? heaters.wait_report(which, now) : temperature_report());
  }

  // ---- commands --------------------------------------------------------------------------

  void start_next() {
    QueuedCommand& command = queue.front();
    if (faults.halts_at(command.index)) {
      ++counters.faults_injected;
      kill(fmt::format("halted at line {} (fault halt-at-line)", command.index));
      return;
    }
    log.push_back(command.text);
    ++counters.commands;
    executing = true;
    wait = Wait::none;
    done_at = now;
    report_position_after = ok_with_temperatures = false;
    next_busy = talk.busy_keepalive && busy_interval > 0 ? now + busy_interval : kInfinity;
    if (faults.fails_heater_at(command.index)) {
      ++counters.faults_injected;
      heaters.fail_hotend(now);
    }
    execute(command);
    if (cfg.dialect == Dialect::repetier && executing && wait != Wait::none && wait != Wait::planner) {
      next_busy = now + kRepetierKeepalive;  // GCode::keepAlive while it blocks
    }
  }

  void complete() {
    if (teacup_waiting_move) {
      // The temperatures are reached: the move G0/G1 held back (temp_wait) goes ahead.
      const printer::GcodeCommand move = *std::exchange(teacup_waiting_move, std::nullopt);
      wait = Wait::none;
      done_at = motion.move(move, now).entered;
      if (done_at > now) {
        wait = Wait::planner;
        return;
      }
    }
    const bool blocked = wait != Wait::none && wait != Wait::planner;
    executing = false;
    wait = Wait::none;
    next_busy = next_wait_report = kInfinity;
    heaters.end_wait();
    last_activity = now;
    if (talk.ok_at == OkAt::done) {
      if (report_position_after) emit(position_reply());  // G28 ends with it
      send_ok(queue.front(), ok_with_temperatures, blocked);
    }
    queue.pop();
  }

  std::string position_reply() const {
    const Motion::Head& h = motion.head();
    const double steps[3] = {cfg.steps_per_mm[0], cfg.steps_per_mm[1], cfg.steps_per_mm[2]};
    return sim::position_reply(cfg.dialect, {h.x, h.y, h.z, h.e, motion.inches()}, motion.feedrate(), steps);
  }

  void unknown(const QueuedCommand& command, const printer::GcodeCommand& c) {
    ++counters.unknown_commands;
    emit(unknown_reply(cfg.dialect, command.text, c, command.line_number));
  }

  void execute(const QueuedCommand& command) {
    printer::GcodeCommand c = printer::parse_gcode_line(command.text);
    if (cfg.dialect == Dialect::teacup) {
      // gcode_parse.c: a line of axis words alone is a G1; a line without any command does
      // nothing (and still gets its ok).
      if (c.letter != 'G' && c.letter != 'M' && c.letter != 'T') {
        if (command.text.find_first_of("XYZEFxyzef") == std::string::npos) return;
        c = printer::parse_gcode_line("G1 " + command.text);
      }
    }
    if (!knows(cfg.dialect, c)) return unknown(command, c);
    if (cfg.dialect == Dialect::teacup && execute_teacup(c)) return;
    if (cfg.dialect == Dialect::repetier && execute_repetier(c)) return;
    if (c.letter == 'G') {
      switch (c.code) {
        case 0:
        case 1:
        case 2:
        case 3: {
          const Motion::Queued queued = motion.move(c, now);
          // G2_G3.cpp: an arc without a centre is SERIAL_ERROR_MSG(STR_ERR_ARC_ARGS)
          // (language.h). Repetier's own arc code is not rebuilt here: it stays silent.
          if (queued.bad_arc && cfg.dialect == Dialect::marlin) emit("Error:G2/G3 bad parameters");
          done_at = queued.entered;
          if (done_at > now) wait = Wait::planner;
          return;
        }
        case 4:
          done_at = motion.finish(now) + *printer::dwell_seconds(c);
          wait = Wait::motion;
          return;
        case 28:
          done_at = motion.home(c, now);
          wait = Wait::motion;
          report_position_after = true;
          return;
        case 21: return;  // gcode.cpp, built without INCH_MODE_SUPPORT: "case 21: NOOP; // No error on unknown G21"
        case 90: case 91: motion.set_mode(c); return;
        case 92:  // G92.1 and G92.9 only with CNC_COORDINATE_SYSTEMS or POWER_LOSS_RECOVERY
          if (c.subcode == 0) motion.set_position(c);
          return;
        default: break;
      }
    } else if (c.letter == 'M') {
      switch (c.code) {
        case 0:
        case 1: {
          double limit = kInfinity;
          if (auto p = c.get('P')) limit = *p / 1000.0;
          if (auto s = c.get('S')) limit = *s;
          done_at = motion.finish(now) + limit;
          wait = Wait::user;
          return;
        }
        case 17: case 73: case 75: case 76: case 77: case 111: case 117: case 300:
          return;
        case 18:
        case 84:
          if (!c.has('S')) {
            done_at = motion.finish(now);
            wait = Wait::motion;
          }
          return;
        case 82: case 83: motion.set_mode(c); return;
        case 104:
          if (auto s = c.get('S')) heaters.set_hotend(*s, now);
          return;
        case 105:
          ok_with_temperatures = true;
          return;
        case 106: fan = static_cast<int>(std::clamp(c.get('S').value_or(255), 0.0, 255.0)); return;
        case 107: fan = 0; return;
        case 108: return;  // already acted on when the line arrived
        case 109:
        case 190: {
          const bool hot = c.code == 109;
          const auto s = c.get('S');
          const auto r = c.get('R');
          if (!s && !r) return;
          hot ? heaters.set_hotend(s ? *s : *r, now) : heaters.set_bed(s ? *s : *r);
          // The planner runs dry while the firmware waits: later moves start from rest.
          motion.finish(now);
          heat_wait(hot ? Heaters::Which::hotend : Heaters::Which::bed, !s);
          return;
        }
        case 110:
          if (auto n = c.get('N')) last_n = static_cast<long>(*n);
          return;
        case 112:
          kill("kill() by M112");
          return;
        case 113:
          if (auto s = c.get('S')) busy_interval = std::clamp(*s, 0.0, 60.0);
          return;
        case 114:
          emit(position_reply());
          return;
        case 115:
          report_firmware();
          return;
        case 140:
          if (auto s = c.get('S')) heaters.set_bed(*s);
          return;
        case 155:
          if (auto s = c.get('S')) {
            autoreport_interval = std::clamp(*s, 0.0, 60.0);
            next_autoreport = autoreport_interval > 0 ? now + autoreport_interval : kInfinity;
          }
          return;
        case 201: case 203: case 204: case 205:
          motion.set_limits(c);
          return;
        case 220:
          if (auto s = c.get('S')) motion.set_feed_percent(std::max(*s, 1.0));
          return;
        case 221:
          motion.set_mode(c);
          return;
        case 400:
          done_at = motion.finish(now);
          wait = Wait::motion;
          return;
        case 410:
          motion.quickstop(now);
          return;
        case 999:
          if (!c.has('S') || c.get('S').value_or(0) == 0) {
            ++counters.resends;
            emit(fmt::format("Resend: {}", last_n + 1));
          }
          return;
        default: break;
      }
    } else if (c.letter == 'T' && c.code >= 0) {
      if (c.code > 0) emit(fmt::format("echo:T{} Invalid extruder", c.code));
      return;
    }
    unknown(command, c);
  }

  HeaterReadings readings() const {
    return {heaters.hotend().temperature(), heaters.hotend().target(), heaters.bed().temperature(),
            heaters.bed().target(), 2 * heaters.hotend().power(), 2 * heaters.bed().power()};
  }

  // When Teacup's temp_achieved() turns true: every heater with a target settled.
  double teacup_settled_at() const {
    return std::max(heaters.settled_at(Heaters::Which::hotend, kTeacupHysteresis, kTeacupResidency),
                    heaters.settled_at(Heaters::Which::bed, kTeacupHysteresis, kTeacupResidency));
  }

  // gcode_process.c process_gcode_command, where Teacup differs from Marlin's switch; false:
  // Marlin's way is Teacup's too.
  bool execute_teacup(const printer::GcodeCommand& c) {
    if (c.letter == 'T') return true;  // next_tool; no output
    if (c.letter == 'G') {
      switch (c.code) {
        case 0:
        case 1:
          if (teacup_wait_for_temp && teacup_settled_at() > now) {  // temp_wait()
            teacup_waiting_move = c;
            done_at = teacup_settled_at();
            wait = Wait::teacup_temperatures;
            return true;
          }
          return false;
        case 4:  // queue_wait(), then P milliseconds (no S)
          done_at = motion.finish(now) + std::max(c.get('P').value_or(0), 0.0) / 1000.0;
          wait = Wait::motion;
          return true;
        case 20: case 21:  // inches/mm: gcode_parse.c reads X Y Z E, and F (254/10), in inches
          motion.set_mode(c);
          return true;
        case 28:  // queue_wait(), then home; no position report
          done_at = motion.home(c, now);
          wait = Wait::motion;
          return true;
        case 92: {  // queue_wait() first
          done_at = motion.finish(now);
          wait = Wait::motion;
          // A bare axis is 0, no axis all four: Teacup's G92 rule (sim/dialect.cpp gcode_rules).
          motion.set_position(c);
          return true;
        }
        case 161: case 162:
          done_at = motion.home(c, now);
          wait = Wait::motion;
          return true;
        default:
          return false;
      }
    }
    switch (c.code) {
      case 0:
      case 2:
      case 84:
        // M0/M2/M84 (M84 "for compatibility with slic3r's default end G-code"): queue_wait(),
        // every heater off, power off, "\nstop\n".
        done_at = motion.finish(now);
        wait = Wait::motion;
        heaters.set_hotend(0, now);
        heaters.set_bed(0);
        emit("");
        emit("stop");
        return true;
      case 3: case 5: case 6: case 101: case 103: case 119:
        return true;
      case 7:
        fan = static_cast<int>(std::clamp(c.get('S').value_or(fan), 0.0, 255.0));
        return true;
      case 105:
        emit(teacup_temperatures(readings()));  // temp_print, then the ok
        return true;
      case 110:
        return true;  // "a no-op in Teacup": the line's own N set N_expected
      case 112:  // timer_stop, queue_flush, power_off, cli(), and a loop for ever
        kill("kill() by M112", false);
        frozen = true;
        return true;
      case 115:
        emit(firmware_report(cfg.dialect, kVersion));
        emit("cap:AUTOREPORT_TEMP:1");
        return true;
      case 116:  // temp_set_wait(): the next G0/G1 waits
        teacup_wait_for_temp = true;
        next_teacup_tick = now + 1;
        return true;
      case 155:
        if (auto s = c.get('S')) {
          autoreport_interval = std::clamp(*s, 0.0, 255.0);
          next_autoreport = autoreport_interval > 0 ? now + autoreport_interval : kInfinity;
        }
        return true;
      default:
        return false;
    }
  }

  // Commands.cpp processMCode, where Repetier differs from Marlin's switch.
  bool execute_repetier(const printer::GcodeCommand& c) {
    // G20/G21: units (Commands.cpp processGCode, in every build); Printer.cpp's convertToMM
    // reads X Y Z E in inches after G20, and F times 25.4 (0.0042333 = 25.4 / 60 / 100).
    if (c.is('G', 20) || c.is('G', 21)) {
      motion.set_mode(c);
      return true;
    }
    if (c.letter != 'M') return false;
    switch (c.code) {
      case 105:
        emit(repetier_temperatures(readings()));  // after the ok it sent on reading the line
        return true;
      case 115: {
        emit(firmware_report(cfg.dialect, kVersion));
        for (const std::string_view cap :
             {"PROGRESS:0", "AUTOREPORT_TEMP:1", "HOST_RESCUE:0", "EEPROM:1", "AUTOLEVEL:0",
              "Z_PROBE:0", "SOFTWARE_POWER:0", "TOGGLE_LIGHTS:0", "PAUSESTOP:1", "PREHEAT:1",
              "EMERGENCY_PARSER:0"}) {
          emit(fmt::format("Cap:{}", cap));
        }
        return true;
      }
      case 116: {
        // Every heater with a target, in turn (TemperatureController::waitForTargetTemperature).
        motion.finish(now);
        done_at = now;
        for (const Heaters::Which which : {Heaters::Which::hotend, Heaters::Which::bed}) {
          const Heater& h = which == Heaters::Which::bed ? heaters.bed() : heaters.hotend();
          if (h.target() > 0) done_at = std::max(done_at, heaters.start_wait(which, false, now));
        }
        wait = Wait::hotend;
        next_wait_report = now + 1;
        return true;
      }
      case 155:  // S<1/0>: temperatures every second
        autoreport_interval = c.get('S').value_or(1) != 0 ? 1.0 : 0.0;
        next_autoreport = autoreport_interval > 0 ? now + autoreport_interval : kInfinity;
        return true;
      default:
        return false;
    }
  }

  // M115.cpp: the FIRMWARE_NAME line, then a "Cap:" line per capability.
  void report_firmware() {
    emit(firmware_report(cfg.dialect, kVersion));
    const std::pair<std::string_view, bool> caps[] = {
        {"SERIAL_XON_XOFF", false},   {"BINARY_FILE_TRANSFER", false},
        {"EEPROM", false},            {"VOLUMETRIC", false},
        {"AUTOREPORT_TEMP", true},    {"PROGRESS", false},
        {"PRINT_JOB", true},          {"AUTOLEVEL", false},
        {"RUNOUT", false},            {"Z_PROBE", false},
        {"LEVELING_DATA", false},     {"BUILD_PERCENT", true},
        {"SOFTWARE_POWER", false},    {"TOGGLE_LIGHTS", false},
        {"CASE_LIGHT_BRIGHTNESS", false}, {"EMERGENCY_PARSER", emergency_parser()},
        {"PROMPT_SUPPORT", false},    {"SDCARD", false},
        {"REPEAT", false},            {"AUTOREPORT_SD_STATUS", false},
        {"LONG_FILENAME", false},     {"THERMAL_PROTECTION", true},
        {"MOTION_MODES", false},      {"ARCS", true},
        {"BABYSTEPPING", false},      {"CHAMBER_TEMPERATURE", false},
        {"COOLER_TEMPERATURE", false}, {"MEATPACK", false},
    };
    for (const auto& [name, on] : caps) emit(fmt::format("Cap:{}:{}", name, on ? 1 : 0));
  }

  // ---- the loop --------------------------------------------------------------------------

  void advance_clock(double t) {
    if (t <= now) return;
    now = t;
    heaters.advance_to(now);
  }

  // Does everything due at `now`.
  void settle() {
    if (state == PrinterState::booting && now >= boot_done) {
      deliver();  // input during boot is lost
      finish_boot();
    }
    if (faults.disconnect_time_due(now) && state != PrinterState::disconnected) {
      disconnect(fmt::format("disconnected at {:g} s (fault disconnect-at-time)",
                             *cfg.faults.disconnect_at_time));
    }
    if (now >= heaters.runaway_at() && state != PrinterState::halted) thermal_runaway();
    for (bool progress = true; progress;) {
      progress = deliver();
      if (state != PrinterState::running && state != PrinterState::disconnected) {
        receiver.discard_buffered();
        return;
      }
      if (receiver.has_buffered() && !queue.full()) read_rx();
      if (!executing && !queue.empty()) {
        start_next();
        progress = true;
      }
      if (executing && done_at <= now) {
        complete();
        progress = true;
      }
    }
    if (executing && now >= next_busy) {
      emit(busy_line());
      next_busy = now + (cfg.dialect == Dialect::repetier ? kRepetierKeepalive : busy_interval);
    }
    if (executing && now >= next_wait_report) {
      if (wait == Wait::hotend) heating_report(Heaters::Which::hotend);
      if (wait == Wait::bed) heating_report(Heaters::Which::bed);
      next_wait_report = now + 1;
    }
    if (now >= next_autoreport) {
      emit(temperature_report());
      next_autoreport = now + autoreport_interval;
    }
    if (teacup_wait_for_temp && now >= next_teacup_tick) {
      // clock.c, each second: "Waiting for target temp" until temp_achieved(), then once
      // "Temp achieved" and the flag is cleared (temp_waiting).
      if (teacup_settled_at() > now) {
        emit("Waiting for target temp");
        next_teacup_tick = now + 1;
      } else {
        emit("Temp achieved");
        teacup_wait_for_temp = false;
        next_teacup_tick = kInfinity;
      }
    }
    if (cfg.idle_wait_interval > 0 && !executing && queue.empty() && !receiver.has_buffered() &&
        now >= last_activity + cfg.idle_wait_interval) {
      emit("wait");  // Marlin's NO_TIMEOUTS
      last_activity = now;
    }
    if (const double t = repetier_idle_at(); now >= t) {
      if (waiting_for_resend >= 0) {
        repetier_request_resend();  // "a started line was not continued": ask again
      } else {
        emit("wait");  // WAITING_IDENTIFIER: unblock a host whose ok was lost
        last_input = now;
      }
    }
    if (state == PrinterState::running && idle() && idle_since < 0) idle_since = now;
  }

  // When Repetier, its buffer empty and no input coming, next speaks up (gcode.cpp
  // readFromSerial): 200 ms after the last input while it awaits a resent line, else 1 s.
  double repetier_idle_at() const {
    if (cfg.dialect != Dialect::repetier || state != PrinterState::running || frozen || executing ||
        !queue.empty() || receiver.has_buffered() || !wire.empty()) {
      return kInfinity;
    }
    return last_input + (waiting_for_resend >= 0 ? kRepetierResendRepeat : kRepetierWait);
  }

  std::string busy_line() const {
    if (cfg.dialect == Dialect::repetier) {  // GCode::keepAlive
      return wait == Wait::hotend || wait == Wait::bed ? "busy:heating" : "busy:processing";
    }
    return wait == Wait::user ? "echo:busy: paused for user" : "echo:busy: processing";
  }

  // An auto-report (M155) in this dialect's words.
  std::string temperature_report() const {
    switch (cfg.dialect) {
      case Dialect::teacup: return teacup_temperatures(readings());
      case Dialect::repetier: return repetier_temperatures(readings());
      case Dialect::marlin: break;
    }
    return heaters.states();
  }

  // The next time after now at which the firmware does something on its own. settle() has
  // done everything due at now, so only later times count.
  double next_event() const {
    double next = kInfinity;
    const auto consider = [&](double t) {
      if (t > now && t < next) next = t;
    };
    consider(replies.next_arrival());
    consider(faults.next_disconnect_time());
    if (state == PrinterState::booting) {
      consider(boot_done);
      return next;
    }
    if (state == PrinterState::halted) return next;
    consider(wire.next_emergency());
    if (!queue.full() && state == PrinterState::running) {
      // Bytes just received are due now (settle() has read everything that came before).
      const double line_end = std::max(wire.next_line_end(), now);
      if (line_end < next) next = line_end;
    }
    if (executing) {
      consider(done_at);
      consider(next_busy);
      consider(next_wait_report);
    }
    consider(next_autoreport);
    consider(heaters.runaway_at());
    if (cfg.idle_wait_interval > 0 && !executing && queue.empty()) {
      consider(last_activity + cfg.idle_wait_interval);
    }
    if (teacup_wait_for_temp) consider(next_teacup_tick);
    consider(repetier_idle_at());
    return next;
  }

  bool run(double until, bool stop_on_output) {
    for (;;) {
      settle();
      if (stop_on_output && replies.ready(now)) return true;
      const double next = next_event();
      if (next > until || next == kInfinity) {
        advance_clock(until);
        settle();
        return replies.ready(now);
      }
      advance_clock(next);
    }
  }

  bool idle() const {
    return !executing && queue.empty() && !receiver.has_buffered() &&
           wire.next_emergency() == kInfinity && wire.next_line_end() == kInfinity;
  }
};

Printer::Printer(Config config) : firmware_(std::make_unique<Firmware>(std::move(config))) {}
Printer::~Printer() = default;
Printer::Printer(Printer&&) noexcept = default;
Printer& Printer::operator=(Printer&&) noexcept = default;

void Printer::receive(std::string_view bytes) { firmware_->receive(bytes); }

void Printer::run_until(double t) {
  if (t >= firmware_->now) firmware_->run(t, false);
}

bool Printer::run_until_output(double t) {
  return firmware_->run(std::max(t, firmware_->now), true);
}

std::string Printer::take_output() { return firmware_->replies.take(firmware_->now); }

void Printer::reset() { firmware_->power_on(); }

void Printer::reconnect() {
  if (firmware_->state == PrinterState::disconnected) firmware_->state = PrinterState::running;
  firmware_->power_on();
}

double Printer::now() const { return firmware_->now; }
double Printer::next_event_time() const { return firmware_->next_event(); }
PrinterState Printer::state() const { return firmware_->state; }
bool Printer::idle() const { return firmware_->idle(); }
const std::string& Printer::stop_reason() const { return firmware_->stop_reason; }
const std::vector<std::string>& Printer::executed_commands() const { return firmware_->log; }
const std::vector<double>& Printer::lost_ok_waits() const { return firmware_->lost_ok_waits; }
const DepositionRecord& Printer::deposition() const { return firmware_->record; }
const Counters& Printer::counters() const { return firmware_->counters; }
const Config& Printer::config() const { return firmware_->cfg; }
double Printer::motion_time() const { return firmware_->motion.motion_time(); }
double Printer::motion_end_time() const { return firmware_->motion.end_time(); }
double Printer::planner_starved() const { return firmware_->motion.starved(); }
void Printer::finish() { firmware_->motion.finish(firmware_->now); }

Printer::Position Printer::position() const {
  const Motion::Head& head = firmware_->motion.head();
  return {head.x, head.y, head.z, head.e};
}
double Printer::hotend_temperature() const { return firmware_->heaters.hotend().temperature(); }
double Printer::bed_temperature() const { return firmware_->heaters.bed().temperature(); }
double Printer::hotend_target() const { return firmware_->heaters.hotend().target(); }
double Printer::bed_target() const { return firmware_->heaters.bed().target(); }

}  // namespace sim
