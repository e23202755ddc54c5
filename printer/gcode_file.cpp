#include "printer/gcode_file.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>

#include <fmt/core.h>

#include "base/text.h"
#include "printer/error.h"
#include "printer/gcode_line.h"

namespace printer {

namespace {

using base::trim;

// Marlin's MAX_CMD_SIZE is 96 with the terminating NUL; the host adds "N<line> " and "*<cs>",
// up to 13 characters for a line number of seven digits.
constexpr std::size_t kLongestCommand = 95 - 13;

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

void GcodeFile::add_command(std::string_view command, std::uint64_t end) {
  text_.append(command);
  starts_.push_back(text_.size());
  ends_.push_back(end);
  ++count_;
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

void ContentHasher::add(std::string_view bytes) {
  for (char c : bytes) {
    hash_ ^= static_cast<unsigned char>(c);
    hash_ *= 0x100000001b3ull;  // FNV-1a's 64-bit prime
  }
}

std::string ContentHasher::text() const { return fmt::format("fnv1a64:{:016x}", hash_); }

std::string content_hash(std::string_view bytes) {
  ContentHasher hasher;
  hasher.add(bytes);
  return hasher.text();
}

namespace {

// parse_gcode's work on text whose first line is line `first_line` + 1 of the file; no hash.
GcodeFile parse_lines(std::string_view text, const std::string& name, GcodeReading reading,
                      std::size_t first_line) {
  GcodeFile file;
  file.path = name;
  const char* const start = text.data();
  std::size_t line_number = first_line;
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
    const std::uint64_t line_end = static_cast<std::uint64_t>(text.data() - start);
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
        if (file.skipped_line_numbers.size() < kSkippedLinesNamed) file.skipped_line_numbers.push_back(line_number);
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
    file.add_command(command, line_end);
  }
  return file;
}

}  // namespace

GcodeFile parse_gcode(std::string_view text, const std::string& name, GcodeReading reading) {
  GcodeFile file = parse_lines(text, name, reading, 0);
  file.hash = content_hash(text);
  return file;
}

std::string for_each_gcode_piece(const std::string& path, const std::string& name, GcodeReading reading,
                                 const std::function<void(const GcodePiece&)>& on_piece) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw ConfigError(fmt::format("{}: is a directory, not a G-code file", name));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open the G-code file: check the path", name));
  ContentHasher hash;
  std::string text;  // read and not yet parsed: the lines after the last piece
  std::vector<char> buffer(kGcodePiece);
  std::uint64_t offset = 0;  // of `text` in the file
  std::size_t lines_before = 0;
  bool at_end = false;
  while (!at_end) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (in.bad()) throw ConfigError(fmt::format("{}: cannot read the G-code file", name));
    at_end = got < buffer.size();
    hash.add(std::string_view(buffer.data(), got));
    text.append(buffer.data(), got);
    // A piece ends before its last ;LAYER: mark (so the ;Z: that follows a mark is read with
    // it, in the next piece), else after its last whole line; at the end, with the file.
    std::size_t cut = text.size();
    if (!at_end) {
      const std::size_t mark = text.rfind("\n;LAYER:");
      cut = mark != std::string::npos ? mark + 1 : text.rfind('\n') + 1;
      if (cut == 0) {  // no line end yet in all that was read
        if (text.size() < kLongestLine) continue;
        throw ConfigError(fmt::format("{}: line {} is longer than {} MiB: this is not a G-code text file",
                                      name, lines_before + 1, kLongestLine >> 20));
      }
    }
    const std::string_view piece_text(text.data(), cut);
    const GcodeFile piece = parse_lines(piece_text, name, reading, lines_before);
    on_piece(GcodePiece{piece, piece_text, offset});
    lines_before += static_cast<std::size_t>(std::count(piece_text.begin(), piece_text.end(), '\n'));
    offset += cut;
    text.erase(0, cut);
  }
  return hash.text();
}

namespace {

std::uint64_t commands_hash(const GcodeFile& held, std::size_t from, std::size_t to) {
  ContentHasher hash;
  for (std::size_t i = from; i < to; ++i) {
    hash.add(held.command(i));
    hash.add("\n");
  }
  return hash.value();
}

}  // namespace

GcodeFile read_gcode_file(const std::string& path, GcodeReading reading, std::size_t block_size,
                          const std::function<void(const GcodePiece&)>& on_piece) {
  GcodeFile file;
  file.path = path;
  file.reading_ = reading;
  file.block_size_ = std::max<std::size_t>(block_size, 1);
  std::uint64_t block_begin = 0;  // where the block being read starts in the file
  ContentHasher block_hash;
  std::size_t in_block = 0;       // its commands so far
  // A block read on into the next piece is kept with the commands so far, and replaced.
  const auto close_block = [&](std::uint64_t end) {
    const GcodeFile::Block block{block_begin, end, block_hash.value()};
    if (!file.blocks_.empty() && file.blocks_.back().begin == block_begin) {
      file.blocks_.back() = block;
    } else {
      file.blocks_.push_back(block);
    }
  };
  file.hash = for_each_gcode_piece(path, path, reading, [&](const GcodePiece& piece) {
    const GcodeFile& held = piece.gcode;
    for (GcodeLayer layer : held.layers) {
      layer.first_command += file.count_;
      file.layers.push_back(layer);
    }
    for (std::size_t i = 0; i < held.size(); ++i) {
      block_hash.add(held.command(i));
      block_hash.add("\n");
      if (++in_block < file.block_size_) continue;
      const std::uint64_t end = piece.offset + held.command_end(i);
      close_block(end);
      block_begin = end;
      block_hash = ContentHasher();
      in_block = 0;
    }
    if (in_block > 0 && held.size() > 0) close_block(piece.offset + held.command_end(held.size() - 1));
    file.count_ += held.size();
    file.skipped_lines += held.skipped_lines;
    for (const std::size_t line : held.skipped_line_numbers) {
      if (file.skipped_line_numbers.size() < kSkippedLinesNamed) file.skipped_line_numbers.push_back(line);
    }
    if (on_piece) on_piece(piece);
  });
  if (file.size() == 0) {
    throw ConfigError(fmt::format("{}: the file has no G-code commands", path));
  }
  return file;
}

GcodeReader::GcodeReader(const GcodeFile& file) : file_(file) {
  if (file_.held()) return;
  in_.open(file_.path, std::ios::binary);
  if (!in_) throw ConfigError(fmt::format("{}: cannot open the G-code file any more: check the path", file_.path));
}

void GcodeReader::load(std::size_t block) {
  const GcodeFile::Block& b = file_.blocks().at(block);
  std::string text(static_cast<std::size_t>(b.end - b.begin), '\0');
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(b.begin));
  in_.read(text.data(), static_cast<std::streamsize>(text.size()));
  const auto got = static_cast<std::size_t>(in_.gcount());
  const std::size_t first = block * file_.block_size();
  const std::size_t count = std::min(file_.block_size(), file_.size() - first);
  const auto changed = [&] {
    return GcodeFileChanged(fmt::format(
        "{}: the file changed on disk while it printed (commands {} to {} are not what was "
        "checked): nothing of it was sent from there; print the file again once it stays as it is",
        file_.path, first + 1, first + count));
  };
  if (in_.bad()) throw ConfigError(fmt::format("{}: cannot read the G-code file any more", file_.path));
  if (got != text.size()) throw changed();
  try {
    block_ = parse_lines(text, file_.path, file_.reading(), 0);
  } catch (const ConfigError&) {
    throw changed();  // the check read the block without a refusal
  }
  if (block_.size() != count || commands_hash(block_, 0, count) != b.commands_hash) {
    block_ = GcodeFile();
    throw changed();
  }
  loaded_ = block;
}

std::string_view GcodeReader::command(std::size_t i) {
  if (file_.held()) return file_.command(i);
  const std::size_t block = i / file_.block_size();
  if (block_.size() == 0 || block != loaded_) load(block);
  return block_.command(i - block * file_.block_size());
}

std::uint64_t GcodeReader::command_end(std::size_t i) {
  if (file_.held()) return file_.command_end(i);
  const std::size_t block = i / file_.block_size();
  if (block_.size() == 0 || block != loaded_) load(block);
  return file_.blocks()[block].begin + block_.command_end(i - block * file_.block_size());
}

}  // namespace printer
