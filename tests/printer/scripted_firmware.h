// A scripted Marlin-style firmware behind printer::Link, for unit tests of the host's protocol
// engine: each test names the lines to corrupt, the oks to lose, when to halt or fall silent,
// and reads back what the firmware executed. Replies are Marlin 2.x's literal strings; the
// clock is simulated (read(timeout) advances it), so timeouts cost no wall time.
//
// It is deliberately small and independent of sim/ (the full simulated printer): a test of the
// engine must not pass because the engine and the simulator share a misreading of the protocol.
#pragma once

#include <chrono>
#include <deque>
#include <set>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "printer/error.h"
#include "printer/gcode_line.h"
#include "printer/link.h"

namespace test_support {

class ScriptedFirmware : public printer::Link {
 public:
  // Behaviour.
  bool advanced_ok = false;      // ok N<n> P<p> B<b>
  bool ok_after_resend = true;   // Marlin 2 prints ok after Resend:; older firmware does not
  bool reject_duplicates = true; // false: drop lines last_N-1..last_N silently (Marlin 2.1)
  int queue_free = 3;            // B in ADVANCED_OK replies
  std::chrono::milliseconds busy_interval{0};  // 0: busy keepalive off
  std::chrono::milliseconds heat_time{60000};  // how long M109/M190 block
  std::chrono::milliseconds home_time{0};      // how long G28 blocks
  std::string firmware_name = "ScriptedFirmware";  // in M115's reply; "" names none
  bool temperatures_before_ok = false;  // M105: "T:..." on a line of its own, then "ok"
  bool accepts_skipped_numbers = false; // Teacup's REQUIRE_LINENUMBER: any N from last_N + 1 up
  bool ignores_line_numbers = false;    // Teacup's default: N never looked at (a checksum is)
  bool resend_as_rs = false;            // Teacup: "rs N<n>" instead of Error: + Resend:
  std::set<std::string> refuse;         // command words it does not know ("M190")
  std::chrono::milliseconds chatter{0};  // a temperature line this often, whatever happens
  bool wait_when_idle = false;          // "wait" 1 s after it ran out of work
  // Time each reply byte takes on the wire (87 us at 115200 baud): a reply line leaves once the
  // one before it is out, so the lines of one answer come in separate reads. 0: all at once.
  std::chrono::nanoseconds byte_time{0};

  // Faults, by line number (first reception of that line only, except where said).
  std::set<long> corrupt;        // seen with a bad checksum
  std::set<std::size_t> corrupt_writes;  // by place in `received` (0: the host's first line)
  std::set<long> lose;           // never arrives (no reply at all)
  std::set<long> drop_ok;        // accepted, its ok lost
  std::set<long> duplicate_ok;   // accepted, ok sent twice
  std::set<long> resend_after_accept;  // accepted and executed, then "Resend: n" anyway
  std::set<long> reject_always;  // every copy corrupted (a resend loop)
  std::set<long> drop_ok_of_blocking;  // by line number, the ok of that (blocking) line lost
  long halt_at = -1;             // Error:Printer halted at this line
  long silent_after = -1;        // no reply to anything after this line
  long restart_at = -1;          // the board resets at this line (prints start)
  bool mute = false;             // never answers anything
  bool noise = false;            // answers every line with bytes that are not text (wrong baud)

  // Record.
  std::vector<std::string> executed;   // commands accepted, in order
  std::vector<std::string> received;   // every line as written by the host
  long bad_frames = 0;                 // host lines whose checksum is wrong (refused)
  long max_ahead = 0;                  // most numbered lines received beyond the last ok read
  long last_n = 0;

  // `start_banner`: print `start` when the link opens, as a board that resets does;
  // `banner_ok`: and an ok after it, as Teacup does (mendel.c).
  explicit ScriptedFirmware(bool start_banner = true, bool banner_ok = false) {
    if (start_banner) emit(now_, "start");
    if (start_banner && banner_ok) emit(now_, "ok");
  }

  void write(std::string_view bytes) override {
    if (closed_) throw printer::LinkError("fake printer: gone");
    input_ += bytes;
    std::size_t end;
    while ((end = input_.find('\n')) != std::string::npos) {
      const std::string text = input_.substr(0, end);
      input_.erase(0, end + 1);
      receive(text);
    }
  }

  std::string read(std::chrono::milliseconds timeout) override {
    if (closed_) throw printer::LinkError("fake printer: gone");
    const auto until = now_ + std::chrono::nanoseconds(timeout);
    if (chatter.count() > 0) {
      while (next_chatter_ <= until) {
        emit(next_chatter_, " T:210.00 /210.00 B:60.00 /60.00 @:0 B@:0");
        next_chatter_ += std::chrono::nanoseconds(chatter);
      }
    }
    if (output_.empty() || output_.front().at > until) {
      now_ = until;
      return {};
    }
    now_ = std::max(now_, output_.front().at);
    std::string bytes;
    while (!output_.empty() && output_.front().at <= now_) {
      bytes += output_.front().text + "\n";
      if (output_.front().ok_for > delivered_ok_) delivered_ok_ = output_.front().ok_for;
      output_.pop_front();
    }
    return bytes;
  }

  std::chrono::nanoseconds now() const override { return now_; }
  std::string name() const override { return "fake printer"; }

  void close() { closed_ = true; }

 private:
  struct Output {
    std::chrono::nanoseconds at;
    std::string text;
    long ok_for = 0;
  };

  void emit(std::chrono::nanoseconds at, std::string text, long ok_for = 0) {
    // Replies leave in order: never before one already queued, and each after its bytes.
    if (!output_.empty() && output_.back().at > at) at = output_.back().at;
    at += static_cast<long>(text.size() + 1) * byte_time;
    output_.push_back({at, std::move(text), ok_for});
  }

  std::string ok_text() const {
    return advanced_ok ? fmt::format("ok N{} P15 B{}", last_n, queue_free) : "ok";
  }

  void reject(std::chrono::nanoseconds at, std::string_view error) {
    if (resend_as_rs) {
      emit(at, fmt::format("rs N{} Expected line number {}", last_n + 1, last_n + 1));
      if (ok_after_resend) emit(at, ok_text());
      return;
    }
    emit(at, fmt::format("Error:{}, Last Line: {}", error, last_n));
    emit(at, fmt::format("Resend: {}", last_n + 1));
    if (ok_after_resend) emit(at, ok_text());
  }

  void receive(const std::string& text) {
    received.push_back(text);
    if (halted_ || silent_ || mute) return;
    if (noise) {
      emit(now_, "\x93\xfe\x11x\xc4\x80\xff\x02");
      return;
    }
    const printer::NumberedLine line = printer::parse_numbered_line(text);
    const auto at = std::max(now_, busy_until_);
    if (line.line_number && !line.checksum_ok) ++bad_frames;
    if (line.command.starts_with("M112")) {  // the emergency parser acts at once: kill()
      halted_ = true;
      output_.clear();
      emit(now_, "Error:Printer halted. kill() called!");
      return;
    }
    if (line.line_number) {
      const long n = *line.line_number;
      max_ahead = std::max(max_ahead, n - delivered_ok_);
      const bool first = seen_.insert(n).second;
      if (first && lose.count(n)) return;
      if (reject_always.count(n) || (first && corrupt.count(n)) || corrupt_writes.count(received.size() - 1)) {
        reject(at, "checksum mismatch");
        return;
      }
      const bool m110 = line.command.starts_with("M110");
      const bool in_sequence = ignores_line_numbers ||
                               (accepts_skipped_numbers ? n >= last_n + 1 : n == last_n + 1);
      if (!m110 && !in_sequence) {
        if (!reject_duplicates && n >= last_n - 1 && n <= last_n) return;
        reject(at, "Line Number is not Last Line Number+1");
        return;
      }
      if (!line.checksum_ok) {
        reject(at, "checksum mismatch");
        return;
      }
      if (m110) {
        const printer::GcodeCommand c = printer::parse_gcode_line(line.command);
        last_n = static_cast<long>(c.get('N').value_or(static_cast<double>(n)));
      } else {
        last_n = n;
      }
      if (first && n == restart_at) {
        last_n = 0;
        emit(at, "start");
        return;
      }
      if (first && n == halt_at) {
        halted_ = true;
        emit(at, "Error:Printer halted. kill() called!");
        return;
      }
      execute(line.command, at, first && (drop_ok.count(n) || drop_ok_of_blocking.count(n)),
              first && duplicate_ok.count(n));
      if (first && resend_after_accept.count(n)) {
        emit(busy_until_, fmt::format("Resend: {}", n));
        if (ok_after_resend) emit(busy_until_, ok_text());
      }
      if (n == silent_after) silent_ = true;
      return;
    }
    execute(line.command, at, false, false);
  }

  void execute(const std::string& command, std::chrono::nanoseconds at, bool drop, bool twice) {
    executed.push_back(command);
    const printer::GcodeCommand c = printer::parse_gcode_line(command);
    auto done = at;
    if (c.is('M', 109) || c.is('M', 190)) done = at + std::chrono::nanoseconds(heat_time);
    if (c.is('G', 28)) done = at + std::chrono::nanoseconds(home_time);
    if (busy_interval.count() > 0) {
      for (auto t = at + std::chrono::nanoseconds(busy_interval); t < done;
           t += std::chrono::nanoseconds(busy_interval)) {
        emit(t, "echo:busy: processing");
      }
    }
    busy_until_ = done;
    const std::string word = c.letter != 0 ? fmt::format("{}{}", c.letter, c.code) : "";
    if (refuse.count(word)) emit(done, fmt::format("echo:Unknown command: \"{}\"", command));
    if (c.is('M', 105) && !temperatures_before_ok) {
      if (!drop) emit(done, "ok T:210.00 /210.00 B:60.00 /60.00 @:0 B@:0", last_n);
      return;
    }
    if (c.is('M', 105)) emit(done, "T:210.00 /210.00 B:60.00 /60.00 @:0 B@:0");
    if (c.is('M', 114)) emit(done, "X:10.00 Y:20.00 Z:0.30 E:5.00 Count X:800 Y:1600 Z:120");
    if (c.is('M', 115) && !firmware_name.empty()) {
      emit(done, "FIRMWARE_NAME:" + firmware_name);
      emit(done, "Cap:EMERGENCY_PARSER:1");
    }
    if (drop) {
      if (wait_when_idle) emit(done + std::chrono::seconds(1), "wait");
      return;
    }
    emit(done, ok_text(), last_n);
    if (twice) emit(done, ok_text(), last_n);
  }

  std::chrono::nanoseconds now_{0};
  std::chrono::nanoseconds busy_until_{0};
  std::deque<Output> output_;
  std::string input_;
  std::set<long> seen_;
  long delivered_ok_ = 0;
  std::chrono::nanoseconds next_chatter_{std::chrono::seconds(1)};
  bool halted_ = false, silent_ = false, closed_ = false;
};

}  // namespace test_support
