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
//   An `ok` right after a resend request belongs to the request (Marlin 1.1 and Repetier send
//   it, Marlin 2 and Teacup do not; the dialect says, or the engine learns it within the first
//   few resends). Repetier's "skip N" is followed by an ok of its own too.
// - Errors: `Error:` lines the firmware recovers from are counted; `Printer halted`, thermal
//   runaway, "!!" and "fatal:" throw PrinterError with the firmware's words; a `start`
//   mid-session (the board reset) throws PrinterError. A refused command ("echo:Unknown
//   command", Teacup's "ok E: Bad M-code 190") is counted, and when the print cannot go on
//   without it (heating, waiting, homing) throws CommandRefused, naming the command and the
//   profile's `firmware` to set.
// - Emergency commands (M112, M108, M410) are written at once, unnumbered, outside the window.
//
// Progress guarantees (what the tests in tests/printer/line_protocol_test.cpp pin):
// - While lines are in flight and the firmware is alive, no more than `probe_after` (+ one
//   tick) passes without a line written or a reply that accounts for them (ok, resend, error)
//   or a keepalive (`busy:`, an M109/M190 report "... W:"): after that much quiet the engine
//   probes. A probe is what this dialect answers exactly (printer/firmware_dialect.h): on
//   Marlin a line whose number skips one, refused with "Resend: n", n the line it wants; on
//   Teacup and Repetier the unanswered line again, which the firmware answers with a request
//   for the next line if it had it and otherwise runs now; on a firmware that does not name
//   itself a numbered M105, whose "ok T:" proves every line before it arrived (a skipped
//   number if that goes unanswered). A `wait` (the firmware idle with lines in flight) probes
//   at once.
// - A probe's answer frees its own slot and every line before it. Plain oks credit the oldest
//   line; a lost ok's slot is credited once the firmware has answered a line sent after it.
// - The long timeout applies only while a command that may run long without an ok is really
//   unanswered (Marlin acknowledges on execution: an unacknowledged M109, G28, M400, ...;
//   Teacup and Repetier acknowledge on reading, so one of the last kBlockingReach lines).
//   Keepalives restart it. One probe goes behind such a command anyway (harmless: it waits in
//   the queue), so a lost ok of M109 costs `probe_after`, not the long timeout.
// - On Marlin the job asks for the busy keepalive every second (M113 S1, use_keepalive()):
//   once one has come, the firmware is known to say "busy:" whenever it is working, so quiet
//   of a second and a half already means a lost ok, and the probe goes then.
// - Without a blocking command, `max_probes` unanswered probes in a row (no ok, no resend, no
//   keepalive between them) end the job with a LinkError: 30 s by default. Replies that are
//   not answers (temperature auto-reports, echo lines) do not count as answers, so a firmware
//   that talks but does not take lines cannot keep a job waiting for ever.
// - M0/M1/M226/M600 (waiting for the user) never time out.
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
#include <vector>

#include "printer/firmware_dialect.h"
#include "printer/link.h"
#include "printer/replies.h"

namespace printer {

struct ProtocolOptions {
  std::size_t window = 1;  // numbered lines in flight; > 1 takes effect with ADVANCED_OK only
  std::chrono::milliseconds probe_after{3000};           // quiet before a probe
  int max_probes = 10;  // unanswered probes before giving up: 30 s of silence, as OctoPrint
  // Quiet before giving up while a command that may run long is unanswered (M109, G28, ...).
  std::chrono::milliseconds long_command_timeout{30 * 60 * 1000};
  // The dialect assumed when the firmware does not name itself in reply to M115.
  Firmware assumed_firmware = Firmware::unknown;
  // Consecutive requests for one line sent again before the link counts as broken. OctoPrint
  // gives up after 10; on a link that corrupts a third of the lines (1% of the bytes) ten in
  // a row come about once in 100 000 lines, a false end to a good print; 25 in a row about
  // once in 10^11, and a dead link still ends within 25 round trips.
  int max_resends_of_one_line = 25;
  std::chrono::milliseconds resend_ok_grace{250};        // wait for an ok after `Resend:`
  std::chrono::milliseconds tick{100};  // longest read while waiting, so on_wait runs often
};

struct ProtocolStats {
  long lines_sent = 0;          // numbered lines written, first time
  long lines_resent = 0;        // numbered lines written again after a resend request
  long resend_requests = 0;     // resend requests acted on
  long stale_resends = 0;       // resend requests for lines sent before a replay (ignored)
  long duplicate_oks = 0;       // oks with nothing in flight
  long probes = 0;              // probes sent after quiet (see the progress guarantees)
  long recoverable_errors = 0;  // Error: lines the firmware went on after
  long busy_reports = 0;
  long bytes_written = 0;
  long unreadable_lines = 0;    // reply lines that are not text (noise, wrong baud rate)
  long refused_commands = 0;    // commands the firmware said it does not know or refused
  // The longest stretch with lines in flight and neither a line written nor an answer nor a
  // keepalive read (see the progress guarantees above).
  std::chrono::nanoseconds longest_silence{0};
};

// What the firmware said about itself in reply to M115.
struct FirmwareInfo {
  std::string name;        // FIRMWARE_NAME:...; "" when M115 named none
  Firmware firmware = Firmware::unknown;  // recognised from the name (or assumed)
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

  // Waits until every line sent so far is accepted or `timeout` passes; true when accepted.
  bool wait_acknowledged_for(std::chrono::milliseconds timeout);
  // Gives up on the lines not yet accepted (a cancel on a stalled link): those not yet
  // written are dropped, and the numbering restarts after the last line written with a
  // numbered M110 (which the firmware takes whatever number it expected), so the next lines
  // are accepted whether or not the abandoned ones arrived.
  void abandon_unacknowledged();
  // Drops the commands given to send() that were not written yet (a cancel leaves send()).
  void drop_unsent();

  // Asks for the temperatures without waiting for them: M155 S<seconds> once where the
  // firmware reports AUTOREPORT_TEMP (then nothing more), else a numbered M105 after the
  // lines queued, answered in passing. Returns whether auto-reports are on.
  bool request_temperatures(std::chrono::seconds every = std::chrono::seconds(2));
  // Asks a Marlin firmware for its busy keepalive every `interval` (M113 S<n>; OctoPrint asks
  // for 2 s): once a keepalive has come, a lost ok is probed for after the interval and
  // 0.5 s instead of `probe_after`. Nothing for other dialects, which have none.
  void use_keepalive(std::chrono::seconds interval);
  bool autoreporting() const { return autoreport_on_; }
  // Link time of the last temperature report, if any.
  std::optional<std::chrono::nanoseconds> temperatures_at() const { return temperatures_at_; }

  // Commands the firmware refused, oldest first ("M107", "M73 P10 R5"), up to 20.
  const std::vector<std::string>& refused() const { return refused_; }

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
  const FirmwareDialect& dialect() const { return dialect_of(firmware_.firmware); }
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
  // True while the firmware may be running a command for long (M109, G28, M0, ...) that it
  // has not answered (see the progress guarantees).
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
    long oks_before = 0;    // oks read before it was last written (Repetier's M105 answer)
  };
  enum class Blocking { none, command, user };

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
  void handle_temperature_line(const Reply& reply);
  void handle_refusal(std::string_view text, std::optional<long> line_number);
  void answered();
  void check_silence();
  void probe();
  void insert_engine_line(std::string command);
  Blocking blocking(long before = -1) const;
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
  bool resent_since_request_ = false;  // the line last asked for was written since
  bool expect_trailing_ok_ = false;
  int trailing_ok_seen_ = 0, trailing_ok_missed_ = 0;
  bool advanced_ok_ = false;
  int queue_free_ = -1;        // last ADVANCED_OK B, -1 before any
  bool connected_ = false;
  bool connect_ok_ = false, connect_rejected_ = false;
  std::chrono::nanoseconds hold_until_{0};      // replay waits until then for a trailing ok
  std::chrono::nanoseconds last_wait_call_{0};
  bool restart_seen_ = false;
  std::chrono::nanoseconds last_write_{0};      // a numbered line written
  std::chrono::nanoseconds last_answer_{0};     // an ok, resend, error or keepalive read
  std::chrono::nanoseconds next_probe_at_{0};
  int probes_unanswered_ = 0;
  long probe_line_ = -1;       // the line number of the outstanding probe, -1 for none
  long oks_read_ = 0;
  int swallow_oks_ = 0;            // oks that belong to Repetier "skip" lines
  int own_errors_expected_ = 0;    // line-number errors the skipped-number probes draw
  bool banner_said_marlin_ = false;
  bool m105_answer_next_ = false;  // a bare "T:" line just came: the next ok may be M105's
  bool idle_reported_ = false;     // the firmware said `wait` with lines in flight
  bool autoreport_on_ = false;
  std::optional<std::chrono::nanoseconds> keepalive_;  // the M113 interval asked for
  bool keepalive_seen_ = false;                         // and a busy: line since
  std::optional<std::chrono::nanoseconds> temperatures_at_;
  std::vector<std::string> refused_;
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
