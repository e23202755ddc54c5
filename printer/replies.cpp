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

// What an ok line carries after the "ok": Teacup's refusal or position, temperatures, the
// line number of Repetier's "ok 12" or of ADVANCED_OK's "ok N12 P15 B3" with its buffer space.
void read_ok(std::string_view rest, Reply& reply) {
  if (is_teacup_error(rest)) {
    reply.refusal = std::string(rest);
    return;
  }
  if (rest.starts_with("X:") || rest.starts_with("C:")) {
    reply.position = read_position(rest);
    if (reply.position) return;
  }
  reply.temperatures = read_temperatures(rest);
  // Repetier's ACK_WITH_LINENUMBER: "ok 12" (gcode.cpp checkAndPushCommand, Com::tOkSpace).
  std::string_view digits = rest;
  const auto value = take_long(digits);
  if (value && (digits.empty() || is_blank(digits.front()))) {
    reply.line_number = *value;
    return;
  }
  // ADVANCED_OK words have no colon: "N12 P15 B3". "B:60" is the bed.
  while (!rest.empty()) {
    while (!rest.empty() && is_blank(rest.front())) rest.remove_prefix(1);
    std::size_t end = 0;
    while (end < rest.size() && !is_blank(rest[end])) ++end;
    std::string_view word = rest.substr(0, end);
    rest.remove_prefix(end);
    if (word.size() < 2 || word.find(':') != std::string_view::npos) continue;
    std::string_view number = word.substr(1);
    const auto n = take_long(number);
    if (!n || !number.empty()) continue;
    switch (word.front()) {
      case 'N': reply.line_number = *n; break;
      case 'P': reply.planner_free = static_cast<int>(*n); break;
      case 'B': reply.queue_free = static_cast<int>(*n); break;
      default: break;
    }
  }
}

bool is_ok(std::string_view line) {
  return starts_with_nocase(line, "ok") && (line.size() == 2 || is_blank(line[2]) || line[2] == ':');
}

// "Resend: 12", "Resend:N12", "rs N12 Expected checksum 67" (without a number: `other`) and
// Repetier's "skip 14"; false for any other line.
bool read_request(std::string_view line, Reply& reply) {
  const bool rs = starts_with_nocase(line, "rs") && line.size() > 2 && (is_blank(line[2]) || line[2] == ':');
  if (rs || starts_with_nocase(line, "resend")) {
    reply.line_number = read_resend_line(line.substr(rs ? 2 : 6));
    reply.kind = reply.line_number ? ReplyKind::resend : ReplyKind::other;
    return true;
  }
  if (starts_with_nocase(line, "skip ") || starts_with_nocase(line, "skip:")) {
    reply.kind = ReplyKind::skip;
    std::string_view rest = trim(line.substr(5));
    reply.line_number = take_long(rest);
    return true;
  }
  return false;
}

// The replies told by their first words alone, in the order they are tried: a line that is
// none of them is a report (position, temperatures) or `other`. "Error:" lines whose text is
// fatal are `fatal`: is_fatal_error.
struct WordRule {
  ReplyKind kind;
  bool (*matches)(std::string_view line);
};

constexpr std::array<WordRule, 7> kWordRules{{
    {ReplyKind::fatal, [](std::string_view l) { return starts_with_nocase(l, "fatal:") || l.starts_with("!!"); }},
    {ReplyKind::error, [](std::string_view l) { return starts_with_nocase(l, "error") || is_teacup_error(l); }},
    {ReplyKind::echo, [](std::string_view l) { return starts_with_nocase(l, "unknown command"); }},
    // Teacup's clock.c says "Waiting for target temp" each second while M116 waits (its only
    // keepalive).
    {ReplyKind::busy,
     [](std::string_view l) {
       const std::string_view body = starts_with_nocase(l, "echo:") ? trim(l.substr(5)) : l;
       return starts_with_nocase(body, "busy:") || l == "Waiting for target temp";
     }},
    {ReplyKind::wait, [](std::string_view l) { return l == "wait"; }},
    {ReplyKind::start, [](std::string_view l) { return starts_with_nocase(l, "start") && l.size() == 5; }},  // Teacup: "Start"
    {ReplyKind::echo, [](std::string_view l) { return starts_with_nocase(l, "echo:"); }},
}};

// Lines of figures without an ok: M114's position, M155's and M109's temperatures.
void read_report(std::string_view line, Reply& reply) {
  if (line.starts_with("X:") || line.starts_with("C:")) {
    if ((reply.position = read_position(line))) {
      reply.kind = ReplyKind::position;
      return;
    }
  }
  if (find_word(line, "T:") != std::string_view::npos ||
      find_word(line, "T0:") != std::string_view::npos || line.starts_with("B:")) {
    if ((reply.temperatures = read_temperatures(line))) {
      reply.kind = ReplyKind::temperature;
      reply.heating_wait = find_word(line, "W:") != std::string_view::npos;
    }
  }
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
  if (is_ok(line)) {
    reply.kind = ReplyKind::ok;
    read_ok(trim(line.substr(2)), reply);
    return reply;
  }
  if (read_request(line, reply)) return reply;
  for (const WordRule& rule : kWordRules) {
    if (!rule.matches(line)) continue;
    reply.kind = rule.kind == ReplyKind::error && is_fatal_error(line) ? ReplyKind::fatal : rule.kind;
    reply.unknown_command = rule.kind == ReplyKind::echo && contains_nocase(line, "unknown command");
    return reply;
  }
  read_report(line, reply);
  return reply;
}

}  // namespace printer
