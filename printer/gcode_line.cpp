#include "printer/gcode_line.h"

#include <cctype>
#include <charconv>
#include <cstdlib>

#include <fmt/core.h>

namespace printer {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

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
  if (!rest.empty() && rest.front() == '.') {  // G29.1-style subcodes: skip the suffix
    rest.remove_prefix(1);
    while (!rest.empty() && std::isdigit(static_cast<unsigned char>(rest.front()))) rest.remove_prefix(1);
  }

  while (!rest.empty()) {
    const unsigned char c = static_cast<unsigned char>(rest.front());
    if (!std::isalpha(c)) {
      rest.remove_prefix(1);
      continue;
    }
    rest.remove_prefix(1);
    GcodeWord word{static_cast<char>(std::toupper(c)), 0};
    if (auto value = take_number(rest)) word.value = *value;
    command.words.push_back(word);
  }
  return command;
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
