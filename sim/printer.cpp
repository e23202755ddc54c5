#include "sim/printer.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
constexpr std::string_view kVersion = "2.0.9.3";

// What the command executing waits for before its ok.
enum class Wait { none, planner, motion, hotend, bed, user };

Config checked(Config config) {
  config.queue_depth = traits(config.dialect).one_line_at_a_time ? 1 : std::max(config.queue_depth, 1);
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
  int skips_left = 0;  // Repetier: lines in flight after a resend request it answers "skip"
  // Ok-when-read dialects: what the command executing says, for its ok line (Teacup) or
  // after it (Repetier).
  std::vector<std::string> said;
  bool saying = false;

  // The firmware waiting for the host: since when (-1: busy), and whether the faults dropped
  // an ok since it last heard from the host (the wait it causes is then a lost ok's).
  double idle_since = -1;
  bool ok_lost = false;
  bool frozen = false;  // fault freeze-at-line: nothing read, nothing said, until a reset
  std::vector<double> lost_ok_waits;

  explicit Firmware(Config config)
      : cfg(checked(std::move(config))),
        talk(traits(cfg.dialect)),
        faults(cfg.faults),
        wire(cfg.baud),
        receiver(cfg.rx_buffer_size, cfg.max_cmd_size),
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
    receiver = SerialReceiver(cfg.rx_buffer_size, cfg.max_cmd_size);
    last_n = 0;
    faults.power_on();
    frozen = false;
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
    last_activity = now;
    if (cfg.boot_time <= 0) finish_boot();
  }

  void finish_boot() {
    state = PrinterState::running;
    for (std::string& line : boot_banner(cfg.dialect, kVersion)) emit(std::move(line));
    last_activity = now;
  }

  // ---- output ----------------------------------------------------------------------------

  void emit(std::string text) {
    if (state == PrinterState::disconnected || frozen) return;
    counters.bytes_sent += replies.send(now + faults.reply_delay(), std::move(text));
  }

  // What a command prints: at once, or, in an ok-when-read dialect, with its ok.
  void say(std::string text) {
    if (saying) {
      said.push_back(std::move(text));
    } else {
      emit(std::move(text));
    }
  }

  // Whether this ok is lost to a fault; `blocked`: the command blocked the firmware.
  bool ok_dropped(bool blocked) {
    const bool dropped = faults.drop_ok() || (blocked && faults.drop_blocking_ok());
    if (!dropped) return false;
    ++counters.faults_injected;
    ok_lost = true;
    return true;
  }

  // The ok of an executed command; M105's carries the temperatures instead of ADVANCED_OK's
  // fields, since Marlin's M105 prints its own ok.
  void send_ok(const QueuedCommand& command, bool with_temperatures, bool blocked) {
    if (ok_dropped(blocked)) return;
    std::string ok = "ok";
    if (with_temperatures) {
      ok += heaters.states();
    } else if (cfg.advanced_ok) {
      if (command.line_number) ok += fmt::format(" N{}", *command.line_number);
      ok += fmt::format(" P{} B{}", motion.planner_free(), queue.free());
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
    const LineCheck check =
        check_line(raw, last_n, LineRules{talk.takes_skipped_numbers, talk.requires_checksum});
    std::optional<long> number;
    if (check.verdict != LineVerdict::unnumbered) {
      if (check.verdict == LineVerdict::wrong_line_number && skips_left > 0) {
        // Repetier: a line sent before its resend request reached the host.
        --skips_left;
        emit(fmt::format("skip {}", check.number));
        emit("ok");
        receiver.discard_buffered();
        return;
      }
      if (check.verdict != LineVerdict::accepted) return line_error(check.verdict, raw);
      if (faults.spurious_resend()) {
        ++counters.faults_injected;
        return line_error(LineVerdict::checksum_mismatch, raw);
      }
      last_n = check.number;
      number = check.number;
      skips_left = 0;
      faults.line_accepted(check.number);
    }

    QueuedCommand queued{command_text(raw), number, ++counters.lines};
    if (cfg.dialect == Dialect::repetier && queued.text.starts_with("M112")) {
      // Repetier stops the moment it reads M112 (checkAndPushCommand), without a word.
      log.push_back("M112");
      ++counters.commands;
      kill("kill() by M112", false);
      return;
    }
    if (cfg.dialect == Dialect::marlin && !emergency_parser() && !number) {
      // queue.cpp's early check of unnumbered lines.
      if (queued.text.starts_with("M108")) emergency(Emergency::m108);
      if (queued.text.starts_with("M112")) emergency(Emergency::m112);
      if (queued.text.starts_with("M410")) emergency(Emergency::m410);
      if (state != PrinterState::running) return;
    }
    last_activity = now;
    if (talk.ok_at == OkAt::queued) ok_on_queueing(queued.text);
    queue.push(std::move(queued));
    if (faults.freezes_at_line(counters.lines)) frozen = true;  // fault freeze-at-line
    if (faults.disconnects_at_line(counters.lines)) {
      disconnect(fmt::format("disconnected at line {} (fault disconnect-at-line)", counters.lines));
    }
  }

  // Repetier's ok as it queues a line (checkAndPushCommand); the command's output comes when
  // it runs.
  void ok_on_queueing(const std::string& text) {
    const printer::GcodeCommand c = printer::parse_gcode_line(text);
    const bool blocks = c.is('G', 4) || c.is('G', 28) || c.is('M', 0) || c.is('M', 1) ||
                        c.is('M', 109) || c.is('M', 190) || c.is('M', 116) || c.is('M', 400);
    if (ok_dropped(blocks)) return;
    const bool twice = faults.duplicate_ok();
    emit("ok");
    if (twice) {
      ++counters.faults_injected;
      emit("ok");
    }
  }

  // Marlin's gcode_line_error + flush_and_request_resend, in this dialect's words.
  void line_error(LineVerdict verdict, std::string_view raw) {
    ++counters.errors;
    ++counters.resends;
    const std::vector<std::string> request =
        resend_request(cfg.dialect, error_text(verdict), last_n + 1, received_checksum(raw));
    emit(request.front());
    receiver.discard_buffered();
    for (std::size_t i = 1; i < request.size(); ++i) emit(request[i]);
    if (talk.ok_after_resend.value_or(cfg.ok_after_resend)) emit("ok");
    if (talk.skips_after_resend) skips_left = 14;  // Repetier's waitingForResend
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

  // The report a heating wait prints each second: Marlin's with "W:", Repetier's without.
  void heating_report(Heaters::Which which) {
    if (!talk.reports_while_heating) return;
    emit(talk.wait_report_field ? heaters.wait_report(which, now) : heaters.states());
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
    if (talk.ok_at != OkAt::start) {
      execute(command);
      return;
    }
    // Teacup writes "ok " before it runs the command and puts its output on the same line.
    said.clear();
    saying = true;
    execute(command);
    saying = false;
    if (state != PrinterState::running) return;  // M112 or a fault stopped it
    const bool blocked = wait != Wait::none && wait != Wait::planner;
    const bool dropped = ok_dropped(blocked);
    const bool twice = !dropped && faults.duplicate_ok();
    std::string ok = "ok";
    if (talk.output_on_ok_line) {  // a lost ok loses what was on its line
      for (const std::string& text : said) ok += " " + text;
      said.clear();
    }
    if (!dropped) {
      emit(ok);
      if (twice) {
        ++counters.faults_injected;
        emit(ok);
      }
    }
    for (std::string& text : said) emit(std::move(text));
    said.clear();
  }

  void complete() {
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
    return sim::position_reply(cfg.dialect, {h.x, h.y, h.z, h.e}, motion.feedrate(), steps);
  }

  void unknown(const std::string& text, const printer::GcodeCommand& c) {
    ++counters.unknown_commands;
    say(unknown_reply(cfg.dialect, text, c));
  }

  void execute(const QueuedCommand& command) {
    const printer::GcodeCommand c = printer::parse_gcode_line(command.text);
    if (!knows(cfg.dialect, c)) return unknown(command.text, c);
    if (cfg.dialect != Dialect::marlin && execute_other_dialect(c)) return;
    if (c.letter == 'G') {
      switch (c.code) {
        case 0:
        case 1:
        case 2:
        case 3: {
          done_at = c.code <= 1 ? motion.move(c, now) : motion.arc(c, c.code == 2, now);
          if (done_at > now) wait = Wait::planner;
          return;
        }
        case 4: {
          double dwell = 0;
          if (auto p = c.get('P')) dwell = *p / 1000.0;
          if (auto s = c.get('S')) dwell = *s;
          done_at = motion.finish(now) + std::max(dwell, 0.0);
          wait = Wait::motion;
          return;
        }
        case 28:
          done_at = motion.home(c, now);
          wait = Wait::motion;
          report_position_after = true;
          return;
        case 90: motion.absolute_positioning(true); return;
        case 91: motion.absolute_positioning(false); return;
        case 92: motion.set_position(c); return;
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
        case 82: motion.absolute_extrusion(true); return;
        case 83: motion.absolute_extrusion(false); return;
        case 104:
          if (auto s = c.get('S')) heaters.set_hotend(*s, now);
          return;
        case 105:
          if (cfg.dialect == Dialect::marlin) {
            ok_with_temperatures = true;
          } else {
            say(heaters.states());  // Repetier: a line after its ok
          }
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
          kill("kill() by M112", cfg.dialect == Dialect::marlin);
          return;
        case 113:
          if (auto s = c.get('S')) busy_interval = std::clamp(*s, 0.0, 60.0);
          return;
        case 114:
          say(position_reply());
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
          if (auto s = c.get('S')) motion.set_flow_percent(std::max(*s, 0.0));
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
    unknown(command.text, c);
  }

  // What Teacup and Repetier do differently from Marlin's switch; false: Marlin's way.
  bool execute_other_dialect(const printer::GcodeCommand& c) {
    if (c.is('M', 116)) {
      // Wait for every heater with a target, in turn (Teacup's temp_achieved, Repetier's M116).
      motion.finish(now);
      done_at = now;
      for (const Heaters::Which which : {Heaters::Which::bed, Heaters::Which::hotend}) {
        const Heater& h = which == Heaters::Which::bed ? heaters.bed() : heaters.hotend();
        if (h.target() > 0) done_at = std::max(done_at, heaters.start_wait(which, false, now));
      }
      wait = Wait::hotend;
      next_wait_report = talk.reports_while_heating ? now + 1 : kInfinity;
      return true;
    }
    if (cfg.dialect != Dialect::teacup) return false;
    if (c.letter == 'G' && (c.code == 20 || c.code == 21)) return true;  // units: mm only here
    if (c.letter != 'M') return false;
    switch (c.code) {
      case 0:
      case 2:
      case 84:
        // Teacup's M0/M2/M84 (slic3r's end G-code): wait for the moves, heaters and motors off.
        done_at = motion.finish(now);
        wait = Wait::motion;
        heaters.set_hotend(0, now);
        heaters.set_bed(0);
        return true;
      case 105:
        say(teacup_temperatures(heaters.hotend().temperature(), heaters.bed().temperature()));
        return true;
      case 110:
        return true;  // "a no-op in Teacup": the line's own N set the count
      case 115:
        say(firmware_report(cfg.dialect, kVersion));
        return true;
      default:
        return false;
    }
  }

  void report_firmware() {
    say(firmware_report(cfg.dialect, kVersion));
    if (cfg.dialect != Dialect::marlin) return;
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
      emit(wait == Wait::user ? "echo:busy: paused for user" : "echo:busy: processing");
      next_busy = now + busy_interval;
    }
    if (executing && now >= next_wait_report) {
      if (wait == Wait::hotend) heating_report(Heaters::Which::hotend);
      if (wait == Wait::bed) heating_report(Heaters::Which::bed);
      next_wait_report = now + 1;
    }
    if (now >= next_autoreport) {
      emit(heaters.states());
      next_autoreport = now + autoreport_interval;
    }
    if (idle_wait_interval() > 0 && !executing && queue.empty() && !receiver.has_buffered() &&
        now >= last_activity + idle_wait_interval()) {
      emit("wait");
      last_activity = now;
    }
    if (state == PrinterState::running && idle() && idle_since < 0) idle_since = now;
  }

  // NO_TIMEOUTS' "wait"; Repetier says it each second by default (WAITING_IDENTIFIER).
  double idle_wait_interval() const {
    if (cfg.idle_wait_interval > 0) return cfg.idle_wait_interval;
    return talk.says_wait_when_idle ? 1.0 : 0.0;
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
    if (idle_wait_interval() > 0 && !executing && queue.empty()) {
      consider(last_activity + idle_wait_interval());
    }
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
