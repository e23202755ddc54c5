// One line of G-code, as the host sends it and the firmware (ours or Marlin) reads it.
//
// Shared by the G-code writer's tests, the simulated printer and the host, so that all three
// agree on what a line means. Every function is total: any input gives a defined result.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace printer {

struct GcodeWord {
  char letter = 0;  // upper case
  std::optional<double> value;  // none for a letter alone ("X" in "G28 X")
};

struct GcodeCommand {
  char letter = 0;    // 'G', 'M' or 'T'; 0 for a line with no command (empty or comment only)
  int code = -1;      // 1 for G1, 109 for M109
  int subcode = 0;    // 1 for G92.1; 0 when none is written
  std::vector<GcodeWord> words;  // parameters in the order written (X, Y, E, S, ...)
  std::string text;   // the command without comment or surrounding blanks: "G1 X10 Y5 E0.3"
  std::string comment;  // text after ';' without the ';', trimmed ("LAYER:3", "TYPE:WALL-OUTER")

  bool empty() const { return letter == 0; }
  bool is(char l, int c) const { return letter == l && code == c; }
  // The word's value, none when the word is absent or written without one: Marlin's
  // parser.seenval (gcode/parser.h), which G0-G3, G92, M104 and most commands read.
  std::optional<double> get(char word) const;
  // Whether the word is written at all, with or without a value: parser.seen, which G28
  // reads ("G28 X" homes X).
  bool has(char word) const;
};

// Parses a line without line number or checksum (use parse_numbered_line first for those).
GcodeCommand parse_gcode_line(std::string_view line);

// Why a command (a line without its comment, trimmed, not empty) is not G-code a printer
// should be sent, or nullopt when it is: it must start with a command word (G, M or T and a
// number, "G1", "M862.3", "T0"), then parameters each a letter with an optional number
// ("X10.5", "E-.2", "X" alone as in "G28 X") or a quoted string (P"MK3S"); M0/M1, M16, M23,
// M28, M30, M32, M117, M118 and M928 take free text. Line numbers and checksums are the
// host's to add, so N and '*' are refused; so is any byte outside printable ASCII, and a
// value past a 32-bit float's range (X1e999), which firmware would read as infinite.
std::optional<std::string> gcode_problem(std::string_view command);

// Whether the command's words after the command word are free text, not parameters: M0/M1,
// M16, M23, M28, M30, M32, M117, M118 and M928 ("M117 Hello" shows "Hello").
bool takes_text(const GcodeCommand& command);

// The checksum Marlin checks: XOR of every byte before '*'.
std::uint8_t gcode_checksum(std::string_view bytes);

// "N<n> <command>*<checksum>" (no line end).
std::string frame_line(long line_number, std::string_view command);

// A line as it arrives at the firmware: optional "N<n> ", command, optional "*<checksum>".
struct NumberedLine {
  std::optional<long> line_number;
  std::optional<int> checksum;  // as written after '*'
  bool checksum_ok = true;      // true when there is no checksum or it matches
  std::string command;          // between the number and the '*', trimmed, comment removed
};
NumberedLine parse_numbered_line(std::string_view line);

}  // namespace printer
