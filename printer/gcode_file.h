// A G-code file as the host streams it: its commands and where each layer starts.
//
// Input: a text file of G-code (from `mahost slice` or any slicer). Output: the commands in
// order without comments or blank lines, exactly as they will be sent, each checked to be
// G-code before anything is sent; the layers, from the
// `;LAYER:<n>` comments slicers write at each layer start (Cura's and ours), with the `;Z:`
// that follows when there is one; a hash of the file's bytes, so a journal can tell whether the
// file changed before a resume. Commands are kept in one buffer (a bunny print has a million
// of them).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace printer {

struct GcodeLayer {
  int number = 0;                 // n of ;LAYER:n
  std::size_t first_command = 0;  // index of the layer's first command
  std::optional<double> z;        // mm, from ;Z: when given
};

class GcodeFile {
 public:
  std::string path;
  std::string hash;                 // "fnv1a64:<16 hex digits>" of the file's bytes
  std::vector<GcodeLayer> layers;   // in file order
  // Lines that are not G-code, left out (only with GcodeReading::skip_invalid): how many,
  // and the first kSkippedLinesNamed line numbers (from 1).
  std::size_t skipped_lines = 0;
  std::vector<std::size_t> skipped_line_numbers;

  std::size_t size() const { return starts_.empty() ? 0 : starts_.size() - 1; }
  std::string_view command(std::size_t i) const {
    return std::string_view(text_).substr(starts_[i], starts_[i + 1] - starts_[i]);
  }
  // Index into layers of the layer command i belongs to; -1 before the first layer mark.
  int layer_index_of(std::size_t command) const;
  // Index into layers of the layer that starts at command i, or -1.
  int layer_starting_at(std::size_t command) const;

  void add_command(std::string_view command);
  // Adds a piece's commands, layers (their indices moved past this file's commands) and
  // skipped lines after this file's.
  void append(const GcodeFile& piece);

 private:
  std::string text_;
  std::vector<std::size_t> starts_{0};
};

inline constexpr std::size_t kSkippedLinesNamed = 5;  // skipped line numbers a file keeps

struct GcodeReading {
  // Leave out lines that are not G-code (printer::gcode_problem) instead of refusing the file.
  bool skip_invalid = false;
  // What a refusal suggests besides fixing the line: the command line's way round it.
  std::string_view otherwise = "or print with --force to leave such lines out";
};

// Parses G-code text; `name` is used in messages. Every line must be a command
// (printer::gcode_problem) or a comment: anything else is refused with its line number and why
// (ConfigError), or with `skip_invalid` left out and counted. Throws ConfigError for text that
// is not G-code: NUL bytes or other binary, or a command too long for Marlin's line buffer.
GcodeFile parse_gcode(std::string_view text, const std::string& name, GcodeReading reading = {});

// A piece of a G-code file: whole lines, parsed as parse_gcode parses a file.
struct GcodePiece {
  const GcodeFile& gcode;  // its commands and layers (indices from the piece's start); no hash
  std::string_view text;   // its bytes
  std::uint64_t offset;    // where they start in the file
};
inline constexpr std::size_t kGcodePiece = 4 << 20;    // bytes read at a time
inline constexpr std::size_t kLongestLine = 16 << 20;  // a "line" longer is no G-code text

// Reads a G-code file in pieces of whole lines, kGcodePiece bytes or so, and hands each, parsed,
// to `on_piece` in order: the same checks and messages as parse_gcode of the whole file, lines
// numbered as in the file, `name` naming it. A piece ends before a ;LAYER: mark, so a mark and
// the ;Z: after it are parsed together. Returns the file's content_hash. Throws ConfigError as
// parse_gcode does, or when the file cannot be read. The file's text is never all in memory.
std::string for_each_gcode_piece(const std::string& path, const std::string& name, GcodeReading reading,
                                 const std::function<void(const GcodePiece&)>& on_piece);

// Reads and parses a file, a piece at a time (it holds the commands, not the comments). Throws
// ConfigError naming the file when it cannot be read, is empty of commands, or is not G-code.
GcodeFile read_gcode_file(const std::string& path, GcodeReading reading = {});

// "fnv1a64:<16 hex digits>": a hash to notice a changed file, not a cryptographic one.
std::string content_hash(std::string_view bytes);

// content_hash of bytes that come in pieces (a file read a few MiB at a time): add() each
// piece in order; text() is content_hash of them all.
class ContentHasher {
 public:
  void add(std::string_view bytes);
  std::string text() const;

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;  // FNV-1a's offset basis
};

}  // namespace printer
