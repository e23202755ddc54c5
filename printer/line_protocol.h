// The host side of Marlin's line protocol (DESIGN.md §4): numbers and checksums every command,
// keeps the lines in flight within a window, replays exactly what the firmware asks for, and
// notices silence, halts and restarts.
//
// Input: commands without line number or comment ("G1 X10 Y5 E0.3"), one at a time; replies
// from a printer::Link. Output: every command accepted by the firmware exactly once, in order;
// the firmware's temperatures (°C) and reported position (mm); counters of what went wrong.
//
// How it stays exact. Marlin executes a numbered line only when its number is the last one it
// accepted plus one, so a line can never run twice or be skipped as long as the host replays
// from exactly the line the firmware names in `Resend:`. The host's own work is to keep the
// stream moving:
// - Window: at most `window` numbered lines beyond the last one known accepted. More than one
//   only once the firmware reports ADVANCED_OK (`ok N<n> P<p> B<b>`), whose N says exactly which
//   line was accepted, and never more than the free queue slots it reports. With plain `ok`,
//   each ok accepts the oldest line in flight; the window is 1.
// - Resends: `Resend: m` means the firmware accepted everything before m and nothing from m on:
//   replay from m. Lines already in flight when the first request came are rejected too and
//   each draws its own request for m; those are stale and ignored (replaying again would loop).
//   An `ok` right after a resend request belongs to the request (Marlin 2 sends it, older
//   firmware does not; the engine learns which within the first few resends).
// - Silence: no byte for `probe_after` while lines are in flight (a lost `ok`, a line whose end
//   was lost) sends a numbered `M105`; its `ok T:` proves everything before it was accepted.
//   While a command that blocks the firmware is in flight (M109, M190, G28, M400, M0, ...)
//   silence is expected and waits `long_command_timeout` (M0/M1/M600: for ever) instead, so a
//   firmware with busy keepalive off does not time out. `busy:` and any other line are signs
//   of life. `max_probes` unanswered probes end the job with a LinkError. (Marlin's own busy
//   keepalive also covers a full planner; without it a long slow move can be silent for
//   seconds, which is why one probe is not yet a failure.)
// - Errors: `Error:` lines the firmware recovers from are counted; `Printer halted`, thermal
//   runaway and the like throw PrinterError with the firmware's words; a `start` mid-session
//   (the board reset) throws PrinterError.
// - Emergency commands (M112, M108, M410) are written at once, unnumbered, outside the window.
//
// All time is the link's clock (Link::now, Link::read's timeout), so against the simulated
// printer every timeout is deterministic and takes no wall time.
#pragma once

#include <chrono>
#include <cstddef>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <string_view>

#include "printer/link.h"
#include "printer/replies.h"

namespace printer {

struct ProtocolOptions {
  std::size_t window = 1;  // numbered lines in flight; > 1 takes effect with ADVANCED_OK only
  std::chrono::milliseconds probe_after{3000};           // silence before an M105 probe
  int max_probes = 10;  // unanswered probes before giving up: 30 s of silence, as OctoPrint
  std::chrono::milliseconds long_command_timeout{30 * 60 * 1000};  // M109, G28, M400, ...
  int max_resends_of_one_line = 10;                      // consecutive requests for one line
  std::chrono::milliseconds resend_ok_grace{250};        // wait for an ok after `Resend:`
  std::chrono::milliseconds tick{100};  // longest read while waiting, so on_wait runs often
};

struct ProtocolStats {
  long lines_sent = 0;          // numbered lines written, first time
  long lines_resent = 0;        // numbered lines written again after a resend request
  long resend_requests = 0;     // resend requests acted on
  long stale_resends = 0;       // resend requests for lines sent before a replay (ignored)
  long duplicate_oks = 0;       // oks with nothing in flight
  long probes = 0;              // M105 sent after silence
  long recoverable_errors = 0;  // Error: lines the firmware went on after
  long busy_reports = 0;
  long bytes_written = 0;
  long unreadable_lines = 0;    // reply lines that are not text (noise, wrong baud rate)
};

// What the firmware said about itself in reply to M115.
struct FirmwareInfo {
  std::string name;        // FIRMWARE_NAME:...
  bool emergency_parser = false;
  bool autoreport_temperature = false;
};

class LineProtocol {
 public:
  explicit LineProtocol(Link& link, ProtocolOptions options = {});

  // Starts numbering: waits up to `boot_wait` for the firmware's `start` (a board resets when its
  // port opens) or for silence, then sends `M110 N0` until it is accepted and `M115` to learn
  // the firmware. Throws LinkError when the printer does not answer.
  void connect(std::chrono::milliseconds boot_wait = std::chrono::milliseconds(2500));

  // Sends one command (without line number, checksum or comment). Returns once it is written;
  // waits, reading replies, while the window is full. Throws LinkError, PrinterError.
  void send(std::string_view command);

  // Waits until every line sent so far is accepted.
  void wait_acknowledged();

  // Reads and handles the replies that arrive within `timeout`; also runs the silence checks.
  void poll(std::chrono::milliseconds timeout);

  // Writes an emergency command (M112, M108, M410) at once, unnumbered, past the window.
  void emergency(std::string_view command);

  // Sends M400 + M114 and waits for the position report the M114 draws.
  std::optional<ReportedPosition> query_position();

  // Called while the engine waits (at least every options.tick of link time): the job's hook
  // for keys, the control socket and the progress line. May throw to abandon the wait.
  std::function<void()> on_wait;
  // Called for every reply line (logs, the UI's messages).
  std::function<void(const Reply&)> on_reply;

  const ProtocolStats& stats() const { return stats_; }
  const std::optional<Temperatures>& temperatures() const { return temperatures_; }
  const std::optional<ReportedPosition>& position() const { return position_; }
  long position_reports() const { return position_reports_; }
  const FirmwareInfo& firmware() const { return firmware_; }
  bool advanced_ok() const { return advanced_ok_; }
  bool restart_seen() const { return restart_seen_; }
  // The number the firmware holds as its last accepted line (exact after a resend or an
  // ADVANCED_OK; otherwise counted from plain oks).
  long last_accepted() const { return accepted_; }
  long last_sent() const { return sent_; }
  std::size_t lines_in_flight() const { return static_cast<std::size_t>(sent_ - accepted_); }
  // Commands given to send() so far, and how many of them the firmware has accepted (the
  // engine's own M105 probes are not counted).
  long commands_sent() const { return commands_sent_; }
  long commands_accepted() const { return commands_accepted_; }
  // True while a line in flight is one the firmware runs for long (M109, G28, M0, ...).
  bool long_command_in_flight() const;
  Link& link() { return link_; }

 private:
  struct SentLine {
    long number = 0;
    std::string command;
    bool blocks = false;    // the firmware runs it for a long time without answering
    bool waits_for_user = false;
    bool is_m105 = false;
    long sequence = 0;      // which send() call it came from; a probe has its predecessor's
  };

  const SentLine* line(long number) const;
  long first_number() const;
  void transmit(long number);
  void wait_until(const std::function<bool()>& done,
                  std::optional<std::chrono::nanoseconds> deadline = std::nullopt);
  void wait_until_or(std::chrono::milliseconds timeout);
  void read_once(std::chrono::milliseconds timeout);
  void feed(const std::string& bytes);
  void handle(const Reply& reply);
  void accept_through(long number);
  void set_accepted(long number);
  void handle_ok(const Reply& reply);
  void handle_resend(long wanted);
  void check_silence();
  std::size_t allowed_in_flight() const;
  bool pending_replay() const { return sent_ < assigned_; }

  Link& link_;
  ProtocolOptions options_;
  ProtocolStats stats_;
  std::deque<SentLine> history_;  // lines history_.front().number .. assigned_
  long assigned_ = 0;   // highest line number given to a command
  long sent_ = 0;       // highest line number written since the last replay started
  long accepted_ = 0;   // highest line number the firmware accepted (see last_accepted)
  long highest_written_ = 0;   // highest line number ever written
  long commands_sent_ = 0, commands_accepted_ = 0;
  int stale_left_ = 0;         // resend requests still expected from lines before the replay
  long last_resend_ = -1;      // line of the last replay
  int same_resend_count_ = 0;
  bool expect_trailing_ok_ = false;
  int trailing_ok_seen_ = 0, trailing_ok_missed_ = 0;
  bool advanced_ok_ = false;
  int queue_free_ = -1;        // last ADVANCED_OK B, -1 before any
  bool connected_ = false;
  bool connect_ok_ = false, connect_rejected_ = false;
  long last_blocking_line_ = 0;    // highest line written that blocks the firmware
  long last_user_wait_line_ = 0;   // highest line written that waits for the user
  std::chrono::nanoseconds hold_until_{0};      // replay waits until then for a trailing ok
  std::chrono::nanoseconds last_wait_call_{0};
  bool restart_seen_ = false;
  std::chrono::nanoseconds last_activity_{0};
  int probes_unanswered_ = 0;
  long probe_line_ = -1;       // the line number of the outstanding probe, -1 for none
  std::string partial_;        // bytes after the last line end
  std::optional<Temperatures> temperatures_;
  std::optional<ReportedPosition> position_;
  long position_reports_ = 0;
  FirmwareInfo firmware_;
};

// True for commands Marlin may run for a long time before its ok: heating waits, homing,
// probing, M400, dwell, user waits.
bool command_blocks(std::string_view command);
// True for commands that wait for the user (M0, M1, M226, M600): no timeout applies.
bool command_waits_for_user(std::string_view command);

}  // namespace printer
