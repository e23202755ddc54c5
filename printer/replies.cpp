#include "printer/replies.h"

#include <array>
#include <cctype>
#include <charconv>

#include "base/text.h"

namespace printer {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\0'; }

// The same blanks for trim: white space and NUL, line noise on a serial port.
constexpr std::string_view kReplyBlanks{" \t\r\n\0", 5};

std::string_view trim(std::string_view s) { return base::trim(s, kReplyBlanks); }

bool starts_with_nocase(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(s[i])) !=
        std::tolower(static_cast<unsigned char>(prefix[i]))) {
      return false;
    }
  }
  return true;
}

bool contains_nocase(std::string_view s, std::string_view needle) {
  if (needle.size() > s.size()) return false;
  for (std::size_t i = 0; i + needle.size() <= s.size(); ++i) {
    if (starts_with_nocase(s.substr(i), needle)) return true;
  }
  return false;
}

// Reads a number at the front of `s`, advancing past it.
std::optional<double> take_double(std::string_view& s) {
  double value = 0;
  const char* begin = s.data();
  if (!s.empty() && s.front() == '+') ++begin;
  const auto [end, ec] = std::from_chars(begin, s.data() + s.size(), value);
  if (ec != std::errc()) return std::nullopt;
  s.remove_prefix(static_cast<std::size_t>(end - s.data()));
  return value;
}

std::optional<long> take_long(std::string_view& s) {
  long value = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc()) return std::nullopt;
  s.remove_prefix(static_cast<std::size_t>(end - s.data()));
  return value;
}

// Finds `key` ("T:", "B:") where it starts a word, so that "B@:" or "TargetBed:" do not match;
// Teacup separates its words with commas ("X:0.000,Y:0.000").
std::size_t find_word(std::string_view s, std::string_view key) {
  for (std::size_t at = s.find(key); at != std::string_view::npos; at = s.find(key, at + 1)) {
    if (at == 0 || is_blank(s[at - 1]) || s[at - 1] == ':' || s[at - 1] == ',') return at;
  }
  return std::string_view::npos;
}

// "E: Bad M-code 190" (Teacup's refusal), not "E:1.20" (an extruder position).
bool is_teacup_error(std::string_view s) {
  if (!s.starts_with("E:")) return false;
  s.remove_prefix(2);
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  return !s.empty() && std::isalpha(static_cast<unsigned char>(s.front()));
}

// "T:200.24 /200.00": the value after `key` and, when a '/' follows, the target.
bool read_heater(std::string_view s, std::string_view key, std::optional<double>& current,
                 std::optional<double>& target) {
  const std::size_t at = find_word(s, key);
  if (at == std::string_view::npos) return false;
  std::string_view rest = s.substr(at + key.size());
  rest = trim(rest);
  const auto value = take_double(rest);
  if (!value) return false;
  current = value;
  while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
  if (!rest.empty() && rest.front() == '/') {
    rest.remove_prefix(1);
    while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
    if (const auto t = take_double(rest)) target = t;
  }
  return true;
}

std::optional<Temperatures> read_temperatures(std::string_view s) {
  Temperatures t;
  const bool hotend = read_heater(s, "T:", t.hotend, t.hotend_target) ||
                      read_heater(s, "T0:", t.hotend, t.hotend_target);
  const bool bed = read_heater(s, "B:", t.bed, t.bed_target);
  if (!hotend && !bed) return std::nullopt;
  return t;
}

std::optional<ReportedPosition> read_position(std::string_view s) {
  // Everything after "Count" is in steps; only the logical coordinates before it count.
  if (const auto count = s.find("Count"); count != std::string_view::npos) s = s.substr(0, count);
  if (s.starts_with("C:")) s.remove_prefix(2);  // Sprinter's "C: X:0.00 Y:0.00 ..."
  ReportedPosition p;
  std::array<std::pair<std::string_view, double*>, 4> axes{
      {{"X:", &p.x}, {"Y:", &p.y}, {"Z:", &p.z}, {"E:", &p.e}}};
  int found = 0;
  for (auto& [key, value] : axes) {
    const std::size_t at = find_word(s, key);
    if (at == std::string_view::npos) continue;
    std::string_view rest = trim(s.substr(at + key.size()));
    if (const auto v = take_double(rest)) {
      *value = *v;
      ++found;
    }
  }
  if (found < 3) return std::nullopt;
  return p;
}

// "Resend: 12", "Resend:N12", "rs N12 Expected checksum 67": the first number after the keyword.
std::optional<long> read_resend_line(std::string_view rest) {
  while (!rest.empty() && (is_blank(rest.front()) || rest.front() == ':' || rest.front() == 'N' ||
                           rest.front() == 'n')) {
    rest.remove_prefix(1);
  }
  return take_long(rest);
}

}  // namespace

bool is_fatal_error(std::string_view error_text) {
  static constexpr std::array<std::string_view, 12> kFatal{
      "halted",         "kill()",           "killed",          "thermal runaway",
      "mintemp",        "maxtemp",          "heating failed",  "system stopped",
      "printer stopped", "watchdog",        "stopped due to",  "emergency stop"};
  for (std::string_view word : kFatal) {
    if (contains_nocase(error_text, word)) return true;
  }
  return false;
}

Reply classify_reply(std::string_view raw) {
  Reply reply;
  const std::string_view line = trim(raw);
  reply.text = std::string(line);

  if (starts_with_nocase(line, "ok") && (line.size() == 2 || is_blank(line[2]) || line[2] == ':')) {
    reply.kind = ReplyKind::ok;
    std::string_view rest = trim(line.substr(2));
    if (is_teacup_error(rest)) {
      reply.refusal = std::string(rest);
      return reply;
    }
    if (rest.starts_with("X:") || rest.starts_with("C:")) {
      reply.position = read_position(rest);
      if (reply.position) return reply;
    }
    reply.temperatures = read_temperatures(rest);
    // Repetier's ACK_WITH_LINENUMBER: "ok 12" (gcode.cpp checkAndPushCommand, Com::tOkSpace).
    {
      std::string_view digits = rest;
      const auto value = take_long(digits);
      if (value && (digits.empty() || is_blank(digits.front()))) {
        reply.line_number = *value;
        return reply;
      }
    }
    // ADVANCED_OK words have no colon: "N12 P15 B3". "B:60" is the bed.
    while (!rest.empty()) {
      while (!rest.empty() && is_blank(rest.front())) rest.remove_prefix(1);
      std::size_t end = 0;
      while (end < rest.size() && !is_blank(rest[end])) ++end;
      std::string_view word = rest.substr(0, end);
      rest.remove_prefix(end);
      if (word.size() < 2 || word.find(':') != std::string_view::npos) continue;
      std::string_view digits = word.substr(1);
      const auto value = take_long(digits);
      if (!value || !digits.empty()) continue;
      switch (word.front()) {
        case 'N': reply.line_number = *value; break;
        case 'P': reply.planner_free = static_cast<int>(*value); break;
        case 'B': reply.queue_free = static_cast<int>(*value); break;
        default: break;
      }
    }
    return reply;
  }
  if (starts_with_nocase(line, "resend")) {
    reply.kind = ReplyKind::resend;
    reply.line_number = read_resend_line(line.substr(6));
    if (!reply.line_number) reply.kind = ReplyKind::other;
    return reply;
  }
  if (starts_with_nocase(line, "rs") && (line.size() > 2 && (is_blank(line[2]) || line[2] == ':'))) {
    reply.kind = ReplyKind::resend;
    reply.line_number = read_resend_line(line.substr(2));
    if (!reply.line_number) reply.kind = ReplyKind::other;
    return reply;
  }
  if (starts_with_nocase(line, "skip ") || starts_with_nocase(line, "skip:")) {
    reply.kind = ReplyKind::skip;
    std::string_view rest = trim(line.substr(5));
    reply.line_number = take_long(rest);
    return reply;
  }
  if (starts_with_nocase(line, "fatal:") || line.starts_with("!!")) {
    reply.kind = ReplyKind::fatal;
    return reply;
  }
  if (starts_with_nocase(line, "error") || is_teacup_error(line)) {
    reply.kind = is_fatal_error(line) ? ReplyKind::fatal : ReplyKind::error;
    return reply;
  }
  if (starts_with_nocase(line, "unknown command")) {
    reply.kind = ReplyKind::echo;
    reply.unknown_command = true;
    return reply;
  }
  std::string_view body = line;
  if (starts_with_nocase(body, "echo:")) body = trim(body.substr(5));
  // Teacup's clock.c says this each second while M116 waits (its only keepalive).
  if (starts_with_nocase(body, "busy:") || line == "Waiting for target temp") {
    reply.kind = ReplyKind::busy;
    return reply;
  }
  if (line == "wait") {
    reply.kind = ReplyKind::wait;
    return reply;
  }
  if (starts_with_nocase(line, "start") && line.size() == 5) {  // Teacup says "Start"
    reply.kind = ReplyKind::start;
    return reply;
  }
  if (starts_with_nocase(line, "echo:")) {
    reply.kind = ReplyKind::echo;
    reply.unknown_command = contains_nocase(line, "unknown command");
    return reply;
  }
  if (line.starts_with("X:") || line.starts_with("C:")) {
    if ((reply.position = read_position(line))) {
      reply.kind = ReplyKind::position;
      return reply;
    }
  }
  if (find_word(line, "T:") != std::string_view::npos ||
      find_word(line, "T0:") != std::string_view::npos || line.starts_with("B:")) {
    if ((reply.temperatures = read_temperatures(line))) {
      reply.kind = ReplyKind::temperature;
      reply.heating_wait = find_word(line, "W:") != std::string_view::npos;
      return reply;
    }
  }
  reply.kind = ReplyKind::other;
  return reply;
}

}  // namespace printer
