#include "printer/gcode_line.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <cstdlib>

#include <fmt/core.h>

#include "base/text.h"

namespace printer {

namespace {

using base::trim;

// Parses a decimal number at the front of `s` (as Marlin's strtod does), advancing `s`.
std::optional<double> take_number(std::string_view& s) {
  std::size_t n = 0;
  if (n < s.size() && (s[n] == '-' || s[n] == '+')) ++n;
  while (n < s.size() && (std::isdigit(static_cast<unsigned char>(s[n])) || s[n] == '.')) ++n;
  if (n == 0) return std::nullopt;
  const std::string text(s.substr(0, n));
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str()) return std::nullopt;
  s.remove_prefix(static_cast<std::size_t>(end - text.c_str()));
  return value;
}

}  // namespace

std::optional<double> GcodeCommand::get(char word) const {
  for (const GcodeWord& w : words) {
    if (w.letter == word) return w.value;
  }
  return std::nullopt;
}

bool GcodeCommand::has(char word) const {
  for (const GcodeWord& w : words) {
    if (w.letter == word) return true;
  }
  return false;
}

GcodeCommand parse_gcode_line(std::string_view line) {
  GcodeCommand command;
  if (const auto semicolon = line.find(';'); semicolon != std::string_view::npos) {
    command.comment = std::string(trim(line.substr(semicolon + 1)));
    line = line.substr(0, semicolon);
  }
  line = trim(line);
  command.text = std::string(line);
  if (line.empty()) return command;

  const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(line.front())));
  std::string_view rest = line.substr(1);
  std::size_t digits = 0;
  while (digits < rest.size() && std::isdigit(static_cast<unsigned char>(rest[digits]))) ++digits;
  if ((letter != 'G' && letter != 'M' && letter != 'T') || digits == 0) {
    command.letter = letter;  // not a command Marlin knows; code stays -1
    return command;
  }
  command.letter = letter;
  std::from_chars(rest.data(), rest.data() + digits, command.code);
  rest.remove_prefix(digits);
  if (!rest.empty() && rest.front() == '.') {  // a subcode: G92.1, M862.3
    rest.remove_prefix(1);
    std::size_t n = 0;
    while (n < rest.size() && std::isdigit(static_cast<unsigned char>(rest[n]))) ++n;
    std::from_chars(rest.data(), rest.data() + n, command.subcode);
    rest.remove_prefix(n);
  }

  while (!rest.empty()) {
    const unsigned char c = static_cast<unsigned char>(rest.front());
    if (!std::isalpha(c)) {
      rest.remove_prefix(1);
      continue;
    }
    rest.remove_prefix(1);
    GcodeWord word{static_cast<char>(std::toupper(c)), take_number(rest)};
    command.words.push_back(word);
  }
  return command;
}

namespace {

bool is_letter(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'); }
bool is_digit(char c) { return c >= '0' && c <= '9'; }
char upper(char c) { return c >= 'a' && c <= 'z' ? static_cast<char>(c - 'a' + 'A') : c; }

// A G-code number at the front of `s` ("10", "-0.5", ".2", "+3", "1e-3"); its length, 0 if none.
std::size_t number_length(std::string_view s) {
  std::size_t n = 0;
  if (n < s.size() && (s[n] == '-' || s[n] == '+')) ++n;
  std::size_t digits = 0;
  while (n < s.size() && is_digit(s[n])) ++n, ++digits;
  if (n < s.size() && s[n] == '.') {
    ++n;
    while (n < s.size() && is_digit(s[n])) ++n, ++digits;
  }
  if (digits == 0) return 0;
  // A version after the number: "U3.9.0" (Prusa's firmware check).
  while (n + 1 < s.size() && s[n] == '.' && is_digit(s[n + 1])) {
    ++n;
    while (n < s.size() && is_digit(s[n])) ++n;
  }
  if (n + 1 < s.size() && (s[n] == 'e' || s[n] == 'E') &&
      (is_digit(s[n + 1]) || ((s[n + 1] == '-' || s[n + 1] == '+') && n + 2 < s.size() && is_digit(s[n + 2])))) {
    n += 2;
    while (n < s.size() && is_digit(s[n])) ++n;
  }
  return n;
}

// Whether a G-code number (number_length's) is past a 32-bit float's range (3.4e38). One
// without an exponent and of at most 38 digits before its point is not, read or not: the
// checking pass reads millions of numbers, and parsing each is most of its time.
bool past_float_range(std::string_view number) {
  const std::size_t sign = number.front() == '-' || number.front() == '+' ? 1 : 0;
  const std::size_t digits = std::min(number.find('.'), number.size()) - sign;
  if (digits <= 38 && number.find_first_of("eE") == std::string_view::npos) return false;
  double value = 0;
  const std::size_t from = number.front() == '+' ? 1 : 0;  // from_chars reads '-' only
  const auto [end, error] = std::from_chars(number.data() + from, number.data() + number.size(), value);
  return error == std::errc::result_out_of_range || std::abs(value) > std::numeric_limits<float>::max();
}

bool text_command(char letter, int code) {
  if (letter != 'M') return false;
  switch (code) {
    case 0: case 1: case 16: case 23: case 28: case 30: case 32: case 117: case 118: case 928:
      return true;
    default:
      return false;
  }
}

}  // namespace

bool takes_text(const GcodeCommand& command) { return text_command(command.letter, command.code); }

std::optional<std::string> gcode_problem(std::string_view command) {
  bool star = false;
  for (char c : command) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x7f || (u < 0x20 && c != '\t')) return std::string("it holds bytes that are not text");
    star |= c == '*';
  }
  if (star) return std::string("checksums are for the host to add");
  if (command.empty() || !is_letter(command.front())) {
    return std::string("it does not start with a command word (G, M or T and a number)");
  }
  const char letter = upper(command.front());
  if (letter == 'N') return std::string("line numbers are for the host to add");
  if (letter != 'G' && letter != 'M' && letter != 'T') {
    return std::string("it does not start with a command word (G, M or T and a number)");
  }
  std::size_t i = 1;
  const std::size_t code_start = i;
  while (i < command.size() && is_digit(command[i])) ++i;
  if (i == code_start) return std::string("its command word has no number");
  int code = 0;
  std::from_chars(command.data() + code_start, command.data() + i, code);
  if (i < command.size() && command[i] == '.') {  // M862.3, G29.1
    ++i;
    const std::size_t sub = i;
    while (i < command.size() && is_digit(command[i])) ++i;
    if (i == sub) return std::string("its command word has no number after the '.'");
  }
  if (i < command.size() && command[i] != ' ' && command[i] != '\t' && !is_letter(command[i])) {
    return std::string("its command word is followed by something that is not a parameter");
  }
  if (text_command(letter, code)) return std::nullopt;  // M117 Hello: the rest is text
  while (i < command.size()) {
    const char c = command[i];
    if (c == ' ' || c == '\t') {
      ++i;
      continue;
    }
    if (c == '"') {  // P "MK3S": a quoted value after its letter
      const auto close = command.find('"', i + 1);
      if (close == std::string_view::npos) return std::string("a quoted parameter is not closed");
      i = close + 1;
      continue;
    }
    if (!is_letter(c)) return std::string("it has a parameter that does not start with a letter");
    ++i;
    if (i < command.size() && command[i] == '"') {  // P"MK3S"
      const auto close = command.find('"', i + 1);
      if (close == std::string_view::npos) return std::string("a quoted parameter is not closed");
      i = close + 1;
    } else {
      const std::size_t length = number_length(command.substr(i));
      // Firmware keeps numbers in 32-bit floats: a value past their range (X1e999) would
      // be infinite there, a move to nowhere or a heater set to anything.
      if (length > 0 && past_float_range(command.substr(i, length))) {
        return fmt::format("{} is too large for a printer's numbers",
                           command.substr(i - 1, length + 1));
      }
      i += length;
    }
    if (i < command.size() && command[i] != ' ' && command[i] != '\t' && !is_letter(command[i])) {
      return std::string("it has a parameter whose value is not a number");
    }
  }
  return std::nullopt;
}

std::uint8_t gcode_checksum(std::string_view bytes) {
  std::uint8_t sum = 0;
  for (char c : bytes) sum ^= static_cast<std::uint8_t>(c);
  return sum;
}

std::string frame_line(long line_number, std::string_view command) {
  const std::string numbered = fmt::format("N{} {}", line_number, command);
  return fmt::format("{}*{}", numbered, gcode_checksum(numbered));
}

NumberedLine parse_numbered_line(std::string_view line) {
  NumberedLine result;
  if (const auto semicolon = line.find(';'); semicolon != std::string_view::npos) {
    line = line.substr(0, semicolon);
  }
  line = trim(line);
  std::string_view body = line;
  if (const auto star = line.rfind('*'); star != std::string_view::npos) {
    body = line.substr(0, star);
    std::string_view digits = trim(line.substr(star + 1));
    int value = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec == std::errc() && end == digits.data() + digits.size()) {
      result.checksum = value;
    } else {
      result.checksum = -1;  // present but unreadable: never matches
    }
    result.checksum_ok = result.checksum == gcode_checksum(body);
  }
  std::string_view command = trim(body);
  if (!command.empty() && (command.front() == 'N' || command.front() == 'n')) {
    std::string_view rest = command.substr(1);
    long value = 0;
    const auto [end, ec] = std::from_chars(rest.data(), rest.data() + rest.size(), value);
    if (ec == std::errc() && end != rest.data()) {
      result.line_number = value;
      command = trim(rest.substr(static_cast<std::size_t>(end - rest.data())));
    }
  }
  result.command = std::string(command);
  return result;
}

}  // namespace printer
