// How Marlin 2.x reads a line from its serial port (Marlin/src/gcode/queue.cpp,
// feature/e_parser.h), as small pieces the simulated printer puts together.
//
// Input: the bytes of one line as the firmware receives them. Output: the line as Marlin
// keeps it (comments, escapes and backspaces applied, cut at max_cmd_size - 1 characters),
// Marlin's verdict on its line number and checksum, and the command its parser sees.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace sim {

inline bool is_line_end(char c) { return c == '\n' || c == '\r'; }

// C's strtol as Marlin calls it: leading blanks, a sign, digits; 0 when there are none.
long marlin_strtol(std::string_view text);

// process_stream_char: builds a line from bytes. ';' starts a comment to the line end, '\'
// takes the next byte as it is, a backspace erases, and bytes beyond max_cmd_size - 1 are
// dropped. Line ends are not fed to it: take() ends the line.
class LineAssembler {
 public:
  explicit LineAssembler(int max_cmd_size) : max_size_(max_cmd_size) {}
  void feed(char c);
  // The line so far, and a fresh start for the next one.
  std::string take();
  // Whether the line being built has been cut (counted once per line).
  bool cut() const { return cut_; }

 private:
  int max_size_;
  std::string line_;
  bool skip_ = false, escape_ = false, cut_ = false;
};

// get_serial_commands' receive side: the RX buffer bytes wait in while the command queue is
// full (rx_buffer_size bytes; more are lost, as on Marlin, counted once per run of lost bytes)
// and the line being assembled from the bytes read. The firmware decides when to read.
class SerialReceiver {
 public:
  // `empty_lines`: an empty line is a line too (Teacup answers it with ok); Marlin skips it.
  SerialReceiver(int rx_buffer_size, int max_cmd_size, bool empty_lines = false)
      : rx_size_(rx_buffer_size), empty_lines_(empty_lines), line_(max_cmd_size) {}

  // A byte the firmware cannot read yet: kept in the RX buffer, or lost (the first of a run
  // of lost bytes is one overflow).
  enum class Buffered { kept, lost_first, lost };
  Buffered buffer(char c);
  bool has_buffered() const { return !rx_.empty(); }
  char take_buffered();
  // The RX buffer's bytes are discarded (a line error, a kill, a reset).
  void discard_buffered();

  // Reads one byte into the line; at a line end, returns the line Marlin kept (empty lines
  // only with `empty_lines`). `cut` is set when this byte cut the line at max_cmd_size.
  std::optional<std::string> read(char c, bool& cut);
  // Drops the line being assembled.
  void drop_line() { line_.take(); }

 private:
  int rx_size_;
  bool empty_lines_;
  std::string rx_;
  std::size_t rx_read_ = 0;  // bytes of rx_ already taken
  bool dropping_ = false;    // inside a run of lost bytes
  LineAssembler line_;
};

// Marlin's checks of a line that starts with N (after blanks), in its order: the number must
// follow last_n (unless the line holds M110), then a checksum must be there and match.
enum class LineVerdict { unnumbered, accepted, wrong_line_number, no_checksum, checksum_mismatch };
struct LineCheck {
  LineVerdict verdict = LineVerdict::unnumbered;
  long number = 0;  // the N (for M110 lines, the N after M110 when given)
};
LineCheck check_line(std::string_view line, long last_n);

// What Teacup reads of a line's number and checksum (gcode_parse.c gcode_parse_char): N is
// the last N word anywhere in the line, the checksum the XOR of every byte before the first
// '*', compared with the number after it.
struct TeacupLine {
  std::optional<long> number;
  bool has_checksum = false;
  bool checksum_ok = true;  // true without a checksum
  int computed = 0;         // the XOR it computed, for "rs N<n> Expected checksum <computed>"
  bool m110 = false;
};
TeacupLine read_teacup_line(std::string_view line);

// What Repetier reads of a line (gcode.cpp parseAscii): N when the line has one, and whether a
// checksum, when there is one, matches (no checksum is fine: FEATURE_CHECKSUM_FORCED 0).
struct RepetierLine {
  std::optional<long> number;
  bool checksum_ok = true;
};
RepetierLine read_repetier_line(std::string_view line);
// The XOR of the bytes before the last '*' (all of them without one): the checksum a
// firmware computes of what it received.
int received_checksum(std::string_view line);

// "Line Number is not Last Line Number+1, Last Line: " and so on, for an error verdict.
std::string_view error_text(LineVerdict verdict);

// What Marlin's parser keeps of a line as the command: without leading blanks, "N<n> ",
// '*' and what follows, and trailing blanks ("N5 G1 X1 *23" -> "G1 X1").
std::string command_text(std::string_view line);

// EMERGENCY_PARSER: watches every byte as it arrives, before any buffer, and recognises
// M108, M112 and M410 (after an optional line number) when their line ends.
enum class Emergency { none, m108, m112, m410 };
class EmergencyParser {
 public:
  Emergency update(char c);

 private:
  enum class State { reset, n, m, m1, m10, m11, m4, m41, m108, m112, m410, ignore };
  State state_ = State::reset;
};

}  // namespace sim
