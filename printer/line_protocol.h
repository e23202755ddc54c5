// The host side of Marlin's line protocol (DESIGN.md §4): numbers and checksums every command,
// keeps the lines in flight within a window, replays exactly what the firmware asks for, and
// notices silence, halts and restarts.
//
// Input: commands without line number or comment ("G1 X10 Y5 E0.3"), one at a time; replies
// from a printer::Link. Output: every command accepted by the firmware exactly once, in order;
// the firmware's temperatures (°C) and reported position (mm); counters of what went wrong.
//
// How it stays exact. Each dialect (printer/firmware_dialect.h) says what answers exactly which
// lines the firmware has; the host only ever sends a line again where the firmware checks line
// numbers, or where sending it again cannot run it twice.
// - Window: at most `window` numbered lines beyond the last one known accepted. More than one
//   only once the firmware reports ADVANCED_OK (`ok N<n> P<p> B<b>`), whose N says exactly which
//   line was accepted, and never more than the free queue slots it reports: by default as many
//   as it reports free, up to 4, so that a lost ok is credited by the next one at once. With
//   plain `ok`, each ok accepts the oldest line in flight; the window is 1. Repetier's
//   "ok <n>" (ACK_WITH_LINENUMBER) also says exactly which line was accepted.
// - Resends: `Resend: m` / "rs N<m>" means the firmware accepted everything before m and
//   nothing from m on: replay from m. Lines already in flight when the first request came are
//   rejected too and each draws its own request for m; those are stale and ignored (replaying
//   again would loop). Repetier's "skip N" is followed by an ok of its own too.
// - The ok after a resend request. Some firmwares print an `ok` right after the request, back
//   to back, as the request's own; which do is a matter of version:
//   Marlin 1.1.x: yes, unless the command at its queue's read slot came without an ok (an SD
//     print's): Marlin_main.cpp flush_and_request_resend ends with ok_to_send() (and so
//     Marlin/src/gcode/queue.cpp in early 2.0.x);
//   Marlin 2.0.9.x: no, queue.cpp flush_and_request_resend ends with the request;
//   Marlin 2.1.x: always, queue.cpp flush_and_request_resend ends with SERIAL_ECHOLNPGM(STR_OK);
//   Repetier: always, gcode.cpp GCode::requestResend prints "Resend:<n>" then "ok";
//   Teacup: its master, once the refused line has ended (mendel.c: the main loop sets
//     ack_waiting on every line end gcode_parse_char reports, refused or not); older ones
//     print "ok" only for a line they run (gcode_parse.c).
//   So the engine learns it, and keeps learning: an ok read right after a request, before any
//   line was written since and with no line before the one asked for still owing its own ok,
//   counts for; anything else first, or nothing within resend_ok_grace, counts against. An ok
//   that may be a line's (the line before, late; the replay's) counts for nothing. The count
//   saturates, so one misread ok is outvoted and a model the firmware contradicts is unlearnt
//   within a few requests; a dialect's answer (printer/firmware_dialect.h) is where it starts.
//   While the ok is expected or not known, the replay waits for it (it comes at once where it
//   comes, else resend_ok_grace): the replay's own ok is never taken for the request's.
// - Errors: `Error:` lines the firmware recovers from are counted; `Printer halted`, thermal
//   runaway, "!!" and "fatal:" throw PrinterError with the firmware's words; a `start`
//   mid-session (the board reset) throws PrinterError. A refused command ("echo:Unknown
//   command", Teacup's "E: Bad M-code 190") is counted, and when the print cannot go on
//   without it (heating, waiting, homing) throws CommandRefused, naming the command and the
//   profile's `firmware` to set.
// - Every reply line is handled once, in order, whether it came alone or with others in one
//   read: a reply that throws leaves the lines after it to be handled by whoever goes on using
//   the engine (a job's heaters-off lines), so no ok already received is lost.
// - Emergency commands (M112, M108, M410) are written at once, unnumbered, outside the window.
//
// Progress guarantees (what the tests in tests/printer/line_protocol_test.cpp pin):
// - When a line's ok is due. The engine runs the motion model (printer/print_time.h) over the
//   commands it sends and mirrors the firmware's planner (printer/planner_mirror.h): a move's
//   ok is due when the planner has room for it, any other command's at once, a command that
//   waits for the moves' once they have run. A lost ok is probed for `lost_ok_margin` after it
//   was due, or later if the planner still holds more than `refill_lead` of moves then (no
//   hurry, and no probe of a line that is merely waiting for room): so the printer does not
//   run out of moves for a lost ok. This once per line; a keepalive after the line was written
//   (the firmware is busy with it) leaves it to the rules below.
// - While lines are in flight and the firmware is alive, no more than `probe_after` (+ one
//   tick) passes without a line written or a reply that accounts for them (ok, resend, error)
//   or a keepalive (`busy:`, an M109/M190 report "... W:", Teacup's "Waiting for target
//   temp"): after that much quiet the engine probes. A probe is what this dialect answers
//   exactly (printer/firmware_dialect.h): on Marlin a line whose number skips one, refused with
//   "Resend: n", n the line it wants; on Teacup a line with a checksum wrong on purpose,
//   refused with "rs N<n>" the same way; on Repetier the unanswered line again, which it
//   answers with "skip N"
//   if it had it and otherwise runs now; on a firmware that does not name itself a numbered
//   M105, whose "ok T:" proves every line before it arrived (a skipped number if that goes
//   unanswered). A `wait` (the firmware idle with lines in flight) probes at once.
// - A probe's answer frees its own slot and every line before it. Plain oks credit the oldest
//   line; a lost ok's slot is credited once the firmware has answered a line sent after it.
// - The long timeout applies only while a command that may run long without an ok is really
//   unanswered (Marlin and Teacup acknowledge on execution: an unacknowledged M109, G28,
//   M400, a Teacup G1 after M116, ...; Repetier acknowledges on reading, so one of the last
//   kBlockingReach lines). Keepalives restart it. One probe goes behind such a command anyway
//   (harmless: it waits in the queue), so a lost ok of M109 costs `probe_after`, not the long
//   timeout.
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
#include "printer/motion_model.h"
#include "printer/planner_mirror.h"
#include "printer/print_time.h"
#include "printer/replies.h"

namespace printer {

struct ProtocolOptions {
  // Numbered lines in flight with ADVANCED_OK (without it, 1); 0: as many as the firmware
  // reports free, up to 4.
  std::size_t window = 0;
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
  // When an ok is due (see the progress guarantees): the printer's motion limits for the
  // motion model, the link's speed for the time a line and its answer take on the wire
  // (bit/s; 0: no time), how late an ok may be before it counts as lost, and how much motion
  // the planner should still hold when the probe goes.
  MotionLimits motion{};
  int baud = 115200;
  std::chrono::milliseconds lost_ok_margin{50};
  std::chrono::milliseconds refill_lead{250};
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

  // Starts numbering with `M110 N0`, sent at once as a probe: a board that answers it without
  // a `start` is up. Otherwise waits up to `boot_wait` for the firmware's `start` (a board
  // resets when its port opens) and the silence after its banner, then sends `M110 N0` until
  // it is accepted. Then `M115` to learn the firmware. Throws LinkError when the printer does
  // not answer.
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
  // Handles the reply lines already received, without waiting for more (a job that stops
  // reads what is in hand before it sends its last lines).
  void handle_received();
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
  // Link time since the firmware last answered a line or said it is busy.
  std::chrono::nanoseconds quiet_for() const;
  bool heat_wait_in_flight() const;
  Link& link() { return link_; }

 private:
  struct SentLine {
    long number = 0;
    std::string command;
    bool blocks = false;    // the firmware runs it for a long time without answering
    bool waits_for_user = false;
    bool is_m105 = false;
    bool m105_answered = false;  // its "T:" line came (Teacup): its ok is next
    bool waits_for_moves = false;  // answered once every queued move ran
    bool waits_for_heat = false;   // Teacup's G0/G1 after M116 (printer/firmware_dialect.h)
    bool answer_is_short = false;  // ok, or a line of figures: its time on the wire is known
    bool is_move = false;   // takes a slot in the firmware's planner
    double motion = 0;      // seconds of motion it adds, from the motion model
    long sequence = 0;      // which send() call it came from; a probe has its predecessor's
    std::chrono::nanoseconds written_at{0};  // when it was last written
    bool probed = false;    // the probe for its lost ok went (once per line)
    bool engine = false;    // the engine's own line (a probe, M113, M155), not a command
  };
  enum class Blocking { none, command, user };

  const SentLine* line(long number) const;
  long first_number() const;
  void transmit(long number);
  void wait_until(const std::function<bool()>& done,
                  std::optional<std::chrono::nanoseconds> deadline = std::nullopt);
  void wait_until_or(std::chrono::milliseconds timeout);
  void read_once(std::chrono::milliseconds timeout);
  void write_connect_line();  // N0 M110 N0, unrecorded
  // connect's steps: true when the first M110 was answered by a board without a banner.
  bool probe_until_booted(std::chrono::milliseconds boot_wait);
  bool exchange_m110();        // M110 N0 until accepted; false when never
  void start_numbering();      // line 1 next, nothing in flight
  void identify_firmware();    // M115, and what its dialect fixes
  bool handle_buffered();
  void handle(const Reply& reply);
  void end_pairings(ReplyKind kind);  // a resend request and its ok, "T:" and M105's ok
  void note_reports(const Reply& reply);   // temperatures, position
  void note_firmware(const Reply& reply);  // its name, the banner, capabilities
  void handle_skip(const Reply& reply);
  void handle_error(const Reply& reply);
  void handle_busy(const Reply& reply);
  void handle_start();
  void accept_through(long number, bool own_ok = false);
  void mirror_accepted(long number, bool own_ok);
  void set_accepted(long number);
  void handle_ok(const Reply& reply);
  void handle_resend(long wanted);
  // The reply after a resend request: whether it was the request's own ok, as evidence.
  void open_request(bool teaches);
  void settle_request(bool ok_followed);
  long line_writes() const;  // numbered lines written so far, first time or again
  void handle_temperature_line(const Reply& reply);
  void handle_refusal(std::string_view text, std::optional<long> line_number);
  void answered();
  void check_silence();
  std::optional<std::chrono::nanoseconds> ok_overdue_at(const SentLine& line) const;
  // When the probe for the oldest line's lost ok goes by the motion model, if it does.
  std::optional<std::chrono::nanoseconds> model_probe_at() const;
  std::chrono::nanoseconds wire_time(std::size_t bytes) const;
  void probe();
  void insert_engine_line(std::string command);
  void remove_engine_line(long number);
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
  // The ok after a resend request (see above): evidence for it minus evidence against; > 0 the
  // firmware sends one, < 0 it does not, 0 not known.
  int trailing_ok_score_ = 0;
  bool request_open_ = false;     // a resend request was read, the reply after it not yet
  bool request_teaches_ = false;  // ... and an ok right after it can only be its own
  bool holding_ = false;          // the replay waits for the request's ok until hold_until_
  long writes_at_request_ = 0;    // line_writes() when the request was read
  bool advanced_ok_ = false;
  int queue_free_ = -1;        // last ADVANCED_OK B, -1 before any
  bool connected_ = false;
  bool connect_ok_ = false, connect_rejected_ = false;
  bool connect_resend_ = false;  // the refusal's resend request came (it follows its Error line)
  std::chrono::nanoseconds hold_until_{0};
  std::chrono::nanoseconds last_wait_call_{0};
  bool restart_seen_ = false;
  long starts_seen_ = 0;       // `start` lines read
  std::chrono::nanoseconds last_write_{0};      // a numbered line written
  std::chrono::nanoseconds last_answer_{0};     // an ok, resend, error or keepalive read
  std::chrono::nanoseconds next_probe_at_{0};
  int probes_unanswered_ = 0;
  long probe_line_ = -1;       // the line number of the outstanding probe, -1 for none
  int swallow_oks_ = 0;            // oks that belong to Repetier "skip" lines or stale probes
  int stale_answers_ = 0;          // Teacup M105s that ran behind a refused line
  std::deque<long> probes_before_;  // Teacup wrong-checksum probes out: sent_ when each went
  int own_errors_expected_ = 0;    // line-number errors the skipped-number probes draw
  bool banner_said_marlin_ = false;
  bool m105_answer_next_ = false;  // a bare "T:" line just came: the next ok may be M105's
  bool idle_reported_ = false;     // the firmware said `wait` with lines in flight
  bool autoreport_on_ = false;
  bool teacup_heat_pending_ = false;  // an M116 went to Teacup: its next G0/G1 waits
  std::chrono::nanoseconds last_keepalive_{-1};  // a busy: line or a heating report
  PrintClock clock_;           // the motion model over the commands sent
  PlannerMirror mirror_;
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
