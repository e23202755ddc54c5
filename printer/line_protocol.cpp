#include "printer/line_protocol.h"

#include <algorithm>
#include <cctype>

#include <fmt/core.h>

#include "printer/error.h"
#include "printer/gcode_line.h"

namespace printer {

namespace {

using std::chrono::milliseconds;
using std::chrono::nanoseconds;

// Lines kept below the last accepted one, for resend requests that arrive late.
constexpr long kHistoryBehind = 4096;
// A blocking command may sit in the firmware's queue (BUFSIZE 4 by default, up to 32 in big
// builds) while later lines are already acknowledged; until this many lines were written after
// it, silence may still be that command running.
constexpr long kBlockingReach = 40;
// M110 attempts at connect before the printer counts as not answering.
constexpr int kConnectTries = 5;

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

bool is_m105(std::string_view command) {
  const GcodeCommand parsed = parse_gcode_line(command);
  return parsed.is('M', 105);
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

LineProtocol::LineProtocol(Link& link, ProtocolOptions options) : link_(link), options_(options) {
  if (options_.window == 0) options_.window = 1;
  if (options_.tick.count() <= 0) options_.tick = milliseconds(100);
  last_activity_ = link_.now();
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
  std::size_t allowed = options_.window;
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
  if (sent->blocks) last_blocking_line_ = std::max(last_blocking_line_, number);
  if (sent->waits_for_user) last_user_wait_line_ = std::max(last_user_wait_line_, number);
  last_activity_ = link_.now();
}

void LineProtocol::send(std::string_view command) {
  SentLine next;
  next.number = ++assigned_;
  next.command = std::string(command);
  next.blocks = command_blocks(command);
  next.waits_for_user = command_waits_for_user(command);
  next.is_m105 = is_m105(command);
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
    if (expect_trailing_ok_ && trailing_ok_seen_ == 0 && now >= hold_until_) {
      // No ok followed the resend request in time: this firmware does not send one.
      expect_trailing_ok_ = false;
      ++trailing_ok_missed_;
    }
    const bool holding = expect_trailing_ok_ && trailing_ok_seen_ == 0;
    while (!holding && pending_replay() && lines_in_flight() < allowed_in_flight()) {
      transmit(sent_ + 1);
    }
    if (done()) return;
    milliseconds wait = options_.tick;
    if (holding) {
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

void LineProtocol::read_once(milliseconds timeout) { feed(link_.read(timeout)); }

void LineProtocol::feed(const std::string& bytes) {
  if (bytes.empty()) return;
  partial_ += bytes;
  std::size_t begin = 0;
  for (std::size_t i = 0; i < partial_.size(); ++i) {
    if (partial_[i] != '\n' && partial_[i] != '\r') continue;
    const std::string_view text(partial_.data() + begin, i - begin);
    begin = i + 1;
    if (text.find_first_not_of(" \t") == std::string_view::npos) continue;
    handle(classify_reply(text));
  }
  partial_.erase(0, begin);
  // A line end lost to noise must not grow the buffer without bound.
  if (partial_.size() > 4096) partial_.clear();
}

void LineProtocol::handle(const Reply& reply) {
  if (on_reply) on_reply(reply);
  const bool readable = reply.kind != ReplyKind::other || is_readable(reply.text);
  if (readable) {
    last_activity_ = link_.now();
    probes_unanswered_ = 0;
  } else {
    stats_.unreadable_lines++;
  }
  // Marlin prints a resend request and its ok back to back: anything else in between means
  // this request has no ok.
  if (expect_trailing_ok_ && reply.kind != ReplyKind::ok) {
    expect_trailing_ok_ = false;
    ++trailing_ok_missed_;
  }
  if (reply.temperatures) {
    Temperatures merged = temperatures_.value_or(Temperatures{});
    if (reply.temperatures->hotend) merged.hotend = reply.temperatures->hotend;
    if (reply.temperatures->hotend_target) merged.hotend_target = reply.temperatures->hotend_target;
    if (reply.temperatures->bed) merged.bed = reply.temperatures->bed;
    if (reply.temperatures->bed_target) merged.bed_target = reply.temperatures->bed_target;
    temperatures_ = merged;
  }
  switch (reply.kind) {
    case ReplyKind::ok:
      handle_ok(reply);
      break;
    case ReplyKind::resend:
      handle_resend(*reply.line_number);
      break;
    case ReplyKind::error:
      ++stats_.recoverable_errors;
      if (!connected_) connect_rejected_ = true;
      break;
    case ReplyKind::fatal:
      throw PrinterError(fmt::format("{}: the printer stopped: {}", link_.name(), reply.text));
    case ReplyKind::busy:
      ++stats_.busy_reports;
      break;
    case ReplyKind::start:
      restart_seen_ = true;
      if (connected_) {
        throw PrinterError(fmt::format(
            "{}: the printer restarted during the job (it sent 'start'), so its position and "
            "heaters were reset",
            link_.name()));
      }
      break;
    case ReplyKind::position:
      position_ = reply.position;
      ++position_reports_;
      break;
    case ReplyKind::other:
      if (reply.text.starts_with("FIRMWARE_NAME:")) {
        std::string_view name = std::string_view(reply.text).substr(14);
        const auto end = name.find(" SOURCE_CODE_URL");
        firmware_.name = std::string(name.substr(0, end));
      } else if (reply.text.starts_with("Cap:")) {
        if (reply.text == "Cap:EMERGENCY_PARSER:1") firmware_.emergency_parser = true;
        if (reply.text == "Cap:AUTOREPORT_TEMP:1") firmware_.autoreport_temperature = true;
      }
      break;
    default:
      break;
  }
}

bool LineProtocol::long_command_in_flight() const {
  for (long n = accepted_ + 1; n <= sent_; ++n) {
    const SentLine* l = line(n);
    if (l != nullptr && l->blocks) return true;
  }
  return false;
}

void LineProtocol::set_accepted(long number) {
  accepted_ = number;
  if (const SentLine* l = line(number)) commands_accepted_ = l->sequence;
}

void LineProtocol::accept_through(long number) {
  if (number <= accepted_) return;
  set_accepted(number);
  stale_left_ = 0;  // the stale requests come before any acceptance of the replay
  same_resend_count_ = 0;
  if (probe_line_ >= 0 && probe_line_ <= number) probe_line_ = -1;
}

void LineProtocol::handle_ok(const Reply& reply) {
  if (!connected_) {
    if (expect_trailing_ok_) {
      expect_trailing_ok_ = false;
      ++trailing_ok_seen_;
      return;
    }
    connect_ok_ = true;
    return;
  }
  const bool accepts_new = reply.line_number && *reply.line_number > accepted_;
  if (expect_trailing_ok_ && !accepts_new) {
    expect_trailing_ok_ = false;
    ++trailing_ok_seen_;
    return;
  }
  if (reply.line_number) {
    // ADVANCED_OK: N is the last line the firmware accepted, whatever happened to earlier oks.
    advanced_ok_ = true;
    if (reply.queue_free) queue_free_ = *reply.queue_free;
    const long n = std::min(*reply.line_number, sent_);
    if (n > accepted_) {
      accept_through(n);
    } else if (!reply.temperatures) {
      ++stats_.duplicate_oks;
    }
    return;
  }
  if (reply.temperatures) {
    // `ok T:` answers the oldest M105 in flight; the firmware works in order, so every line
    // before it was accepted even if its ok was lost.
    for (long n = accepted_ + 1; n <= sent_; ++n) {
      const SentLine* in_flight = line(n);
      if (in_flight != nullptr && in_flight->is_m105) {
        accept_through(n);
        return;
      }
    }
  }
  if (accepted_ < sent_) {
    accept_through(accepted_ + 1);
  } else {
    ++stats_.duplicate_oks;
  }
}

void LineProtocol::handle_resend(long wanted) {
  const nanoseconds now = link_.now();
  if (trailing_ok_seen_ > 0 || trailing_ok_missed_ < 3) {
    expect_trailing_ok_ = true;
    hold_until_ = now + options_.resend_ok_grace;
  }
  if (!connected_) {
    connect_rejected_ = true;
    return;
  }
  if (stale_left_ > 0 && wanted == last_resend_) {
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
    if (++same_resend_count_ > options_.max_resends_of_one_line) {
      throw LinkError(fmt::format(
          "{}: the printer asked for line {} {} times in a row: the link corrupts nearly every "
          "line; check the cable and try a lower --baud",
          link_.name(), wanted, same_resend_count_));
    }
  } else {
    last_resend_ = wanted;
    same_resend_count_ = 1;
  }
  ++stats_.resend_requests;
  // Lines written after `wanted` are rejected too, each with its own request for `wanted`.
  stale_left_ = static_cast<int>(std::max<long>(0, sent_ - wanted));
  set_accepted(wanted - 1);
  sent_ = wanted - 1;
}

void LineProtocol::check_silence() {
  const nanoseconds now = link_.now();
  if (lines_in_flight() == 0) {
    last_activity_ = now;
    probes_unanswered_ = 0;
    return;
  }
  if (last_user_wait_line_ > 0 && last_user_wait_line_ > highest_written_ - kBlockingReach) {
    return;  // M0 and friends wait for the user as long as it takes
  }
  const bool blocking = last_blocking_line_ > 0 && last_blocking_line_ > highest_written_ - kBlockingReach;
  const nanoseconds limit = blocking ? nanoseconds(options_.long_command_timeout)
                                     : nanoseconds(options_.probe_after);
  if (now - last_activity_ < limit) return;
  if (probes_unanswered_ >= options_.max_probes) {
    throw LinkError(fmt::format(
        "{}: the printer stopped answering: nothing for {:.0f} s and {} M105 probes "
        "unanswered; check that it is powered and connected",
        link_.name(), seconds(now - last_activity_) + seconds(limit) * probes_unanswered_,
        probes_unanswered_));
  }
  ++probes_unanswered_;
  ++stats_.probes;
  // The probe is a numbered M105 right after the last line written: its `ok T:` says exactly
  // that everything up to it was accepted. Lines not yet written move up one number.
  SentLine probe;
  probe.number = sent_ + 1;
  probe.command = "M105";
  probe.is_m105 = true;
  if (const SentLine* before = line(sent_)) probe.sequence = before->sequence;
  const auto at = history_.begin() + static_cast<std::ptrdiff_t>(probe.number - first_number());
  for (auto it = history_.insert(at, probe) + 1; it != history_.end(); ++it) ++it->number;
  ++assigned_;
  probe_line_ = probe.number;
  transmit(probe.number);
  last_activity_ = now;
}

void LineProtocol::emergency(std::string_view command) {
  std::string bytes(command);
  bytes += '\n';
  link_.write(bytes);
  stats_.bytes_written += static_cast<long>(bytes.size());
}

std::optional<ReportedPosition> LineProtocol::query_position() {
  const long before = position_reports_;
  send("M400");
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

void LineProtocol::connect(milliseconds boot_wait) {
  connected_ = false;
  const nanoseconds start = link_.now();
  // A board resets when its port opens; Marlin prints `start` and its settings, then listens.
  while (link_.now() - start < nanoseconds(boot_wait)) {
    const auto left = std::chrono::duration_cast<milliseconds>(nanoseconds(boot_wait) - (link_.now() - start));
    const bool had_start = restart_seen_;
    const std::string bytes = link_.read(std::clamp(left, milliseconds(1), milliseconds(300)));
    if (bytes.empty() && had_start) break;  // the banner is over
    feed(bytes);
  }

  // M110 N0 resets the firmware's count whatever it was; retried when noise corrupts it.
  bool reset = false;
  for (int attempt = 0; attempt < kConnectTries && !reset; ++attempt) {
    connect_ok_ = false;
    connect_rejected_ = false;
    expect_trailing_ok_ = false;
    const std::string framed = frame_line(0, "M110 N0") + "\n";
    link_.write(framed);
    stats_.bytes_written += static_cast<long>(framed.size());
    const nanoseconds deadline = link_.now() + nanoseconds(options_.probe_after);
    while (!connect_ok_ && !connect_rejected_ && link_.now() < deadline) read_once(options_.tick);
    if (connect_rejected_) {
      // Swallow the ok that may follow the resend request before trying again.
      const nanoseconds grace = link_.now() + nanoseconds(options_.resend_ok_grace);
      while (expect_trailing_ok_ && link_.now() < grace) read_once(options_.tick);
      expect_trailing_ok_ = false;
      continue;
    }
    reset = connect_ok_;
  }
  if (!reset) {
    throw LinkError(fmt::format(
        "{}: the printer does not answer (no 'ok' to M110 in {} tries{}); check that it is on, "
        "that --baud matches its firmware (115200 or 250000) and that no other program uses "
        "the port",
        link_.name(), kConnectTries,
        stats_.unreadable_lines > 0
            ? fmt::format(", {} unreadable reply lines: likely the wrong --baud", stats_.unreadable_lines)
            : std::string()));
  }
  history_.clear();
  assigned_ = sent_ = accepted_ = highest_written_ = 0;
  commands_sent_ = commands_accepted_ = 0;
  stale_left_ = 0;
  last_resend_ = -1;
  same_resend_count_ = 0;
  probe_line_ = -1;
  probes_unanswered_ = 0;
  last_blocking_line_ = last_user_wait_line_ = 0;
  connected_ = true;
  last_activity_ = link_.now();
  send("M115");
  wait_acknowledged();
}

}  // namespace printer
