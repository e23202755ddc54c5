#include "sim/serial_line.h"

#include <algorithm>

namespace sim {

namespace {
bool is_digit(char c) { return c >= '0' && c <= '9'; }
}  // namespace

long marlin_strtol(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
  bool negative = false;
  if (i < s.size() && (s[i] == '-' || s[i] == '+')) negative = s[i++] == '-';
  long value = 0;
  while (i < s.size() && is_digit(s[i])) {
    value = value * 10 + (s[i++] - '0');
    if (value > 1'000'000'000'000L) break;  // far beyond any line number; keeps it defined
  }
  return negative ? -value : value;
}

void LineAssembler::feed(char c) {
  if (skip_) return;
  if (escape_) {
    escape_ = false;
  } else if (c == '\\') {
    escape_ = true;
    return;
  } else if (c == ';') {
    skip_ = true;
    return;
  }
  if (c == '\b') {
    if (!line_.empty()) line_.pop_back();
    return;
  }
  line_ += c;
  if (static_cast<int>(line_.size()) >= max_size_ - 1) {
    skip_ = true;
    cut_ = true;
  }
}

std::string LineAssembler::take() {
  std::string line = std::move(line_);
  line_.clear();
  skip_ = escape_ = cut_ = false;
  return line;
}

SerialReceiver::Buffered SerialReceiver::buffer(char c) {
  if (static_cast<int>(rx_.size() - rx_read_) < rx_size_) {
    if (rx_read_ >= 4096) {  // bytes read stay until the buffer runs empty; not for ever
      rx_.erase(0, rx_read_);
      rx_read_ = 0;
    }
    rx_ += c;
    dropping_ = false;
    return Buffered::kept;
  }
  const bool first = !dropping_;
  dropping_ = true;
  return first ? Buffered::lost_first : Buffered::lost;
}

char SerialReceiver::take_buffered() {
  const char c = rx_[rx_read_++];
  if (rx_read_ == rx_.size()) {
    rx_.clear();
    rx_read_ = 0;
  }
  return c;
}

void SerialReceiver::discard_buffered() {
  rx_.clear();
  rx_read_ = 0;
  dropping_ = false;
}

std::optional<std::string> SerialReceiver::read(char c, bool& cut) {
  cut = false;
  if (!is_line_end(c)) {
    const bool was_cut = line_.cut();
    line_.feed(c);
    cut = line_.cut() && !was_cut;
    return std::nullopt;
  }
  std::string raw = line_.take();
  if (raw.empty() && !empty_lines_) return std::nullopt;
  return raw;
}

int received_checksum(std::string_view line) {
  const auto star = line.rfind('*');
  unsigned char sum = 0;
  for (std::size_t i = 0; i < std::min(star, line.size()); ++i) sum ^= static_cast<unsigned char>(line[i]);
  return sum;
}

LineCheck check_line(std::string_view command, long last_n) {
  while (!command.empty() && command.front() == ' ') command.remove_prefix(1);
  LineCheck check;
  if (command.empty() || command.front() != 'N') return check;
  const bool m110 = command.find("M110") != std::string_view::npos;
  std::string_view npos = command;
  if (m110 && command.size() > 4) {
    if (const auto n2 = command.find('N', 4); n2 != std::string_view::npos) npos = command.substr(n2);
  }
  check.number = marlin_strtol(npos.substr(1));
  if (check.number != last_n + 1 && !m110) {
    check.verdict = LineVerdict::wrong_line_number;
    return check;
  }
  const auto star = command.rfind('*');
  if (star == std::string_view::npos) {
    check.verdict = LineVerdict::no_checksum;
    return check;
  }
  unsigned char sum = 0;
  for (std::size_t i = 0; i < star; ++i) sum ^= static_cast<unsigned char>(command[i]);
  check.verdict = marlin_strtol(command.substr(star + 1)) == sum ? LineVerdict::accepted
                                                                 : LineVerdict::checksum_mismatch;
  return check;
}

TeacupLine read_teacup_line(std::string_view line) {
  TeacupLine t;
  const auto star = line.find('*');
  unsigned char sum = 0;
  for (std::size_t i = 0; i < std::min(star, line.size()); ++i) sum ^= static_cast<unsigned char>(line[i]);
  t.computed = sum;
  const std::string_view body = line.substr(0, std::min(star, line.size()));
  for (std::size_t i = 0; i < body.size(); ++i) {
    const char c = body[i];
    if (c == 'N' || c == 'n') t.number = marlin_strtol(body.substr(i + 1));
  }
  t.m110 = body.find("M110") != std::string_view::npos || body.find("m110") != std::string_view::npos;
  if (star != std::string_view::npos) {
    t.has_checksum = true;
    t.checksum_ok = marlin_strtol(line.substr(star + 1)) == sum;
  }
  return t;
}

RepetierLine read_repetier_line(std::string_view line) {
  RepetierLine r;
  std::size_t i = 0;
  while (i < line.size() && line[i] == ' ') ++i;
  if (i < line.size() && (line[i] == 'N' || line[i] == 'n')) r.number = marlin_strtol(line.substr(i + 1));
  if (const auto star = line.find('*'); star != std::string_view::npos) {
    unsigned char sum = 0;
    for (std::size_t k = 0; k < star; ++k) sum ^= static_cast<unsigned char>(line[k]);
    r.checksum_ok = marlin_strtol(line.substr(star + 1)) == sum;
  }
  return r;
}

std::string_view error_text(LineVerdict verdict) {
  switch (verdict) {
    case LineVerdict::wrong_line_number: return "Line Number is not Last Line Number+1, Last Line: ";
    case LineVerdict::no_checksum: return "No Checksum with line number, Last Line: ";
    case LineVerdict::checksum_mismatch: return "checksum mismatch, Last Line: ";
    case LineVerdict::unnumbered:
    case LineVerdict::accepted: break;
  }
  return "";
}

std::string command_text(std::string_view line) {
  std::size_t i = 0;
  while (i < line.size() && line[i] == ' ') ++i;
  if (i + 1 < line.size() && (line[i] == 'N' || line[i] == 'n') &&
      (is_digit(line[i + 1]) || line[i + 1] == '-')) {
    i += 2;
    while (i < line.size() && is_digit(line[i])) ++i;
    while (i < line.size() && line[i] == ' ') ++i;
  }
  line.remove_prefix(std::min(i, line.size()));
  if (const auto star = line.find('*'); star != std::string_view::npos) line = line.substr(0, star);
  while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) line.remove_suffix(1);
  return std::string(line);
}

Emergency EmergencyParser::update(char c) {
  switch (state_) {
    case State::reset:
      if (c == ' ' || is_line_end(c)) break;
      state_ = c == 'N' ? State::n : c == 'M' ? State::m : State::ignore;
      break;
    case State::n:
      if (is_digit(c) || c == '-' || c == ' ') break;
      state_ = c == 'M' ? State::m : State::ignore;
      break;
    case State::m: state_ = c == '1' ? State::m1 : c == '4' ? State::m4 : State::ignore; break;
    case State::m1: state_ = c == '0' ? State::m10 : c == '1' ? State::m11 : State::ignore; break;
    case State::m10: state_ = c == '8' ? State::m108 : State::ignore; break;
    case State::m11: state_ = c == '2' ? State::m112 : State::ignore; break;
    case State::m4: state_ = c == '1' ? State::m41 : State::ignore; break;
    case State::m41: state_ = c == '0' ? State::m410 : State::ignore; break;
    default:
      // After a command (and whatever follows it on the line), or a line to ignore.
      if (is_line_end(c)) {
        const State done = state_;
        state_ = State::reset;
        if (done == State::m108) return Emergency::m108;
        if (done == State::m112) return Emergency::m112;
        if (done == State::m410) return Emergency::m410;
      }
      break;
  }
  return Emergency::none;
}

}  // namespace sim
