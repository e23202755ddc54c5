#include "sim/printer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <limits>
#include <numbers>
#include <optional>
#include <random>

#include <fmt/core.h>

#include "printer/gcode_line.h"
#include "sim/heater.h"
#include "sim/serial_line.h"

namespace sim {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr std::string_view kVersion = "2.0.9.3";

// A command in the queue: what the parser sees, and where it came from.
struct Queued {
  std::string text;
  std::optional<long> line_number;  // for ADVANCED_OK's "N<n>"
  std::uint64_t index = 0;          // 1-based count of accepted lines, for *-at-line faults
};

// Bytes on their way from the host: byte k of a chunk arrives at start + (k + 1) * byte_time.
struct Chunk {
  double start = 0;
  std::string bytes;
  std::size_t next = 0;
};

struct Reply {
  double at = 0;  // when its last byte reaches the host
  std::string text;
};

struct PendingEmergency {
  double at = 0;
  std::uint64_t byte = 0;  // sequence number of the byte that completes it
  Emergency kind = Emergency::none;
};

enum class Wait { none, planner, motion, hotend, bed, user };

}  // namespace

struct Printer::Firmware {
  Config cfg;
  double now = 0;
  PrinterState state = PrinterState::booting;
  std::string stop_reason;
  Counters counters;
  std::vector<std::string> log;
  DepositionRecord record;

  // One random stream per fault, so enabling one does not move another's pattern.
  std::mt19937_64 rng_corrupt, rng_drop, rng_dup, rng_resend;
  bool line_corrupted = false;  // this line (as it crosses the wire) already has its flip
  bool wire_line_start = true;  // the next non-blank byte on the wire starts a line
  bool disconnect_time_done = false;
  bool faults_armed = true;  // from-line: probabilistic faults wait for that line

  // Serial input.
  double byte_time = 0;
  std::deque<Chunk> wire;
  double wire_free = 0;
  std::uint64_t bytes_sent_on_wire = 0, bytes_off_wire = 0;  // sequence numbers
  std::deque<PendingEmergency> emergencies;
  EmergencyParser emergency_parser;
  std::string rx;            // the firmware's RX buffer
  bool rx_dropping = false;  // inside a run of lost bytes (one overflow)
  LineAssembler line;
  long last_n = 0;

  // Command queue; the front is the command executing, as in Marlin's ring buffer.
  std::deque<Queued> queue;
  bool executing = false;
  bool report_position_after = false;  // G28
  bool ok_with_temperatures = false;   // M105
  Wait wait = Wait::none;
  double done_at = 0;
  double next_busy = kInfinity;
  double next_wait_report = kInfinity;
  double residency_from = kInfinity;  // when the waited-for heater got within its window
  double last_activity = 0;           // for NO_TIMEOUTS' "wait"

  // Serial output.
  std::deque<Reply> out;
  double tx_free = 0;

  // Machine.
  printer::MotionModel motion;
  std::deque<double> open_moves;  // arrival time of each move still open in the planner
  double stepper_free = 0;        // when all moves made final so far have run
  Position pos;
  double motion_e = 0;            // filament actually fed (flow applied), the planner's E
  double feedrate = 25;           // mm/s (Marlin boots with 1500 mm/min)
  bool relative = false;
  enum class EMode { follow, absolute, relative } e_mode = EMode::follow;
  double feed_percent = 100, flow_percent = 100;
  int fan = 0;
  Heater hotend, bed;
  double autoreport_interval = 0, next_autoreport = kInfinity;
  double busy_interval = 2;
  double runaway_at = kInfinity;
  double boot_done = 0;

  explicit Firmware(Config config)
      : cfg(std::move(config)),
        rng_corrupt(cfg.faults.seed * 4 + 0),
        rng_drop(cfg.faults.seed * 4 + 1),
        rng_dup(cfg.faults.seed * 4 + 2),
        rng_resend(cfg.faults.seed * 4 + 3),
        motion(cfg.motion, static_cast<std::size_t>(std::max(cfg.planner_depth, 1))),
        line(cfg.max_cmd_size),
        hotend(cfg.hotend, cfg.ambient),
        bed(cfg.bed, cfg.ambient) {
    cfg.queue_depth = std::max(cfg.queue_depth, 1);
    cfg.planner_depth = std::max(cfg.planner_depth, 1);
    cfg.rx_buffer_size = std::max(cfg.rx_buffer_size, 1);
    cfg.max_cmd_size = std::max(cfg.max_cmd_size, 2);
    byte_time = cfg.baud > 0 ? 10.0 / cfg.baud : 0.0;
    power_on();
  }

  double chance(std::mt19937_64& rng) {
    return std::uniform_real_distribution<double>(0.0, 1.0)(rng);
  }

  // ---- power and reset -------------------------------------------------------------------

  void power_on() {
    ++counters.resets;
    state = PrinterState::booting;
    stop_reason.clear();
    boot_done = now + std::max(cfg.boot_time, 0.0);
    wire.clear();
    emergencies.clear();
    bytes_off_wire = bytes_sent_on_wire;
    emergency_parser = EmergencyParser{};
    wire_free = now;
    rx.clear();
    rx_dropping = false;
    line = LineAssembler(cfg.max_cmd_size);
    last_n = 0;
    faults_armed = !cfg.faults.from_line;
    queue.clear();
    executing = false;
    wait = Wait::none;
    next_busy = next_wait_report = residency_from = kInfinity;
    out.clear();
    tx_free = now;
    motion = printer::MotionModel(cfg.motion, static_cast<std::size_t>(cfg.planner_depth));
    open_moves.clear();
    stepper_free = now;
    pos = Position{};
    motion_e = 0;
    feedrate = 25;
    relative = false;
    e_mode = EMode::follow;
    feed_percent = flow_percent = 100;
    fan = 0;
    hotend = Heater(cfg.hotend, cfg.ambient);
    bed = Heater(cfg.bed, cfg.ambient);
    hotend.advance_to(now);
    bed.advance_to(now);
    autoreport_interval = 0;
    next_autoreport = kInfinity;
    busy_interval = cfg.busy_interval;
    runaway_at = kInfinity;
    last_activity = now;
    if (cfg.boot_time <= 0) finish_boot();
  }

  void finish_boot() {
    state = PrinterState::running;
    emit("start");
    emit(fmt::format("echo:Marlin {}", kVersion));
    emit("echo: Last Updated: 2021-12-25 | Author: (mahost simulated printer)");
    last_activity = now;
  }

  // ---- output ----------------------------------------------------------------------------

  void emit(std::string text) {
    if (state == PrinterState::disconnected) return;
    text += '\n';
    double at = now + (faults_armed ? cfg.faults.delay : 0.0);
    if (byte_time > 0) at = std::max(at, tx_free) + byte_time * static_cast<double>(text.size());
    if (!out.empty()) at = std::max(at, out.back().at);
    tx_free = at;
    counters.bytes_sent += text.size();
    out.push_back(Reply{at, std::move(text)});
  }

  bool output_ready() const { return !out.empty() && out.front().at <= now; }

  std::string take_output() {
    std::string text;
    while (output_ready()) {
      text += out.front().text;
      out.pop_front();
    }
    return text;
  }

  std::string heater_states() const {
    return fmt::format(" T:{:.2f} /{:.2f} B:{:.2f} /{:.2f} @:{} B@:{}", hotend.temperature(),
                       hotend.target(), bed.temperature(), bed.target(), hotend.power(),
                       bed.power());
  }

  // The ok of an executed command; M105's carries the temperatures instead of ADVANCED_OK's
  // fields, since Marlin's M105 prints its own ok.
  void send_ok(const Queued& command, bool with_temperatures) {
    if (faults_armed && cfg.faults.drop_ok > 0 && chance(rng_drop) < cfg.faults.drop_ok) {
      ++counters.faults_injected;
      return;
    }
    std::string ok = "ok";
    if (with_temperatures) {
      ok += heater_states();
    } else if (cfg.advanced_ok) {
      if (command.line_number) ok += fmt::format(" N{}", *command.line_number);
      ok += fmt::format(" P{} B{}", planner_free(), cfg.queue_depth - static_cast<int>(queue.size()));
    }
    const bool twice = faults_armed && cfg.faults.dup_ok > 0 && chance(rng_dup) < cfg.faults.dup_ok;
    emit(ok);
    if (twice) {
      ++counters.faults_injected;
      emit(ok);
    }
  }

  int planner_free() const {
    return std::max(0, cfg.planner_depth - static_cast<int>(motion.pending()));
  }

  // ---- serial input ----------------------------------------------------------------------

  // One bit flipped in `c` that Marlin's checksum is sure to catch (sim/faults.h), or c.
  char corrupt(char c) {
    std::uniform_int_distribution<int> bit(0, 7);
    for (int attempt = 0; attempt < 16; ++attempt) {
      const char flipped = static_cast<char>(c ^ (1 << bit(rng_corrupt)));
      if (is_line_end(flipped) || flipped == ';' || flipped == '*' || flipped == '\b' ||
          flipped == '\0' || flipped == '\\' || flipped == 'N' || flipped == 'n') {
        continue;
      }
      return flipped;
    }
    return c;
  }

  void receive(std::string_view bytes) {
    if (state == PrinterState::disconnected || bytes.empty()) return;
    Chunk chunk;
    chunk.start = std::max(now, wire_free);
    chunk.bytes.assign(bytes);
    for (std::size_t k = 0; k < chunk.bytes.size(); ++k) {
      char& c = chunk.bytes[k];
      const bool eol = is_line_end(c);
      const bool protected_byte = eol || c == ';' || c == '*' || c == '\b' || c == '\0' ||
                                  c == '\\' || (wire_line_start && (c == 'N' || c == 'n'));
      if (faults_armed && cfg.faults.corrupt > 0 && !line_corrupted && !protected_byte &&
          chance(rng_corrupt) < cfg.faults.corrupt) {
        const char flipped = corrupt(c);
        if (flipped != c) {
          c = flipped;
          line_corrupted = true;
          ++counters.faults_injected;
        }
      }
      if (eol) {
        line_corrupted = false;
        wire_line_start = true;
      } else if (c != ' ') {
        wire_line_start = false;
      }
      if (cfg.emergency_parser) {
        const Emergency e = emergency_parser.update(c);
        if (e != Emergency::none) {
          emergencies.push_back(
              {chunk.start + byte_time * static_cast<double>(k + 1), bytes_sent_on_wire + k, e});
        }
      }
    }
    wire_free = chunk.start + byte_time * static_cast<double>(chunk.bytes.size());
    bytes_sent_on_wire += chunk.bytes.size();
    wire.push_back(std::move(chunk));
  }

  bool queue_full() const { return static_cast<int>(queue.size()) >= cfg.queue_depth; }

  // Bytes that have arrived by now go to the firmware: read at once while the queue has
  // room (Marlin's loop keeps up), else into the RX buffer, else lost. The byte that
  // completes an emergency command acts as it arrives; bytes that arrived in the same instant
  // before it are read and their commands run first, so that a stream arriving at once keeps
  // its order. Returns true when it stopped at such a byte (there is more to deliver now).
  bool deliver() {
    std::size_t delivered = 0;
    while (!wire.empty()) {
      Chunk& chunk = wire.front();
      std::size_t arrived = chunk.bytes.size();
      if (byte_time > 0) {
        const double n = std::floor((now - chunk.start) / byte_time + 1e-9);
        arrived = n <= 0 ? 0 : std::min(chunk.bytes.size(), static_cast<std::size_t>(n));
      }
      while (chunk.next < arrived) {
        const bool trigger = !emergencies.empty() && emergencies.front().byte == bytes_off_wire;
        if (trigger && delivered > 0) return true;
        arrive(chunk.bytes[chunk.next++]);
        if (wire.empty()) return false;  // the line it ended disconnected the link
        ++bytes_off_wire;
        ++delivered;
        if (trigger) {
          const Emergency e = emergencies.front().kind;
          emergencies.pop_front();
          if (state == PrinterState::running) emergency(e);
          if (wire.empty()) return false;  // a kill or disconnect dropped the rest
        }
      }
      if (chunk.next < chunk.bytes.size()) break;
      wire.pop_front();
    }
    return false;
  }

  void arrive(char c) {
    if (state == PrinterState::booting || state == PrinterState::halted) return;
    if (rx.empty() && !queue_full() && state == PrinterState::running) {
      ++counters.bytes_received;
      read_char(c);
      return;
    }
    if (static_cast<int>(rx.size()) < cfg.rx_buffer_size) {
      ++counters.bytes_received;
      rx += c;
      rx_dropping = false;
      return;
    }
    if (!rx_dropping) ++counters.overflows;
    rx_dropping = true;
    ++counters.overflow_bytes;
  }

  // Reads the RX buffer while the queue has room.
  void read_rx() {
    std::size_t used = 0;
    while (used < rx.size() && !queue_full() && state == PrinterState::running) {
      const char c = rx[used++];
      if (read_char(c)) used = 0;  // a line error emptied the buffer
    }
    rx.erase(0, std::min(used, rx.size()));
  }

  // Marlin's get_serial_commands for one character. Returns true when a line error
  // discarded the RX buffer.
  bool read_char(char c) {
    if (!is_line_end(c)) {
      const bool was_cut = line.cut();
      line.feed(c);
      if (line.cut() && !was_cut) ++counters.long_lines;
      return false;
    }
    const std::string raw = line.take();
    if (raw.empty()) return false;
    return line_done(raw);
  }

  bool line_done(const std::string& raw) {
    const LineCheck check = check_line(raw, last_n);
    std::optional<long> number;
    if (check.verdict != LineVerdict::unnumbered) {
      if (check.verdict != LineVerdict::accepted) return line_error(error_text(check.verdict));
      if (faults_armed && cfg.faults.resend > 0 && chance(rng_resend) < cfg.faults.resend) {
        ++counters.faults_injected;
        return line_error(error_text(LineVerdict::checksum_mismatch));
      }
      last_n = check.number;
      number = check.number;
      if (cfg.faults.from_line && check.number >= *cfg.faults.from_line) faults_armed = true;
    }

    Queued queued{command_text(raw), number, ++counters.lines};
    if (!cfg.emergency_parser && !number) {
      // queue.cpp's early check of unnumbered lines.
      if (queued.text.starts_with("M108")) emergency(Emergency::m108);
      if (queued.text.starts_with("M112")) emergency(Emergency::m112);
      if (queued.text.starts_with("M410")) emergency(Emergency::m410);
      if (state != PrinterState::running) return false;
    }
    last_activity = now;
    queue.push_back(std::move(queued));
    if (cfg.faults.disconnect_at_line && counters.lines == *cfg.faults.disconnect_at_line) {
      disconnect(fmt::format("disconnected at line {} (fault disconnect-at-line)", counters.lines));
    }
    return false;
  }

  // gcode_line_error + flush_and_request_resend.
  bool line_error(std::string_view what) {
    ++counters.errors;
    ++counters.resends;
    emit(fmt::format("Error:{}{}", what, last_n));
    rx.clear();
    rx_dropping = false;
    emit(fmt::format("Resend: {}", last_n + 1));
    if (cfg.ok_after_resend) emit("ok");
    return true;
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
        quickstop();
        break;
      case Emergency::none:
        break;
    }
  }

  // ---- faults and stops ------------------------------------------------------------------

  void kill(std::string reason) {
    hotend.set_target(0);
    bed.set_target(0);
    emit("Error:Printer halted. kill() called!");
    if (state != PrinterState::disconnected) state = PrinterState::halted;
    stop_reason = std::move(reason);
    queue.clear();
    executing = false;
    wait = Wait::none;
    rx.clear();
    line.take();
    next_busy = next_wait_report = next_autoreport = runaway_at = kInfinity;
    quickstop();
  }

  void disconnect(std::string reason) {
    ++counters.faults_injected;
    state = PrinterState::disconnected;
    stop_reason = std::move(reason);
    wire.clear();
    emergencies.clear();
    bytes_off_wire = bytes_sent_on_wire;
    rx.clear();
    out.clear();
  }

  void update_runaway() {
    // Thermal protection: a failed heater that stays `hysteresis` below its target for
    // `period` seconds stops the printer.
    runaway_at = kInfinity;
    if (!hotend.failed() || hotend.target() <= cfg.ambient) return;
    const double below = hotend.target() - cfg.runaway_hysteresis;
    const double from = hotend.temperature() < below ? now : hotend.time_reaching(below);
    runaway_at = from + cfg.runaway_period;
  }

  void thermal_runaway() {
    stop_reason = "thermal runaway (fault runaway-at-line)";
    emit("Error:Thermal Runaway, system stopped! Heater_ID: 0");
    kill("thermal runaway (fault runaway-at-line)");
  }

  // ---- motion ----------------------------------------------------------------------------

  // Queues a move in the planner; returns when it could enter (a slot was free).
  double plan_move(printer::AxisPosition target, double speed) {
    const printer::AxisPosition from = motion.position();
    const bool moves = target.x != from.x || target.y != from.y || target.z != from.z ||
                       target.e != from.e;
    const std::size_t before = motion.pending();
    const double seconds = motion.push(target, speed);
    const std::size_t opened = before + (moves ? 1 : 0);
    const std::size_t finalized = opened > motion.pending() ? opened - motion.pending() : 0;
    if (moves) open_moves.push_back(now);
    if (finalized == 0) return now;
    const double start = std::max(stepper_free, open_moves.front());
    for (std::size_t i = 0; i < finalized && !open_moves.empty(); ++i) open_moves.pop_front();
    stepper_free = start + seconds;
    return std::max(now, stepper_free);
  }

  // planner.synchronize(): every queued move runs out. Returns when the last one ends.
  double finish_motion() {
    const double seconds = motion.flush();
    if (!open_moves.empty()) {
      const double start = std::max(stepper_free, open_moves.front());
      stepper_free = std::max(start + seconds, open_moves.back());
      open_moves.clear();
    }
    return std::max(now, stepper_free);
  }

  void quickstop() {
    // The sim cannot say where inside a move the head stopped: queued moves are dropped
    // from the clock and the position stays where the last command put it.
    motion.flush();
    open_moves.clear();
    stepper_free = std::min(stepper_free, now);
    motion.set_position({pos.x, pos.y, pos.z, motion_e});
  }

  bool e_relative() const {
    if (e_mode == EMode::relative) return true;
    if (e_mode == EMode::absolute) return false;
    return relative;
  }

  // Where a G0-G3 goes, in the current modes; F sets the feedrate.
  Position destination(const printer::GcodeCommand& c) {
    Position target = pos;
    if (auto v = c.get('X')) target.x = relative ? pos.x + *v : *v;
    if (auto v = c.get('Y')) target.y = relative ? pos.y + *v : *v;
    if (auto v = c.get('Z')) target.z = relative ? pos.z + *v : *v;
    if (auto v = c.get('E')) target.e = e_relative() ? pos.e + *v : *v;
    if (auto f = c.get('F'); f && *f > 0) feedrate = *f / 60.0;
    return target;
  }

  // One straight move: recorded if it extrudes, queued in the planner. Returns when it
  // entered the planner.
  double line_to(const Position& target) {
    const double speed = feedrate * feed_percent / 100.0;
    const double fed = (target.e - pos.e) * flow_percent / 100.0;
    const geometry::Vec2 start{pos.x, pos.y}, end{target.x, target.y};
    pos = target;
    motion_e += fed;
    if (fed > 0 && !(start == end)) record.add(target.z, start, end, fed, speed);
    return plan_move({pos.x, pos.y, pos.z, motion_e}, speed);
  }

  double move(const printer::GcodeCommand& c) { return line_to(destination(c)); }

  // G2 (clockwise) / G3: an arc in XY about the centre at I, J from the start (or of radius
  // R), Z and E spread along it, cut into 1 mm segments (Marlin's plan_arc with
  // MM_PER_ARC_SEGMENT 1). A start equal to the end with I/J is a full circle.
  double arc(const printer::GcodeCommand& c, bool clockwise) {
    const Position start = pos;
    const Position target = destination(c);
    double i = c.get('I').value_or(0), j = c.get('J').value_or(0);
    if (auto r = c.get('R'); r && *r != 0 && (target.x != start.x || target.y != start.y)) {
      const double e = (clockwise != (*r < 0)) ? -1 : 1;
      const double dx = target.x - start.x, dy = target.y - start.y, d = std::hypot(dx, dy);
      const double h2 = (*r - 0.5 * d) * (*r + 0.5 * d), h = h2 >= 0 ? std::sqrt(h2) : 0.0;
      const double cx = (start.x + target.x) / 2 + e * h * -dy / d;
      const double cy = (start.y + target.y) / 2 + e * h * dx / d;
      i = cx - start.x;
      j = cy - start.y;
    }
    const double cx = start.x + i, cy = start.y + j;
    const double radius = std::hypot(i, j);
    const double ax = -i, ay = -j;  // centre to start
    const double bx = target.x - cx, by = target.y - cy;
    double angle = std::atan2(ax * by - ay * bx, ax * bx + ay * by);
    if (angle < 0) angle += 2 * std::numbers::pi;
    if (clockwise) angle -= 2 * std::numbers::pi;
    if (angle == 0 && start.x == target.x && start.y == target.y && radius > 0) {
      angle = clockwise ? -2 * std::numbers::pi : 2 * std::numbers::pi;
    }
    const double flat = radius * std::abs(angle), rise = target.z - start.z;
    const double travel = std::hypot(flat, rise);
    if (!(radius > 0) || travel < 0.001) return line_to(target);
    const int segments = std::max(1, static_cast<int>(std::floor(travel / 1.0)));
    double entered = now;
    for (int k = 1; k <= segments; ++k) {
      Position p = target;
      if (k < segments) {
        const double share = static_cast<double>(k) / segments, turn = angle * share;
        p.x = cx + ax * std::cos(turn) - ay * std::sin(turn);
        p.y = cy + ax * std::sin(turn) + ay * std::cos(turn);
        p.z = start.z + rise * share;
        p.e = start.e + (target.e - start.e) * share;
      }
      entered = std::max(entered, line_to(p));
    }
    return entered;
  }

  double home(const printer::GcodeCommand& c) {
    finish_motion();
    const bool all = !c.has('X') && !c.has('Y') && !c.has('Z');
    printer::AxisPosition at{pos.x, pos.y, pos.z, motion_e};
    motion.set_position(at);
    double seconds = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (!all && !c.has("XYZ"[axis])) continue;
      double* coordinate = axis == 0 ? &at.x : axis == 1 ? &at.y : &at.z;
      const double speed = cfg.homing_feedrate[axis];
      const double bump = cfg.homing_bump[axis];
      *coordinate = 0;  // to the endstop at 0
      seconds += motion.push(at, speed);
      *coordinate = bump;  // back off
      seconds += motion.push(at, speed);
      *coordinate = 0;  // and touch again, slower
      seconds += motion.push(at, speed / (axis == 2 ? 4 : 2));
      seconds += motion.flush();
      (axis == 0 ? pos.x : axis == 1 ? pos.y : pos.z) = 0;
    }
    stepper_free = std::max(stepper_free, now) + seconds;
    return stepper_free;
  }

  void set_position(const printer::GcodeCommand& c) {
    if (auto v = c.get('X')) pos.x = *v;
    if (auto v = c.get('Y')) pos.y = *v;
    if (auto v = c.get('Z')) pos.z = *v;
    if (auto v = c.get('E')) pos.e = *v;
    motion.set_position({pos.x, pos.y, pos.z, motion_e});
  }

  std::string position_report() const {
    return fmt::format("X:{:.2f} Y:{:.2f} Z:{:.2f} E:{:.2f} Count X:{} Y:{} Z:{}", pos.x, pos.y,
                       pos.z, pos.e, std::lround(pos.x * cfg.steps_per_mm[0]),
                       std::lround(pos.y * cfg.steps_per_mm[1]),
                       std::lround(pos.z * cfg.steps_per_mm[2]));
  }

  // ---- heaters ---------------------------------------------------------------------------

  void set_hotend(double target) {
    hotend.set_target(std::clamp(target, 0.0, cfg.max_hotend_temp));
    update_runaway();
  }
  void set_bed(double target) { bed.set_target(std::clamp(target, 0.0, cfg.max_bed_temp)); }

  // M109/M190: wait_for_hotend / wait_for_bed. Reports at once and every second; done when
  // within the window for the residency time and at the target.
  double heat_wait(Heater& heater, const HeaterConstants& constants, bool wait_for_cooling) {
    emit_wait_report(constants);
    next_wait_report = now + 1;
    const double target = heater.target();
    const bool cooling = heater.temperature() > target;
    if (cooling && !wait_for_cooling) return now;
    if (std::abs(heater.temperature() - target) <= constants.window) {
      residency_from = now;
    } else {
      residency_from = heater.time_reaching(cooling ? target + constants.window
                                                    : target - constants.window);
    }
    const double at_target = heater.time_reaching(target);
    return std::max(at_target, residency_from + constants.residency);
  }

  void emit_wait_report(const HeaterConstants& constants) {
    std::string w = "?";
    if (residency_from <= now) {
      const long left_ms = std::lround((constants.residency - (now - residency_from)) * 1000);
      w = fmt::format("{}", left_ms / 1000);
    }
    emit(heater_states() + " W:" + w);
  }

  // ---- commands --------------------------------------------------------------------------

  void start_next() {
    Queued& command = queue.front();
    if (cfg.faults.halt_at_line && command.index == *cfg.faults.halt_at_line) {
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
    next_busy = busy_interval > 0 ? now + busy_interval : kInfinity;
    if (cfg.faults.runaway_at_line && command.index == *cfg.faults.runaway_at_line) {
      ++counters.faults_injected;
      hotend.fail();
      update_runaway();
    }
    execute(command);
  }

  void complete() {
    executing = false;
    wait = Wait::none;
    next_busy = next_wait_report = residency_from = kInfinity;
    last_activity = now;
    if (report_position_after) emit(position_report());  // G28 ends with it
    send_ok(queue.front(), ok_with_temperatures);
    queue.pop_front();
  }

  void unknown(const std::string& text) {
    ++counters.unknown_commands;
    emit(fmt::format("echo:Unknown command: \"{}\"", text));
  }

  void execute(const Queued& command) {
    const printer::GcodeCommand c = printer::parse_gcode_line(command.text);
    if (c.letter == 'G') {
      switch (c.code) {
        case 0:
        case 1:
        case 2:
        case 3: {
          done_at = c.code <= 1 ? move(c) : arc(c, c.code == 2);
          if (done_at > now) wait = Wait::planner;
          return;
        }
        case 4: {
          double dwell = 0;
          if (auto p = c.get('P')) dwell = *p / 1000.0;
          if (auto s = c.get('S')) dwell = *s;
          done_at = finish_motion() + std::max(dwell, 0.0);
          wait = Wait::motion;
          return;
        }
        case 28:
          done_at = home(c);
          wait = Wait::motion;
          report_position_after = true;
          return;
        case 90: relative = false; e_mode = EMode::follow; return;
        case 91: relative = true; e_mode = EMode::follow; return;
        case 92: set_position(c); return;
        default: break;
      }
    } else if (c.letter == 'M') {
      switch (c.code) {
        case 0:
        case 1: {
          double limit = kInfinity;
          if (auto p = c.get('P')) limit = *p / 1000.0;
          if (auto s = c.get('S')) limit = *s;
          done_at = finish_motion() + limit;
          wait = Wait::user;
          return;
        }
        case 17: case 73: case 75: case 76: case 77: case 111: case 117: case 300:
          return;
        case 18:
        case 84:
          if (!c.has('S')) {
            done_at = finish_motion();
            wait = Wait::motion;
          }
          return;
        case 82: e_mode = EMode::absolute; return;
        case 83: e_mode = EMode::relative; return;
        case 104:
          if (auto s = c.get('S')) set_hotend(*s);
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
          hot ? set_hotend(s ? *s : *r) : set_bed(s ? *s : *r);
          // The planner runs dry while the firmware waits: later moves start from rest.
          finish_motion();
          done_at = hot ? heat_wait(hotend, cfg.hotend, !s) : heat_wait(bed, cfg.bed, !s);
          wait = hot ? Wait::hotend : Wait::bed;
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
          emit(position_report());
          return;
        case 115:
          report_firmware();
          return;
        case 140:
          if (auto s = c.get('S')) set_bed(*s);
          return;
        case 155:
          if (auto s = c.get('S')) {
            autoreport_interval = std::clamp(*s, 0.0, 60.0);
            next_autoreport = autoreport_interval > 0 ? now + autoreport_interval : kInfinity;
          }
          return;
        case 201: case 203: case 204: case 205:
          set_limits(c);
          return;
        case 220:
          if (auto s = c.get('S')) feed_percent = std::max(*s, 1.0);
          return;
        case 221:
          if (auto s = c.get('S')) flow_percent = std::max(*s, 0.0);
          return;
        case 400:
          done_at = finish_motion();
          wait = Wait::motion;
          return;
        case 410:
          quickstop();
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
    unknown(command.text);
  }

  void set_limits(const printer::GcodeCommand& c) {
    printer::MotionLimits limits = motion.limits();
    constexpr std::string_view axes = "XYZE";
    for (int axis = 0; axis < 4; ++axis) {
      const auto v = c.get(axes[axis]);
      if (!v || *v <= 0) continue;
      if (c.code == 201) limits.max_acceleration[axis] = *v;
      if (c.code == 203) limits.max_speed[axis] = *v;
    }
    if (c.code == 204) {
      if (auto s = c.get('S'); s && *s > 0) limits.print_acceleration = limits.travel_acceleration = *s;
      if (auto p = c.get('P'); p && *p > 0) limits.print_acceleration = *p;
      if (auto r = c.get('R'); r && *r > 0) limits.retract_acceleration = *r;
      if (auto t = c.get('T'); t && *t > 0) limits.travel_acceleration = *t;
    }
    if (c.code == 205) {
      if (auto j = c.get('J'); j && *j > 0) limits.junction_deviation = *j;
      if (auto s = c.get('S'); s && *s >= 0) limits.min_feedrate = *s;
    }
    motion.set_limits(limits);
  }

  void report_firmware() {
    emit(fmt::format(
        "FIRMWARE_NAME:Marlin {} (mahost simulated printer) "
        "SOURCE_CODE_URL:github.com/MarlinFirmware/Marlin PROTOCOL_VERSION:1.0 "
        "MACHINE_TYPE:mahost sim EXTRUDER_COUNT:1 UUID:cede2a2f-41a2-4748-9b12-c55c62f367ff",
        kVersion));
    const std::pair<std::string_view, bool> caps[] = {
        {"SERIAL_XON_XOFF", false},   {"BINARY_FILE_TRANSFER", false},
        {"EEPROM", false},            {"VOLUMETRIC", false},
        {"AUTOREPORT_TEMP", true},    {"PROGRESS", false},
        {"PRINT_JOB", true},          {"AUTOLEVEL", false},
        {"RUNOUT", false},            {"Z_PROBE", false},
        {"LEVELING_DATA", false},     {"BUILD_PERCENT", true},
        {"SOFTWARE_POWER", false},    {"TOGGLE_LIGHTS", false},
        {"CASE_LIGHT_BRIGHTNESS", false}, {"EMERGENCY_PARSER", cfg.emergency_parser},
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
    hotend.advance_to(now);
    bed.advance_to(now);
  }

  // Does everything due at `now`.
  void settle() {
    if (state == PrinterState::booting && now >= boot_done) {
      deliver();  // input during boot is lost
      finish_boot();
    }
    if (cfg.faults.disconnect_at_time && !disconnect_time_done &&
        now >= *cfg.faults.disconnect_at_time) {
      disconnect_time_done = true;
      if (state != PrinterState::disconnected) {
        disconnect(fmt::format("disconnected at {:g} s (fault disconnect-at-time)",
                               *cfg.faults.disconnect_at_time));
      }
    }
    if (now >= runaway_at && state != PrinterState::halted) thermal_runaway();
    for (bool progress = true; progress;) {
      progress = deliver();
      if (state != PrinterState::running && state != PrinterState::disconnected) {
        rx.clear();
        return;
      }
      if (!rx.empty() && !queue_full()) read_rx();
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
      if (wait == Wait::hotend) emit_wait_report(cfg.hotend);
      if (wait == Wait::bed) emit_wait_report(cfg.bed);
      next_wait_report = now + 1;
    }
    if (now >= next_autoreport) {
      emit(heater_states());
      next_autoreport = now + autoreport_interval;
    }
    if (cfg.idle_wait_interval > 0 && !executing && queue.empty() && rx.empty() &&
        now >= last_activity + cfg.idle_wait_interval) {
      emit("wait");
      last_activity = now;
    }
  }

  // Arrival of the next line end on the wire (when the firmware would read it).
  double next_line_end() const {
    for (const Chunk& chunk : wire) {
      for (std::size_t k = chunk.next; k < chunk.bytes.size(); ++k) {
        if (is_line_end(chunk.bytes[k])) return chunk.start + byte_time * static_cast<double>(k + 1);
      }
    }
    return kInfinity;
  }

  // The next time after now at which the firmware does something on its own. settle() has
  // done everything due at now, so only later times count.
  double next_event() const {
    double next = kInfinity;
    const auto consider = [&](double t) {
      if (t > now && t < next) next = t;
    };
    if (!out.empty()) consider(out.front().at);
    if (cfg.faults.disconnect_at_time && !disconnect_time_done) {
      consider(*cfg.faults.disconnect_at_time);
    }
    if (state == PrinterState::booting) {
      consider(boot_done);
      return next;
    }
    if (state == PrinterState::halted) return next;
    if (!emergencies.empty()) consider(emergencies.front().at);
    if (!queue_full() && state == PrinterState::running) {
      // Bytes just received are due now (settle() has read everything that came before).
      const double line_end = std::max(next_line_end(), now);
      if (line_end < next) next = line_end;
    }
    if (executing) {
      consider(done_at);
      consider(next_busy);
      consider(next_wait_report);
    }
    consider(next_autoreport);
    consider(runaway_at);
    if (cfg.idle_wait_interval > 0 && !executing && queue.empty()) {
      consider(last_activity + cfg.idle_wait_interval);
    }
    return next;
  }

  bool run(double until, bool stop_on_output) {
    for (;;) {
      settle();
      if (stop_on_output && output_ready()) return true;
      const double next = next_event();
      if (next > until || next == kInfinity) {
        advance_clock(until);
        settle();
        return output_ready();
      }
      advance_clock(next);
    }
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

std::string Printer::take_output() { return firmware_->take_output(); }

void Printer::reset() { firmware_->power_on(); }

void Printer::reconnect() {
  if (firmware_->state == PrinterState::disconnected) firmware_->state = PrinterState::running;
  firmware_->power_on();
}

double Printer::now() const { return firmware_->now; }
double Printer::next_event_time() const {
  const double next = firmware_->next_event();
  return next;
}
PrinterState Printer::state() const { return firmware_->state; }
bool Printer::idle() const {
  const Firmware& f = *firmware_;
  return !f.executing && f.queue.empty() && f.rx.empty() && f.emergencies.empty() &&
         f.next_line_end() == std::numeric_limits<double>::infinity();
}
const std::string& Printer::stop_reason() const { return firmware_->stop_reason; }
const std::vector<std::string>& Printer::executed_commands() const { return firmware_->log; }
const DepositionRecord& Printer::deposition() const { return firmware_->record; }
const Counters& Printer::counters() const { return firmware_->counters; }
const Config& Printer::config() const { return firmware_->cfg; }
double Printer::motion_time() const { return firmware_->motion.total_time(); }
double Printer::motion_end_time() const { return firmware_->stepper_free; }
void Printer::finish() { firmware_->finish_motion(); }

Printer::Position Printer::position() const { return firmware_->pos; }
double Printer::hotend_temperature() const { return firmware_->hotend.temperature(); }
double Printer::bed_temperature() const { return firmware_->bed.temperature(); }
double Printer::hotend_target() const { return firmware_->hotend.target(); }
double Printer::bed_target() const { return firmware_->bed.target(); }

}  // namespace sim
