#include "printer/gcode_file.h"

#include <algorithm>
#include <charconv>
#include <cstring>
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

// The lines of `text` checked as parse_gcode checks a file, the first being line `line_number`
// + 1 of the file (line_number is left at the last line's): each command, trimmed and without
// its comment, goes to on_command(command, end) with the byte after its line (from the start
// of `text`); layer marks and lines left out are added to `file`, whose size() on_command
// keeps counting. `awaiting_z`: a ;LAYER: mark is waiting for its ;Z:.
template <typename OnCommand>
void scan_lines(std::string_view text, const std::string& name, GcodeReading reading, std::size_t& line_number,
                bool& awaiting_z, GcodeFile& file, OnCommand&& on_command) {
  const char* const start = text.data();
  const char* const stop = start + text.size();
  // The first NUL byte, looked for once: the line that holds it is refused when reached, after
  // the lines before it are checked, as the whole file's first bad line.
  const auto* nul = text.empty() ? nullptr : static_cast<const char*>(std::memchr(start, '\0', text.size()));
  for (const char* at = start; at < stop;) {
    ++line_number;
    const auto* newline = static_cast<const char*>(std::memchr(at, '\n', static_cast<std::size_t>(stop - at)));
    const char* const next = newline != nullptr ? newline + 1 : stop;
    const std::string_view raw(at, static_cast<std::size_t>((newline != nullptr ? newline : stop) - at));
    at = next;
    if (nul != nullptr && nul < next) {
      throw ConfigError(fmt::format("{}: line {} contains NUL bytes: this is not a G-code text file",
                                    name, line_number));
    }
    std::string_view command = raw;
    if (const auto* semicolon = static_cast<const char*>(std::memchr(raw.data(), ';', raw.size()))) {
      command = raw.substr(0, static_cast<std::size_t>(semicolon - raw.data()));
      const std::string_view comment = trim(raw.substr(command.size() + 1));
      if (const auto layer = number_after(comment, "LAYER:")) {
        file.layers.push_back({static_cast<int>(*layer), file.size(), std::nullopt});
        awaiting_z = true;
      } else if (const auto z = number_after(comment, "Z:"); z && awaiting_z) {
        file.layers.back().z = z;
        awaiting_z = false;
      }
    }
    command = trim(command);
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
    on_command(command, static_cast<std::uint64_t>(next - start));
  }
}

// parse_gcode's work on text whose first line is line `first_line` + 1 of the file; no hash.
GcodeFile parse_lines(std::string_view text, const std::string& name, GcodeReading reading,
                      std::size_t first_line) {
  GcodeFile file;
  file.path = name;
  bool awaiting_z = false;
  scan_lines(text, name, reading, first_line, awaiting_z, file,
             [&](std::string_view command, std::uint64_t end) { file.add_command(command, end); });
  return file;
}

// Where a piece that is not the file's last ends in `text`: before its last ;LAYER: mark (so
// the ;Z: that follows a mark is read with it, in the next piece), else after its last whole
// line; 0 when it holds no line end.
std::size_t piece_cut(std::string_view text) {
  std::size_t last_line_end = 0;
  for (std::size_t end = text.size(); end > 0;) {
    const auto* newline = static_cast<const char*>(::memrchr(text.data(), '\n', end));
    if (newline == nullptr) break;
    const std::size_t after = static_cast<std::size_t>(newline - text.data()) + 1;
    if (last_line_end == 0) last_line_end = after;
    if (text.substr(after).starts_with(";LAYER:")) return after;
    end = after - 1;
  }
  return last_line_end;
}

// Reads the file at `path` in pieces of whole lines, kGcodePiece bytes or so (see piece_cut;
// the last piece ends with the file), and hands each to on_text(text, offset in the file).
// Throws ConfigError naming the file (`name`) when it cannot be read or holds a line longer
// than kLongestLine.
template <typename OnText>
void read_pieces(const std::string& path, const std::string& name, OnText&& on_text) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw ConfigError(fmt::format("{}: is a directory, not a G-code file", name));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(fmt::format("{}: cannot open the G-code file: check the path", name));
  // The lines after the last piece stay at the buffer's front, read on after.
  std::vector<char> buffer(kGcodePiece);
  std::size_t held = 0;
  std::uint64_t offset = 0;  // of the buffer's front in the file
  std::size_t lines_before = 0;
  for (bool at_end = false; !at_end;) {
    if (held == buffer.size()) {  // no line end in all that was read
      if (buffer.size() >= kLongestLine) {
        throw ConfigError(fmt::format("{}: line {} is longer than {} MiB: this is not a G-code text file",
                                      name, lines_before + 1, kLongestLine >> 20));
      }
      buffer.resize(buffer.size() * 2);
    }
    in.read(buffer.data() + held, static_cast<std::streamsize>(buffer.size() - held));
    const auto got = static_cast<std::size_t>(in.gcount());
    if (in.bad()) throw ConfigError(fmt::format("{}: cannot read the G-code file", name));
    at_end = got < buffer.size() - held;
    held += got;
    const std::string_view text(buffer.data(), held);
    const std::size_t cut = at_end ? held : piece_cut(text);
    if (cut == 0) continue;
    on_text(text.substr(0, cut), offset);
    lines_before += static_cast<std::size_t>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(cut), '\n'));
    std::memmove(buffer.data(), buffer.data() + cut, held - cut);
    held -= cut;
    offset += cut;
  }
}

}  // namespace

GcodeFile parse_gcode(std::string_view text, const std::string& name, GcodeReading reading) {
  GcodeFile file = parse_lines(text, name, reading, 0);
  file.hash = content_hash(text);
  return file;
}

std::string for_each_gcode_piece(const std::string& path, const std::string& name, GcodeReading reading,
                                 const std::function<void(const GcodePiece&)>& on_piece) {
  ContentHasher hash;
  std::size_t lines_before = 0;
  read_pieces(path, name, [&](std::string_view text, std::uint64_t offset) {
    hash.add(text);
    const GcodeFile piece = parse_lines(text, name, reading, lines_before);
    on_piece(GcodePiece{piece, text, offset});
    lines_before += static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  });
  return hash.text();
}

GcodeFile read_gcode_file(const std::string& path, GcodeReading reading, std::size_t block_size,
                          const std::function<void(const GcodePiece&)>& on_piece) {
  GcodeFile file;
  file.path = path;
  file.reading_ = reading;
  file.block_size_ = std::max<std::size_t>(block_size, 1);
  // One pass: the file's hash runs through its bytes in order, and a block keeps the hash where
  // it begins and where it ends (GcodeReader hashes the block's bytes again from the first
  // and compares with the second).
  ContentHasher hash;
  std::uint64_t hashed_to = 0;  // bytes of the file hashed so far
  std::size_t in_block = 0;     // commands of the block being read, so far
  std::uint64_t block_begin = 0, block_begin_hash = hash.value();
  std::uint64_t last_end = 0, last_end_hash = 0;  // the last command's line end, and the hash there
  std::size_t line_number = 0;
  bool awaiting_z = false;
  read_pieces(path, path, [&](std::string_view text, std::uint64_t offset) {
    const auto hash_to = [&](std::uint64_t to) {
      hash.add(text.substr(static_cast<std::size_t>(hashed_to - offset), static_cast<std::size_t>(to - hashed_to)));
      hashed_to = to;
    };
    const std::size_t lines_before = line_number;
    const std::size_t commands_before = file.size();
    scan_lines(text, path, reading, line_number, awaiting_z, file, [&](std::string_view, std::uint64_t end) {
      ++file.count_;
      last_end = offset + end;
      if (++in_block < file.block_size_) return;
      hash_to(last_end);
      file.blocks_.push_back({block_begin, last_end, block_begin_hash, hash.value()});
      block_begin = last_end;
      block_begin_hash = hash.value();
      in_block = 0;
    });
    if (in_block > 0 && file.size() > commands_before) {  // the last block may end in this piece
      hash_to(last_end);
      last_end_hash = hash.value();
    }
    hash_to(offset + text.size());
    if (on_piece) on_piece(GcodePiece{parse_lines(text, path, reading, lines_before), text, offset});
  });
  if (in_block > 0) file.blocks_.push_back({block_begin, last_end, block_begin_hash, last_end_hash});
  file.hash = hash.text();
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
  ContentHasher hash(b.hash_at_begin);
  hash.add(text);
  if (hash.value() != b.hash_at_end) throw changed();
  try {
    block_ = parse_lines(text, file_.path, file_.reading(), 0);
  } catch (const ConfigError&) {
    throw changed();  // the check read these bytes without a refusal: only a hash collision
  }
  if (block_.size() != count) {
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
