#include "printer/line_protocol.h"

#include <algorithm>
#include <cctype>
#include <utility>

#include <fmt/core.h>

#include "printer/error.h"
#include "printer/gcode_line.h"

namespace printer {

namespace {

using std::chrono::milliseconds;
using std::chrono::nanoseconds;

// Lines kept below the last accepted one, for resend requests that arrive late.
constexpr long kHistoryBehind = 4096;
// Where the firmware acknowledges a line on reading it (Teacup, Repetier), a blocking command
// may still run in its queue (a few commands, up to 32 in big builds) while later lines are
// already acknowledged; until this many lines were written after it, quiet may still be that
// command running.
constexpr long kBlockingReach = 40;
// Behind a command that may run long, a probe waits in the firmware's queue; one more goes
// this many probe intervals later (the first may have been lost on the wire), and no more: each
// takes a place in the firmware's queue or RX buffer until the command ends.
constexpr int kBlockedProbeSpacing = 10;
constexpr int kBlockedProbes = 2;
// M110 attempts at connect before the printer counts as not answering.
constexpr int kConnectTries = 5;
// Refused commands remembered for the summary.
constexpr std::size_t kRefusedKept = 20;
// How late a keepalive may be before the firmware counts as idle (serial and USB latency).
constexpr nanoseconds kKeepaliveMargin = std::chrono::milliseconds(500);
// The ok after a resend request (see the header): evidence for it counts +1, against it -1,
// within +-kTrailingOkCap, so that a model once contradicted is unlearnt within a few
// requests however long it held; a dialect's own answer starts the count at +-kTrailingOkPrior.
constexpr int kTrailingOkCap = 8;
constexpr int kTrailingOkPrior = 2;
// Lines in flight with ADVANCED_OK when the user gave no window: Marlin's BUFSIZE is 4.
constexpr std::size_t kAutoWindow = 4;
// Bytes of an answer on the wire, for when an ok is due ("ok N1234 P15 B3" and its line end).
constexpr std::size_t kAnswerBytes = 20;

double seconds(nanoseconds d) { return std::chrono::duration<double>(d).count(); }

// A reply line with mostly printable ASCII: a firmware talking, not line noise at the wrong baud.
bool is_readable(std::string_view text) {
  if (text.empty()) return false;
  std::size_t printable = 0;
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) ++printable;
  }
  return printable * 10 >= text.size() * 9;
}

// Commands the print cannot go on without: heating and waiting for it, homing, waiting for
// the moves. A firmware that refuses one of these would print cold, or unhomed.
bool print_needs(const GcodeCommand& c) {
  if (c.letter == 'G') return c.code == 28 || c.code == 4;
  if (c.letter != 'M') return false;
  switch (c.code) {
    case 104: case 109: case 116: case 140: case 141: case 190: case 191: case 400:
      return true;
    default:
      return false;
  }
}

// The command a refusal names: "Unknown command: \"M190 S60\"" -> M190, "E: Bad M-code 190"
// -> M190, "Unknown command:N12 G29" -> G29.
std::optional<GcodeCommand> command_named_in(std::string_view text) {
  for (const std::string_view kind : {"M-code", "G-code"}) {
    if (const auto at = text.find(kind); at != std::string_view::npos) {
      std::string_view rest = text.substr(at + kind.size());
      while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
      if (!rest.empty() && std::isdigit(static_cast<unsigned char>(rest.front()))) {
        return parse_gcode_line(std::string(1, kind.front()) + std::string(rest));
      }
    }
  }
  const auto colon = text.find("ommand:");
  if (colon == std::string_view::npos) return std::nullopt;
  std::string_view rest = text.substr(colon + 7);
  while (!rest.empty() && (rest.front() == ' ' || rest.front() == '"')) rest.remove_prefix(1);
  if (!rest.empty() && (rest.front() == 'N' || rest.front() == 'n')) {  // a line number first
    std::size_t i = 1;
    while (i < rest.size() && std::isdigit(static_cast<unsigned char>(rest[i]))) ++i;
    rest.remove_prefix(i);
    while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
  }
  if (const auto quote = rest.find('"'); quote != std::string_view::npos) rest = rest.substr(0, quote);
  const GcodeCommand c = parse_gcode_line(rest);
  if (c.code < 0) return std::nullopt;
  return c;
}

// What a user does about a refused command: the profile's firmware to set, in words.
std::string refusal_advice(const GcodeCommand& c, const FirmwareDialect& dialect) {
  if (c.is('M', 109) || c.is('M', 190) || c.is('M', 191)) {
    if (dialect.waits_with_m116) {
      return fmt::format(
          "{} has no M{}: it waits for temperatures with M116; set firmware = \"{}\" in the "
          "printer profile (or --set firmware={}) and slice again, so the G-code heats with "
          "M104/M140 and waits with M116",
          dialect.display, c.code, dialect.name, dialect.name);
    }
    return fmt::format(
        "{} has no M{}; if it waits for temperatures with M116 (as Teacup does), set firmware = "
        "\"teacup\" in the printer profile (or --set firmware=teacup) and slice again",
        dialect.firmware == Firmware::unknown ? "this firmware" : dialect.display, c.code);
  }
  if (c.is('M', 116)) {
    const std::string_view name = dialect.firmware == Firmware::unknown ? "marlin" : dialect.name;
    return fmt::format(
        "{} has no M116; set firmware = \"{}\" in the printer profile (or --set firmware={}) "
        "and slice again, so the G-code waits for temperatures with M109/M190",
        dialect.firmware == Firmware::unknown ? "this firmware" : dialect.display, name, name);
  }
  return fmt::format(
      "the print cannot go on without it; check the printer profile's firmware (one of {}) "
      "and its start G-code",
      firmware_names());
}

// Commands answered with an ok, a refusal or a line of figures at most (M105, M114): the time
// their answer takes on the wire is known.
bool answer_is_short(const GcodeCommand& c) {
  if (c.letter == 'G') return c.code <= 3 || (c.code >= 90 && c.code <= 92);
  if (c.letter != 'M') return c.letter == 'T';
  switch (c.code) {
    case 18: case 73: case 82: case 83: case 84: case 104: case 105: case 106: case 107: case 110:
    case 113: case 114: case 117: case 140: case 155: case 220: case 221:
      return true;
    default:
      return false;
  }
}

}  // namespace

bool command_waits_for_user(std::string_view command) {
  const GcodeCommand c = parse_gcode_line(command);
  return c.is('M', 0) || c.is('M', 1) || c.is('M', 226) || c.is('M', 600);
}

bool command_blocks(std::string_view command) {
  const GcodeCommand c = parse_gcode_line(command);
  if (c.letter == 'G') return c.code == 4 || c.code == 28 || c.code == 29 || c.code == 33 || c.code == 34;
  if (c.letter == 'M') {
    switch (c.code) {
      case 0: case 1: case 109: case 116: case 190: case 191: case 226: case 303: case 400:
      case 600: case 701: case 702: case 1001:
        return true;
      default:
        return false;
    }
  }
  return false;
}

LineProtocol::LineProtocol(Link& link, ProtocolOptions options)
    : link_(link), options_(options), clock_(options.motion) {
  if (options_.tick.count() <= 0) options_.tick = milliseconds(100);
  last_write_ = last_answer_ = link_.now();
}

long LineProtocol::first_number() const {
  return history_.empty() ? assigned_ + 1 : history_.front().number;
}

const LineProtocol::SentLine* LineProtocol::line(long number) const {
  if (history_.empty() || number < history_.front().number || number > history_.back().number) {
    return nullptr;
  }
  return &history_[static_cast<std::size_t>(number - history_.front().number)];
}

std::size_t LineProtocol::allowed_in_flight() const {
  if (!advanced_ok_) return 1;
  std::size_t allowed = options_.window > 0 ? options_.window : kAutoWindow;
  if (queue_free_ >= 0) allowed = std::min(allowed, std::max<std::size_t>(1, queue_free_));
  return allowed;
}

void LineProtocol::transmit(long number) {
  const SentLine* sent = line(number);
  if (sent == nullptr) return;
  std::string framed = frame_line(number, sent->command);
  framed += '\n';
  link_.write(framed);
  stats_.bytes_written += static_cast<long>(framed.size());
  if (number > highest_written_) {
    highest_written_ = number;
    ++stats_.lines_sent;
  } else {
    ++stats_.lines_resent;
  }
  sent_ = number;
  if (number == last_resend_) resent_since_request_ = true;
  last_write_ = link_.now();
  history_[static_cast<std::size_t>(number - history_.front().number)].written_at = last_write_;
}

void LineProtocol::send(std::string_view command) {
  SentLine next;
  next.number = ++assigned_;
  next.command = std::string(command);
  const GcodeCommand parsed = parse_gcode_line(command);
  next.blocks = command_blocks(command);
  next.waits_for_user = command_waits_for_user(command);
  next.is_m105 = parsed.is('M', 105);
  next.waits_for_moves = waits_for_moves(dialect().firmware, parsed);
  next.answer_is_short = answer_is_short(parsed);
  // Teacup's M116 only sets a flag: the next G0/G1 is the command that waits for the heaters
  // (gcode_process.c, temp_wait()).
  if (dialect().firmware == Firmware::teacup) {
    if (parsed.is('M', 116)) {
      teacup_heat_pending_ = true;
      next.blocks = false;  // answered at once
    }
    if (teacup_heat_pending_ && (parsed.is('G', 0) || parsed.is('G', 1))) {
      next.blocks = next.waits_for_heat = true;
      teacup_heat_pending_ = false;
    }
  }
  const double before = clock_.modeled();
  const std::size_t moves_before = clock_.moves_queued();
  clock_.command(parsed);
  // A move takes the planner a slot even when the model's time barely grows (a short move
  // that lets the one before it keep its speed).
  next.is_move = clock_.moves_queued() > moves_before;
  next.motion = std::max(0.0, clock_.modeled() - before);
  next.sequence = ++commands_sent_;
  history_.push_back(std::move(next));
  while (history_.size() > 1 && history_.front().number < accepted_ - kHistoryBehind) {
    history_.pop_front();
  }
  // Done once everything assigned is written (a probe may have moved this line up a number).
  wait_until([&] { return sent_ >= assigned_; });
}

void LineProtocol::wait_acknowledged() {
  wait_until([&] { return accepted_ >= assigned_; });
}

void LineProtocol::poll(milliseconds timeout) {
  wait_until_or(timeout);
}

void LineProtocol::wait_until_or(milliseconds timeout) {
  const nanoseconds deadline = link_.now() + timeout;
  bool first = true;
  wait_until([&] {
    if (first) {
      first = false;
      return false;
    }
    return link_.now() >= deadline;
  }, deadline);
}

void LineProtocol::wait_until(const std::function<bool()>& done, std::optional<nanoseconds> deadline) {
  while (true) {
    const nanoseconds now = link_.now();
    // No ok followed the resend request in time: this firmware sent none.
    if (holding_ && now >= hold_until_) settle_request(false);
    while (!holding_ && pending_replay() && lines_in_flight() < allowed_in_flight()) {
      transmit(sent_ + 1);
    }
    if (done()) return;
    milliseconds wait = options_.tick;
    if (const std::optional<nanoseconds> probe_at = model_probe_at()) {
      // Awake when the oldest line's ok becomes overdue, not a tick later.
      wait = std::min(wait, std::chrono::duration_cast<milliseconds>(*probe_at - now) + milliseconds(1));
    }
    if (holding_) {
      wait = std::min(wait, std::chrono::duration_cast<milliseconds>(hold_until_ - now) + milliseconds(1));
    }
    if (deadline) {
      wait = std::min(wait, std::chrono::duration_cast<milliseconds>(*deadline - now) + milliseconds(1));
    }
    read_once(std::max(wait, milliseconds(0)));
    check_silence();
    if (on_wait && link_.now() - last_wait_call_ >= options_.tick) {
      last_wait_call_ = link_.now();
      on_wait();
    }
  }
}

void LineProtocol::read_once(milliseconds timeout) {
  // Lines left by a reply that threw come first; then what the link brings.
  if (handle_buffered()) return;
  partial_ += link_.read(timeout);
  handle_buffered();
  // A line end lost to noise must not grow the buffer without bound.
  if (partial_.size() > 4096) partial_.clear();
}

bool LineProtocol::handle_buffered() {
  // Each line leaves the buffer before it is handled: a reply that throws (a halt, a refused
  // command) must not be read again, and the lines after it stay for whoever goes on using
  // the engine.
  bool handled = false;
  std::size_t end;
  while ((end = partial_.find_first_of("\r\n")) != std::string::npos) {
    const std::string text = partial_.substr(0, end);
    partial_.erase(0, end + 1);
    if (text.find_first_not_of(" \t") == std::string::npos) continue;
    handled = true;
    handle(classify_reply(text));
  }
  return handled;
}

void LineProtocol::handle_received() {
  handle_buffered();
  partial_ += link_.read(milliseconds(0));
  handle_buffered();
}

void LineProtocol::handle(const Reply& reply) {
  if (on_reply) on_reply(reply);
  if (reply.kind == ReplyKind::other && !is_readable(reply.text)) stats_.unreadable_lines++;
  end_pairings(reply.kind);
  note_reports(reply);
  note_firmware(reply);
  switch (reply.kind) {
    case ReplyKind::ok:
      handle_ok(reply);
      break;
    case ReplyKind::resend:
      handle_resend(*reply.line_number);
      break;
    case ReplyKind::skip:
      handle_skip(reply);
      break;
    case ReplyKind::error:
      handle_error(reply);
      break;
    case ReplyKind::fatal:
      throw FirmwareStopped(fmt::format("{}: the printer stopped: {}", link_.name(), reply.text));
    case ReplyKind::busy:
      handle_busy(reply);
      break;
    case ReplyKind::wait:
      if (connected_ && lines_in_flight() > 0) idle_reported_ = true;
      break;
    case ReplyKind::start:
      handle_start();
      break;
    case ReplyKind::temperature:
      if (reply.heating_wait) {
        last_keepalive_ = link_.now();
        answered();  // M109/M190 report while they wait: a keepalive
      } else {
        handle_temperature_line(reply);
      }
      break;
    case ReplyKind::echo:
      if (reply.unknown_command && connected_) handle_refusal(reply.text, std::nullopt);
      break;
    default:
      break;
  }
}

void LineProtocol::end_pairings(ReplyKind kind) {
  // A firmware prints a resend request and its ok back to back: anything else first means
  // this request has no ok.
  if (request_open_ && kind != ReplyKind::ok) settle_request(false);
  // "T:" then "ok" answer an M105 only when they come one after the other.
  if (kind != ReplyKind::ok && kind != ReplyKind::temperature) m105_answer_next_ = false;
}

void LineProtocol::note_reports(const Reply& reply) {
  if (reply.temperatures) {
    Temperatures merged = temperatures_.value_or(Temperatures{});
    if (reply.temperatures->hotend) merged.hotend = reply.temperatures->hotend;
    if (reply.temperatures->hotend_target) merged.hotend_target = reply.temperatures->hotend_target;
    if (reply.temperatures->bed) merged.bed = reply.temperatures->bed;
    if (reply.temperatures->bed_target) merged.bed_target = reply.temperatures->bed_target;
    temperatures_ = merged;
    temperatures_at_ = link_.now();
  }
  if (reply.position) {
    position_ = reply.position;
    ++position_reports_;
  }
}

void LineProtocol::note_firmware(const Reply& reply) {
  if (!connected_ && (reply.text.starts_with("echo:Marlin") || reply.text.starts_with("Marlin "))) {
    banner_said_marlin_ = true;
  }
  if (reply.text.find("FIRMWARE_NAME:") != std::string::npos) {
    std::string_view name = std::string_view(reply.text).substr(reply.text.find("FIRMWARE_NAME:") + 14);
    for (const std::string_view next : {" SOURCE_CODE_URL", " FIRMWARE_URL", " PROTOCOL_VERSION"}) {
      name = name.substr(0, name.find(next));
    }
    firmware_.name = std::string(name);
  }
  // "Cap:NAME:1" (Marlin's M115.cpp, Repetier's Commands.cpp), "cap:..." (Teacup's M115).
  if (reply.kind == ReplyKind::other && reply.text.size() > 4 &&
      (reply.text.starts_with("Cap:") || reply.text.starts_with("cap:"))) {
    const std::string_view cap = std::string_view(reply.text).substr(4);
    if (cap == "EMERGENCY_PARSER:1") firmware_.emergency_parser = true;
    if (cap == "AUTOREPORT_TEMP:1") firmware_.autoreport_temperature = true;
  }
}

void LineProtocol::handle_skip(const Reply& reply) {
  // Repetier does not run a line it already has and says "skip N", then "ok"
  // (gcode.cpp checkAndPushCommand): the answer to the unanswered line sent again. It says
  // the same of a line sent before a resend request it is waiting on.
  ++swallow_oks_;
  last_answer_ = link_.now();
  if (connected_ && reply.line_number && *reply.line_number == probe_line_ && probe_line_ <= sent_) {
    accept_through(*reply.line_number);
  }
}

void LineProtocol::handle_error(const Reply& reply) {
  // The refusal a skipped-number probe asked for is not the firmware's trouble.
  if (own_errors_expected_ > 0 && reply.text.find("Line Number") != std::string::npos) {
    --own_errors_expected_;
  } else {
    ++stats_.recoverable_errors;
  }
  if (!connected_) connect_rejected_ = true;
  last_answer_ = link_.now();
  if (connected_ && reply.text.starts_with("E:")) handle_refusal(reply.text, std::nullopt);
}

void LineProtocol::handle_busy(const Reply& reply) {
  // Teacup says "Waiting for target temp" while M116's flag is set, whatever runs: a sign of
  // life only for the G0/G1 that waits, not for a lost ok of another line.
  if (reply.text == "Waiting for target temp" && !heat_wait_in_flight()) return;
  ++stats_.busy_reports;
  if (keepalive_) keepalive_seen_ = true;
  last_keepalive_ = link_.now();
  answered();
}

void LineProtocol::handle_start() {
  restart_seen_ = true;
  ++starts_seen_;
  if (connected_) {
    throw FirmwareStopped(fmt::format(
        "{}: the printer restarted during the job (it sent 'start'), so its position and "
        "heaters were reset",
        link_.name()));
  }
}

void LineProtocol::answered() {
  last_answer_ = link_.now();
  probes_unanswered_ = 0;
}

void LineProtocol::handle_temperature_line(const Reply&) {
  if (!connected_) return;
  if (dialect().temperatures == TemperatureReply::before_ok && !autoreport_on_) {
    if (stale_answers_ > 0) {  // an M105 that ran behind a refused line: its ok follows
      --stale_answers_;
      ++swallow_oks_;
      return;
    }
    // Teacup prints M105's temperatures before its ok, and runs lines in order: the line
    // answers the oldest M105 not yet answered, and every line before that M105 has run
    // (temp.c temp_print, mendel.c).
    for (long n = accepted_ + 1; n <= sent_; ++n) {
      const SentLine* in_flight = line(n);
      if (in_flight == nullptr || !in_flight->is_m105 || in_flight->m105_answered) continue;
      accept_through(n - 1);
      history_[static_cast<std::size_t>(n - history_.front().number)].m105_answered = true;
      answered();
      return;
    }
  }
  // While a command that may run long runs, the firmware's own reports are signs of life
  // (Repetier's each second in M109, an auto-report).
  if (blocking() != Blocking::none) {
    last_keepalive_ = link_.now();
    answered();
    return;
  }
  if (autoreport_on_ || dialect().temperatures != TemperatureReply::on_ok_or_before) return;
  // A firmware unknown to the table may print M105's temperatures on a line of their own and
  // then "ok": that ok then answers the M105.
  for (long n = accepted_ + 1; n <= sent_; ++n) {
    const SentLine* in_flight = line(n);
    if (in_flight != nullptr && in_flight->is_m105) {
      m105_answer_next_ = true;
      return;
    }
  }
}

void LineProtocol::handle_refusal(std::string_view text, std::optional<long> answered_line) {
  ++stats_.refused_commands;
  // The refused line: the one the text names, searched from the newest line written back (a
  // firmware that acknowledges on reading reports it later), else the line this reply answers.
  const SentLine* refused = nullptr;
  const std::optional<GcodeCommand> named = command_named_in(text);
  if (named && !history_.empty()) {
    const long oldest = std::max(history_.front().number, accepted_ - kBlockingReach);
    for (long n = highest_written_; n >= oldest && refused == nullptr; --n) {
      const SentLine* l = line(n);
      if (l == nullptr) continue;
      const GcodeCommand c = parse_gcode_line(l->command);
      if (c.letter == named->letter && c.code == named->code) refused = l;
    }
  }
  if (refused == nullptr) refused = line(answered_line.value_or(accepted_ + 1));
  const std::string what = refused != nullptr ? refused->command : std::string(text);
  if (refused != nullptr && parse_gcode_line(refused->command).is('M', 113)) keepalive_.reset();
  if (refused_.size() < kRefusedKept) refused_.push_back(what);
  if (refused == nullptr) return;
  const GcodeCommand c = parse_gcode_line(refused->command);
  if (!print_needs(c)) return;
  // Where the print stopped is the job's to say (the protocol does not know what was printed).
  throw CommandRefused(fmt::format("{}: the printer refused {} (\"{}\")", link_.name(), refused->command, text), "",
                       refusal_advice(c, dialect()));
}

LineProtocol::Blocking LineProtocol::blocking(long before) const {
  if (lines_in_flight() == 0) return Blocking::none;
  // Marlin answers a command when it is done: it can be running only if unanswered. Teacup
  // and Repetier answer on reading: any of the last lines may be running.
  const long from = dialect().ok_means == OkMeans::executed
                        ? accepted_ + 1
                        : std::max<long>(first_number(), highest_written_ - kBlockingReach + 1);
  const long to = before >= 0 ? std::min(before - 1, sent_) : sent_;
  Blocking found = Blocking::none;
  for (long n = from; n <= to; ++n) {
    const SentLine* l = line(n);
    if (l == nullptr) continue;
    if (l->waits_for_user) return Blocking::user;
    if (l->blocks) found = Blocking::command;
  }
  return found;
}

bool LineProtocol::long_command_in_flight() const { return blocking() != Blocking::none; }

nanoseconds LineProtocol::quiet_for() const {
  return link_.now() - std::max(last_answer_, last_keepalive_);
}

bool LineProtocol::heat_wait_in_flight() const {
  for (long n = accepted_ + 1; n <= sent_; ++n) {
    if (const SentLine* l = line(n); l != nullptr && l->waits_for_heat) return true;
  }
  return false;
}

void LineProtocol::set_accepted(long number) {
  accepted_ = number;
  if (const SentLine* l = line(number)) commands_accepted_ = l->sequence;
}

void LineProtocol::accept_through(long number, bool own_ok) {
  if (number <= accepted_) return;
  mirror_accepted(number, own_ok);
  set_accepted(number);
  stale_left_ = 0;  // the stale requests come before any acceptance of the replay
  same_resend_count_ = 0;
  if (probe_line_ >= 0 && probe_line_ <= number) probe_line_ = -1;
  idle_reported_ = false;
  answered();
}

void LineProtocol::mirror_accepted(long number, bool own_ok) {
  // The planner mirror learns what entered: the last line by its own ok (its link time says
  // when it entered), the ones before it by an answer that came later.
  const nanoseconds now = link_.now();
  for (long n = accepted_ + 1; n <= number; ++n) {
    const SentLine* l = line(n);
    if (l == nullptr) continue;
    if (l->waits_for_moves) mirror_.drained(now);
    if (!l->is_move) continue;
    if (own_ok && n == number) {
      const std::size_t bytes = l->command.size() + 16 + kAnswerBytes;  // "N<n> ", "*<cs>", the ok
      const bool prompt = now <= l->written_at + wire_time(bytes) + options_.lost_ok_margin / 5;
      mirror_.entered(l->written_at, now, l->motion, prompt);
    } else {
      mirror_.entered_unseen(l->written_at, l->motion);
    }
  }
}

void LineProtocol::handle_ok(const Reply& reply) {
  if (!connected_) {
    // The M110 exchange's oks teach nothing about the ok after a resend request: an ok there
    // may be a repeated M110's (the print's resends teach it).
    if (request_open_) {
      request_open_ = holding_ = false;
      return;
    }
    connect_ok_ = true;
    return;
  }
  if (swallow_oks_ > 0) {  // the ok of a Repetier "skip"
    --swallow_oks_;
    return;
  }
  const bool accepts_new = reply.line_number && *reply.line_number > accepted_;
  if (request_open_) {
    // The request's own ok is a bare "ok" (ADVANCED_OK's fields at most) and comes right after
    // it; an ok read before any line was written since cannot answer the replay: it is the
    // request's, or a line's the request already counted as accepted. Either way it accepts
    // nothing more. One read after a line was written may be that line's: it teaches nothing.
    const bool bare = !accepts_new && !reply.temperatures && !reply.refusal;
    if (bare && line_writes() == writes_at_request_) {
      settle_request(true);
      return;
    }
    if (bare) {
      request_open_ = holding_ = false;
    } else {
      settle_request(false);
    }
  }
  // Teacup's ok carries its refusal: "ok E: Bad M-code 190" answers the oldest line, which is
  // accepted (and run, to no effect) all the same.
  if (reply.refusal) {
    const long refused = accepted_ + 1;
    if (accepted_ < sent_) accept_through(refused);
    handle_refusal(*reply.refusal, refused);
    return;
  }
  const bool m105_answer = std::exchange(m105_answer_next_, false);
  if (reply.line_number) {
    // ADVANCED_OK ("ok N12 P15 B3") and Repetier's "ok 12": N is the last line the firmware
    // accepted, whatever happened to earlier oks. Only ADVANCED_OK reports buffer space.
    if (reply.planner_free || reply.queue_free) advanced_ok_ = true;
    if (reply.queue_free) queue_free_ = *reply.queue_free;
    const long n = std::min(*reply.line_number, sent_);
    if (n > accepted_) {
      accept_through(n, true);
    } else if (!reply.temperatures) {
      ++stats_.duplicate_oks;
    }
    return;
  }
  if (reply.temperatures || m105_answer) {
    // `ok T:` (or "T:" just before the ok) answers the oldest M105 in flight; the firmware
    // works in order, so every line before it was accepted even if its ok was lost.
    for (long n = accepted_ + 1; n <= sent_; ++n) {
      const SentLine* in_flight = line(n);
      if (in_flight != nullptr && in_flight->is_m105) {
        accept_through(n, n == accepted_ + 1);
        return;
      }
    }
  }
  if (accepted_ < sent_) {
    accept_through(accepted_ + 1, true);
  } else {
    ++stats_.duplicate_oks;
  }
}

void LineProtocol::handle_resend(long wanted) {
  // The ok right after this request teaches whether the firmware sends one only where it can
  // be nothing else: no line before `wanted` still owes its own ok (a move still queued, an ok
  // lost), and the replay of `wanted` not yet written since the request that started it.
  const bool stale = wanted == last_resend_ && stale_left_ > 0;
  open_request(wanted - 1 <= accepted_ && !(stale && resent_since_request_));
  if (!connected_) {
    connect_rejected_ = connect_resend_ = true;
    return;
  }
  if (stale) {
    --stale_left_;
    ++stats_.stale_resends;
    return;
  }
  if (wanted > assigned_ + 1 || wanted < 1) {
    throw PrinterError(fmt::format(
        "{}: the printer asked for line {}, but the host numbered only {} lines: another program "
        "may be talking to it",
        link_.name(), wanted, assigned_));
  }
  if (wanted <= assigned_ && line(wanted) == nullptr) {
    throw PrinterError(fmt::format(
        "{}: the printer asked for line {}, which is older than the {} lines the host keeps",
        link_.name(), wanted, kHistoryBehind));
  }
  if (wanted == last_resend_) {
    // Only a request that answers the line sent again counts toward a loop: a probe is
    // answered with the same request without anything having been resent.
    if (resent_since_request_ && ++same_resend_count_ > options_.max_resends_of_one_line) {
      throw LinkError(fmt::format(
          "{}: the printer asked for line {} {} times in a row: the link corrupts nearly every "
          "line; check the cable and try a lower --baud",
          link_.name(), wanted, same_resend_count_));
    }
  } else {
    last_resend_ = wanted;
    same_resend_count_ = 1;
  }
  int stale_probes = 0;
  if (!dialect().checks_line_numbers && !probes_before_.empty()) {
    // Teacup answers a wrong-checksum probe with "rs N<one past the last line it ran>": past
    // every line written before the probe, it only says how far it got.
    if (wanted > probes_before_.front()) {
      probes_before_.pop_front();
      if (wanted - 1 > accepted_) accept_through(wanted - 1);
      answered();
      return;
    }
    // A line written before a probe was refused, or lost: it is sent again, and each probe
    // still out will draw the same request (it comes before the replay): stale.
    stale_probes = static_cast<int>(probes_before_.size());
    probes_before_.clear();
  }
  resent_since_request_ = false;
  ++stats_.resend_requests;
  if (!dialect().checks_line_numbers) {
    // Teacup ran the lines written after the refused one all the same (it ignores their
    // numbers): they are not sent again, and their answers come (gcode_parse.c). Only the
    // engine's own M105 can be there, one line being in flight otherwise.
    while (sent_ > wanted && line(sent_) != nullptr && line(sent_)->engine) {
      ++stale_answers_;
      remove_engine_line(sent_--);
    }
  }
  // Lines written after `wanted` are rejected too, each with its own request for `wanted`.
  stale_left_ = (dialect().checks_line_numbers ? static_cast<int>(std::max<long>(0, sent_ - wanted)) : 0) +
                stale_probes;
  if (wanted - 1 > accepted_) mirror_accepted(wanted - 1, false);
  set_accepted(wanted - 1);
  sent_ = wanted - 1;
  if (probe_line_ >= wanted) probe_line_ = -1;  // the probe is resent with the rest
  idle_reported_ = false;
  answered();
}

long LineProtocol::line_writes() const { return stats_.lines_sent + stats_.lines_resent; }

void LineProtocol::open_request(bool teaches) {
  request_open_ = true;
  request_teaches_ = teaches;
  writes_at_request_ = line_writes();
  // The replay waits for the request's ok where one is expected or not yet known (it comes at
  // once where it comes): so the replay's own ok is never taken for it.
  holding_ = connected_ && trailing_ok_score_ >= 0;
  hold_until_ = link_.now() + options_.resend_ok_grace;
}

void LineProtocol::settle_request(bool ok_followed) {
  if (connected_ && (!ok_followed || request_teaches_)) {
    trailing_ok_score_ = std::clamp(trailing_ok_score_ + (ok_followed ? 1 : -1), -kTrailingOkCap, kTrailingOkCap);
  }
  request_open_ = holding_ = false;
}

void LineProtocol::check_silence() {
  const nanoseconds now = link_.now();
  if (lines_in_flight() == 0) {
    last_answer_ = now;
    probes_unanswered_ = 0;
    idle_reported_ = false;
    return;
  }
  const nanoseconds quiet = now - std::max(last_write_, last_answer_);
  stats_.longest_silence = std::max(stats_.longest_silence, quiet);
  // A firmware that keeps alive at a known interval is idle once that interval passes
  // without a word: a lost ok is probed for then, not after the full probe interval.
  nanoseconds probe_after(options_.probe_after);
  if (keepalive_ && keepalive_seen_) probe_after = std::min(probe_after, *keepalive_ + kKeepaliveMargin);
  const bool probe_out = probe_line_ > accepted_ && probe_line_ <= sent_;
  const Blocking running = blocking();
  const Blocking ahead_of_probe = probe_out ? blocking(probe_line_) : Blocking::none;
  if (idle_reported_ && !probe_out) {
    probe();  // the firmware says it is idle while lines are in flight: one was lost
    return;
  }
  // The oldest line's ok is due by the motion model: probed for once, soon after it is late.
  if (const std::optional<nanoseconds> overdue = model_probe_at()) {
    if (now >= *overdue) {
      history_[static_cast<std::size_t>(accepted_ + 1 - history_.front().number)].probed = true;
      probe();
    }
    return;
  }
  if (quiet < probe_after) return;
  if (ahead_of_probe != Blocking::none) {
    // The probe waits in the firmware's queue behind a command that may run long.
    if (ahead_of_probe == Blocking::command && now - last_answer_ >= nanoseconds(options_.long_command_timeout)) {
      throw LinkError(fmt::format(
          "{}: the printer stopped answering: nothing for {:.0f} s while it ran a long command "
          "({}); check that it is powered and connected",
          link_.name(), seconds(now - last_answer_), line(accepted_ + 1) ? line(accepted_ + 1)->command : ""));
    }
    if (quiet >= probe_after * kBlockedProbeSpacing && probes_unanswered_ < kBlockedProbes) probe();
    return;
  }
  if (running == Blocking::none && probes_unanswered_ >= options_.max_probes) {
    throw LinkError(fmt::format(
        "{}: the printer stopped answering: nothing for {:.0f} s and {} probes unanswered; check "
        "that it is powered and connected",
        link_.name(), seconds(now - last_answer_), probes_unanswered_));
  }
  probe();
}

nanoseconds LineProtocol::wire_time(std::size_t bytes) const {
  if (options_.baud <= 0) return nanoseconds(0);
  return std::chrono::duration_cast<nanoseconds>(
      std::chrono::duration<double>(10.0 * static_cast<double>(bytes) / options_.baud));
}

std::optional<nanoseconds> LineProtocol::model_probe_at() const {
  if (accepted_ >= sent_) return std::nullopt;
  const SentLine* oldest = line(accepted_ + 1);
  const bool probe_out = probe_line_ > accepted_ && probe_line_ <= sent_;
  if (oldest == nullptr || oldest->probed || probe_out || blocking() != Blocking::none) return std::nullopt;
  return ok_overdue_at(*oldest);
}

std::optional<nanoseconds> LineProtocol::ok_overdue_at(const SentLine& l) const {
  // Not for a command that may run long or whose answer may be long (M115's capabilities),
  // nor once the firmware said it is busy with it.
  if (l.blocks || l.waits_for_user || !l.answer_is_short || l.written_at <= last_keepalive_) {
    return std::nullopt;
  }
  const nanoseconds written = l.written_at;
  const nanoseconds transit = wire_time(l.command.size() + 16 + kAnswerBytes);
  nanoseconds due = written + transit;
  if (l.waits_for_moves) {
    due = mirror_.dry_at(written) + transit;
  } else if (l.is_move) {
    due = std::max(due, mirror_.room_at(written) + wire_time(kAnswerBytes));
  }
  // No probe while the planner still holds more than the lead: the printer has work, and the
  // line may only be waiting for room.
  return std::max(due + options_.lost_ok_margin, mirror_.dry_at(written) - options_.refill_lead);
}

void LineProtocol::probe() {
  ++probes_unanswered_;
  ++stats_.probes;
  idle_reported_ = false;
  const LostOkProbe kind = dialect().probe;
  if (kind == LostOkProbe::same_line_again && accepted_ + 1 == sent_) {
    // Repetier: the unanswered line again, with its own number, draws "skip N" if it arrived
    // and runs now if it did not.
    probe_line_ = sent_;
    transmit(sent_);
    return;
  }
  if (kind == LostOkProbe::wrong_checksum) {
    // Teacup: a line whose checksum is wrong on purpose is refused with "rs N<n>", n one past
    // the last line it ran, and runs nothing (printer/firmware_dialect.h). Not stored.
    const std::string body = fmt::format("N{} M105", sent_ + 1);
    unsigned char sum = 0;
    for (const char c : body) sum ^= static_cast<unsigned char>(c);
    const std::string framed = fmt::format("{}*{}\n", body, sum ^ 0x55);
    probes_before_.push_back(sent_);
    link_.write(framed);
    stats_.bytes_written += static_cast<long>(framed.size());
    last_write_ = link_.now();
    return;
  }
  const bool m105_out = probe_line_ > accepted_ && probe_line_ <= sent_;
  if (kind == LostOkProbe::skipped_number || m105_out) {
    // A line one number past the next: refused with "Resend: <the line the firmware wants>",
    // which says exactly what it has. Not stored: it is a question, never a command.
    const std::string framed = frame_line(sent_ + 2, "M105") + "\n";
    link_.write(framed);
    stats_.bytes_written += static_cast<long>(framed.size());
    ++own_errors_expected_;
    last_write_ = link_.now();
    return;
  }
  // A numbered M105 right after the last line written: its "ok T:" says that everything up
  // to it was accepted. Lines not yet written move up one number.
  insert_engine_line("M105");
  probe_line_ = sent_ + 1;
  transmit(sent_ + 1);
}

void LineProtocol::remove_engine_line(long number) {
  const auto at = history_.begin() + static_cast<std::ptrdiff_t>(number - first_number());
  for (auto it = history_.erase(at); it != history_.end(); ++it) --it->number;
  --assigned_;
  if (probe_line_ == number) probe_line_ = -1;
  if (probe_line_ > number) --probe_line_;
}

void LineProtocol::insert_engine_line(std::string command) {
  SentLine engine;
  engine.engine = true;
  engine.number = sent_ + 1;
  engine.command = std::move(command);
  const GcodeCommand parsed = parse_gcode_line(engine.command);
  engine.is_m105 = parsed.is('M', 105);
  engine.answer_is_short = answer_is_short(parsed);
  engine.blocks = command_blocks(engine.command);
  if (const SentLine* before = line(sent_)) engine.sequence = before->sequence;
  const auto at = history_.begin() + static_cast<std::ptrdiff_t>(engine.number - first_number());
  for (auto it = history_.insert(at, engine) + 1; it != history_.end(); ++it) ++it->number;
  ++assigned_;
  if (probe_line_ > sent_) ++probe_line_;
}

void LineProtocol::use_keepalive(std::chrono::seconds interval) {
  if (dialect().firmware != Firmware::marlin || keepalive_) return;
  insert_engine_line(fmt::format("M113 S{}", interval.count()));
  keepalive_ = std::chrono::duration_cast<nanoseconds>(interval);
  keepalive_seen_ = false;
}

bool LineProtocol::request_temperatures(std::chrono::seconds every) {
  if (autoreport_on_) return true;
  if (firmware_.autoreport_temperature && dialect().autoreport_usable) {
    insert_engine_line(fmt::format("M155 S{}", every.count()));
    autoreport_on_ = true;
    return true;
  }
  // One M105 in the stream at a time is enough.
  for (long n = accepted_ + 1; n <= assigned_; ++n) {
    const SentLine* l = line(n);
    if (l != nullptr && l->is_m105) return false;
  }
  insert_engine_line("M105");
  return false;
}

bool LineProtocol::wait_acknowledged_for(milliseconds timeout) {
  const nanoseconds deadline = link_.now() + timeout;
  wait_until([&] { return accepted_ >= assigned_ || link_.now() >= deadline; }, deadline);
  return accepted_ >= assigned_;
}

void LineProtocol::drop_unsent() {
  // Lines never written, or written before a resend request and not since.
  while (!history_.empty() && history_.back().number > sent_) history_.pop_back();
  assigned_ = sent_;
  if (probe_line_ > sent_) probe_line_ = -1;
}

void LineProtocol::abandon_unacknowledged() {
  drop_unsent();
  if (accepted_ >= sent_) return;
  // The firmware takes an M110 line whatever number it expected and counts from its N.
  const long number = sent_ + 1;
  SentLine resync;
  resync.number = number;
  resync.command = fmt::format("M110 N{}", number);
  if (const SentLine* before = line(sent_)) resync.sequence = before->sequence;
  history_.push_back(resync);
  assigned_ = number;
  set_accepted(number - 1);
  stale_left_ = 0;
  last_resend_ = -1;
  same_resend_count_ = 0;
  request_open_ = holding_ = false;
  probe_line_ = -1;
  m105_answer_next_ = false;
  transmit(number);
}

void LineProtocol::emergency(std::string_view command) {
  std::string bytes(command);
  bytes += '\n';
  link_.write(bytes);
  stats_.bytes_written += static_cast<long>(bytes.size());
}

std::optional<ReportedPosition> LineProtocol::query_position() {
  const long before = position_reports_;
  send(dialect().has_m400 ? "M400" : "G4 P0");
  send("M114");
  wait_acknowledged();
  if (position_reports_ == before) {
    // The report comes before M114's ok; a late one still counts.
    const nanoseconds deadline = link_.now() + nanoseconds(options_.probe_after);
    while (position_reports_ == before && link_.now() < deadline) {
      read_once(options_.tick);
      if (on_wait) on_wait();
    }
  }
  if (position_reports_ == before) return std::nullopt;
  return position_;
}

void LineProtocol::write_connect_line() {
  const std::string framed = frame_line(0, "M110 N0") + "\n";
  link_.write(framed);
  stats_.bytes_written += static_cast<long>(framed.size());
}

void LineProtocol::connect(milliseconds boot_wait) {
  connected_ = false;
  // Answered without a banner: the probe reset the count. After a banner (Teacup's ends with an
  // ok of its own, mendel.c) or a refusal, the exchange of M110s does.
  if (!probe_until_booted(boot_wait) && !exchange_m110()) {
    throw LinkError(fmt::format(
        "{}: the printer does not answer (no 'ok' to M110 in {} tries{}); check that it is on, "
        "that --baud matches its firmware (115200 or 250000) and that no other program uses "
        "the port",
        link_.name(), kConnectTries,
        stats_.unreadable_lines > 0
            ? fmt::format(", {} unreadable reply lines: likely the wrong --baud", stats_.unreadable_lines)
            : std::string()));
  }
  // An ok that was not M110's (Teacup's banner ends with one, mendel.c) must not be taken for
  // M115's: what comes in a short quiet after is swallowed.
  const nanoseconds quiet = link_.now() + nanoseconds(options_.resend_ok_grace);
  while (link_.now() < quiet) {
    read_once(std::chrono::duration_cast<milliseconds>(quiet - link_.now()) + milliseconds(1));
  }
  start_numbering();
  identify_firmware();
}

bool LineProtocol::probe_until_booted(milliseconds boot_wait) {
  // A board that resets as its port opens (DTR: Arduino-style boards) says `start` once booted,
  // Marlin its settings after, then listens; one that does not (native USB) says nothing and
  // is listening already. So M110 N0 goes out at once, as a probe: an ok to it with no `start`
  // before is a board that is up, and the wait for a banner ends there. A board in its
  // bootloader loses the probe; its `start` comes, then silence once the banner is over, and
  // the M110 exchange follows. The probe goes once within boot_wait (printcore and OctoPrint
  // also say their first hello at once): an ATmega2560's stk500v2 bootloader stays in itself
  // while bytes keep arriving, and starts the firmware only after F_CPU/2 polls with none
  // (recchar_timeout in stk500boot.c).
  const nanoseconds start = link_.now();
  const long starts_before = starts_seen_;
  connect_ok_ = false;
  connect_rejected_ = connect_resend_ = false;
  request_open_ = holding_ = false;
  write_connect_line();
  while (link_.now() - start < nanoseconds(boot_wait)) {
    const auto left = std::chrono::duration_cast<milliseconds>(nanoseconds(boot_wait) - (link_.now() - start));
    const bool had_start = starts_seen_ > starts_before;
    const std::string bytes = link_.read(std::clamp(left, milliseconds(1), milliseconds(300)));
    if (bytes.empty() && had_start) break;  // the banner is over
    partial_ += bytes;
    handle_buffered();
    if (starts_seen_ == starts_before && (connect_ok_ || connect_rejected_)) break;  // the probe's answer
  }
  return connect_ok_ && starts_seen_ == starts_before;
}

bool LineProtocol::exchange_m110() {
  // M110 N0 resets the firmware's count whatever it was; retried when noise corrupts it.
  for (int attempt = 0; attempt < kConnectTries; ++attempt) {
    if (connect_rejected_) {
      // The refusal is "Error:...", then "Resend: n", then on some firmwares an ok (Marlin's
      // queue.cpp gcode_line_error, flush_and_request_resend; Teacup's and Repetier's have no
      // Error line): the next M110 goes once it is all in, or its ok passes for the refusal's.
      const nanoseconds grace = link_.now() + nanoseconds(options_.resend_ok_grace);
      while ((!connect_resend_ || request_open_) && link_.now() < grace) read_once(options_.tick);
    }
    connect_ok_ = false;
    connect_rejected_ = connect_resend_ = false;
    request_open_ = holding_ = false;
    write_connect_line();
    const nanoseconds deadline = link_.now() + nanoseconds(options_.probe_after);
    while (!connect_ok_ && !connect_rejected_ && link_.now() < deadline) read_once(options_.tick);
    if (connect_ok_ && !connect_rejected_) return true;
  }
  return false;
}

void LineProtocol::start_numbering() {
  history_.clear();
  assigned_ = sent_ = accepted_ = highest_written_ = 0;
  commands_sent_ = commands_accepted_ = 0;
  stale_left_ = 0;
  last_resend_ = -1;
  same_resend_count_ = 0;
  probe_line_ = -1;
  probes_unanswered_ = 0;
  swallow_oks_ = 0;
  m105_answer_next_ = idle_reported_ = autoreport_on_ = keepalive_seen_ = false;
  own_errors_expected_ = 0;
  keepalive_.reset();
  last_keepalive_ = nanoseconds(-1);
  teacup_heat_pending_ = false;
  stale_answers_ = 0;
  probes_before_.clear();
  request_open_ = holding_ = false;
  clock_ = PrintClock(options_.motion);
  mirror_ = PlannerMirror(dialect_of(Firmware::unknown).planner_depth);
  connected_ = true;
  last_write_ = last_answer_ = link_.now();
}

void LineProtocol::identify_firmware() {
  firmware_ = FirmwareInfo{};
  send("M115");
  wait_acknowledged();
  // A reply's lines may come after the ok (Repetier prints on executing).
  const nanoseconds settle = link_.now() + nanoseconds(options_.resend_ok_grace);
  while (firmware_.name.empty() && link_.now() < settle) read_once(options_.tick);
  firmware_.firmware = recognise_firmware(firmware_.name);
  if (firmware_.firmware == Firmware::unknown) {
    firmware_.firmware = banner_said_marlin_ ? Firmware::marlin : options_.assumed_firmware;
  }
  mirror_.set_depth(dialect().planner_depth);
  // Where learning starts: the dialect's answer, unless this engine has learnt already.
  if (const auto known = dialect().ok_after_resend; known && trailing_ok_score_ == 0) {
    trailing_ok_score_ = *known ? kTrailingOkPrior : -kTrailingOkPrior;
  }
}

}  // namespace printer
