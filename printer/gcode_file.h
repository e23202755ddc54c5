// A G-code file as the host streams it: its commands and where each layer starts.
//
// Input: a text file of G-code (from `mahost slice` or any slicer). Output: the commands in
// order without comments or blank lines, exactly as they will be sent, each checked to be
// G-code before anything is sent; the layers, from the
// `;LAYER:<n>` comments slicers write at each layer start (Cura's and ours), with the `;Z:`
// that follows when there is one; a hash of the file's bytes, so a journal can tell whether the
// file changed before a resume.
//
// A file read from disk (read_gcode_file) is an index, not its commands: one checking pass
// keeps where each block of kGcodeBlock commands lies in the file and the file's hash at the
// block's ends, and a GcodeReader loads one block at a time, so a job's memory does not grow with
// the file. A file parsed from text (parse_gcode) holds its commands.
#pragma once

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "printer/error.h"

namespace printer {

struct GcodeLayer {
  int number = 0;                 // n of ;LAYER:n
  std::size_t first_command = 0;  // index of the layer's first command
  std::optional<double> z;        // mm, from ;Z: when given
};

struct GcodeReading {
  // Leave out lines that are not G-code (printer::gcode_problem) instead of refusing the file.
  bool skip_invalid = false;
  // What a refusal suggests besides fixing the line: the command line's way round it.
  std::string_view otherwise = "or print with --force to leave such lines out";
};

// Commands a block of a file on disk holds (the last block may hold fewer): about 100 kB of
// G-code, read in one go when a job reaches it.
inline constexpr std::size_t kGcodeBlock = 4096;

struct GcodePiece;

class GcodeFile {
 public:
  std::string path;
  std::string hash;                 // "fnv1a64:<16 hex digits>" of the file's bytes
  std::vector<GcodeLayer> layers;   // in file order
  // Lines that are not G-code, left out (only with GcodeReading::skip_invalid): how many,
  // and the first kSkippedLinesNamed line numbers (from 1).
  std::size_t skipped_lines = 0;
  std::vector<std::size_t> skipped_line_numbers;

  std::size_t size() const { return count_; }
  // Index into layers of the layer command i belongs to; -1 before the first layer mark.
  int layer_index_of(std::size_t command) const;
  // Index into layers of the layer that starts at command i, or -1.
  int layer_starting_at(std::size_t command) const;

  // A file parsed from text holds its commands; one read from disk is read through a
  // GcodeReader.
  bool held() const { return blocks_.empty(); }
  // Command i of a held file (see held()).
  std::string_view command(std::size_t i) const {
    return std::string_view(text_).substr(starts_[i], starts_[i + 1] - starts_[i]);
  }
  // The byte after command i's line (its line end included) in the text it was parsed from.
  std::uint64_t command_end(std::size_t i) const { return ends_[i]; }

  void add_command(std::string_view command, std::uint64_t end);

  // A block of a file on disk: commands [index * block_size, ...), the bytes [begin, end) of
  // the file (from the line after the block before to its last command's line end), and the
  // file's hash (ContentHasher::value) as it ran through the file, at begin and at end: its
  // bytes read again hash from the one to the other unless the file changed under a job.
  struct Block {
    std::uint64_t begin = 0, end = 0;
    std::uint64_t hash_at_begin = 0, hash_at_end = 0;
  };
  const std::vector<Block>& blocks() const { return blocks_; }
  std::size_t block_size() const { return block_size_; }
  GcodeReading reading() const { return reading_; }

 private:
  friend GcodeFile read_gcode_file(const std::string& path, GcodeReading reading, std::size_t block_size,
                                   const std::function<void(const GcodePiece&)>& on_piece);
  std::size_t count_ = 0;
  // A held file's commands.
  std::string text_;
  std::vector<std::size_t> starts_{0};
  std::vector<std::uint64_t> ends_;
  // A file on disk.
  std::vector<Block> blocks_;
  std::size_t block_size_ = kGcodeBlock;
  GcodeReading reading_;
};

inline constexpr std::size_t kSkippedLinesNamed = 5;  // skipped line numbers a file keeps

// Parses G-code text; `name` is used in messages. Every line must be a command
// (printer::gcode_problem) or a comment: anything else is refused with its line number and why
// (ConfigError), or with `skip_invalid` left out and counted. Throws ConfigError for text that
// is not G-code: NUL bytes or other binary, or a command too long for Marlin's line buffer.
GcodeFile parse_gcode(std::string_view text, const std::string& name, GcodeReading reading = {});

// A piece of a G-code file: whole lines, parsed as parse_gcode parses a file.
struct GcodePiece {
  // Its commands and layers (indices from the piece's start; command_end from its text's
  // start); no hash.
  const GcodeFile& gcode;
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

// Reads and checks a file a piece at a time and returns its index: layers, hash, blocks of
// `block_size` commands (see GcodeFile), no commands; `on_piece`, when given, sees each piece
// as for_each_gcode_piece hands it (to read more from the same pass). Throws ConfigError naming
// the file when it cannot be read, is empty of commands, or is not G-code.
GcodeFile read_gcode_file(const std::string& path, GcodeReading reading = {},
                          std::size_t block_size = kGcodeBlock,
                          const std::function<void(const GcodePiece&)>& on_piece = {});

// A file changed on disk after it was read: a block no longer holds the commands the check
// read there. Nothing of the changed block is sent.
struct GcodeFileChanged : ConfigError {
  using ConfigError::ConfigError;
};

// Reads a GcodeFile's commands: a held file's from memory, a file on disk's a block at a time
// (the file kept open, so a file replaced by a new one under the same name is still read as
// it was checked; one changed in place throws GcodeFileChanged). In order is cheapest; any
// command may be asked for (a resume starts mid-file).
class GcodeReader {
 public:
  explicit GcodeReader(const GcodeFile& file);
  // Command i; the view lasts until the next call that asks for a command of another block.
  // Throws GcodeFileChanged, or ConfigError when the file cannot be read any more.
  std::string_view command(std::size_t i);
  // The byte after command i's line in the file (OctoPrint's filepos once it is done).
  std::uint64_t command_end(std::size_t i);
  // Commands in memory for this reader: at most a block (0 for a held file's reader).
  std::size_t commands_held() const { return file_.held() ? 0 : block_.size(); }

 private:
  void load(std::size_t block);
  const GcodeFile& file_;
  std::ifstream in_;
  std::size_t loaded_ = 0;  // index of the block in block_ (valid when block_ has commands)
  GcodeFile block_;
};

// "fnv1a64:<16 hex digits>": a hash to notice a changed file, not a cryptographic one.
std::string content_hash(std::string_view bytes);

// content_hash of bytes that come in pieces (a file read a few MiB at a time): add() each
// piece in order; text() is content_hash of them all.
class ContentHasher {
 public:
  ContentHasher() = default;
  // Goes on from `value`, another hasher's value() after some bytes: adding the bytes that
  // followed them gives the value that hasher had after those.
  explicit ContentHasher(std::uint64_t value) : hash_(value) {}
  void add(std::string_view bytes);
  std::string text() const;
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;  // FNV-1a's offset basis
};

}  // namespace printer
