#include "printer/gcode_file.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/core.h>

#include "printer/error.h"
#include "printer/gcode_line.h"

namespace printer {

namespace {

// Marlin's MAX_CMD_SIZE is 96 with the terminating NUL; the host adds "N<line> " and "*<cs>",
// up to 13 characters for a line number of seven digits.
constexpr std::size_t kLongestCommand = 95 - 13;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

// The start of a line for a message: printable, at most 40 characters.
std::string excerpt(std::string_view line) {
  std::string out;
  for (char c : line.substr(0, 40)) {
    const auto u = static_cast<unsigned char>(c);
    out += u >= 0x20 && u < 0x7f ? c : '?';
  }
  if (line.size() > 40) out += "...";
  return out;
}

std::optional<double> number_after(std::string_view comment, std::string_view key) {
  if (!comment.starts_with(key)) return std::nullopt;
  comment.remove_prefix(key.size());
  comment = trim(comment);
  double value = 0;
  const auto [end, ec] = std::from_chars(comment.data(), comment.data() + comment.size(), value);
  if (ec != std::errc()) return std::nullopt;
  return value;
}

}  // namespace

void GcodeFile::add_command(std::string_view command) {
  text_.append(command);
  starts_.push_back(text_.size());
}

int GcodeFile::layer_index_of(std::size_t command) const {
  const auto after = std::upper_bound(layers.begin(), layers.end(), command,
                                      [](std::size_t c, const GcodeLayer& l) { return c < l.first_command; });
  return static_cast<int>(after - layers.begin()) - 1;
}

int GcodeFile::layer_starting_at(std::size_t command) const {
  const int index = layer_index_of(command);
  if (index >= 0 && layers[static_cast<std::size_t>(index)].first_command == command) return index;
  return -1;
}

std::string content_hash(std::string_view bytes) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ull;
  }
  return fmt::format("fnv1a64:{:016x}", hash);
}

GcodeFile parse_gcode(std::string_view text, const std::string& name, GcodeReading reading) {
  GcodeFile file;
  file.path = name;
  file.hash = content_hash(text);
  std::size_t line_number = 0;
  bool awaiting_z = false;
  while (!text.empty()) {
    ++line_number;
    const std::size_t end = text.find('\n');
    std::string_view raw = text.substr(0, end);
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    if (raw.find('\0') != std::string_view::npos) {
      throw ConfigError(fmt::format("{}: line {} contains NUL bytes: this is not a G-code text file",
                                    name, line_number));
    }
    std::string_view comment;
    std::string_view command = raw;
    if (const auto semicolon = raw.find(';'); semicolon != std::string_view::npos) {
      comment = trim(raw.substr(semicolon + 1));
      command = raw.substr(0, semicolon);
    }
    command = trim(command);
    if (!comment.empty()) {
      if (const auto layer = number_after(comment, "LAYER:")) {
        file.layers.push_back({static_cast<int>(*layer), file.size(), std::nullopt});
        awaiting_z = true;
      } else if (const auto z = number_after(comment, "Z:"); z && awaiting_z) {
        file.layers.back().z = z;
        awaiting_z = false;
      }
    }
    if (command.empty()) continue;
    if (const std::optional<std::string> problem = gcode_problem(command)) {
      if (reading.skip_invalid) {
        ++file.skipped_lines;
        if (file.skipped_line_numbers.size() < 5) file.skipped_line_numbers.push_back(line_number);
        continue;
      }
      throw ConfigError(fmt::format(
          "{}: line {} is not G-code ({}: \"{}\"); every line must be a command such as G1 X10 "
          "E0.5, or a ;comment: fix the line{}{}",
          name, line_number, *problem, excerpt(command), reading.otherwise.empty() ? "" : ", ",
          reading.otherwise));
    }
    if (command.size() > kLongestCommand) {
      throw ConfigError(fmt::format(
          "{}: line {} is a command of {} characters; Marlin reads at most {} with the line "
          "number and checksum: shorten it",
          name, line_number, command.size(), kLongestCommand));
    }
    file.add_command(command);
  }
  return file;
}

GcodeFile read_gcode_file(const std::string& path, GcodeReading reading) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw ConfigError(fmt::format("{}: is a directory, not a G-code file", path));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open the G-code file: check the path", path));
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (in.bad()) throw ConfigError(fmt::format("{}: cannot read the G-code file", path));
  GcodeFile file = parse_gcode(bytes.str(), path, reading);
  if (file.size() == 0) {
    throw ConfigError(fmt::format("{}: the file has no G-code commands", path));
  }
  return file;
}

}  // namespace printer
