// Loading G-code for a job: commands as sent, layer marks, the hash, refusals.
#include "printer/gcode_file.h"

#include <doctest/doctest.h>

#include <fstream>
#include <string>

#include "printer/error.h"
#include "printer/print_state.h"
#include "support/run_command.h"

namespace gcode_file_test {

using namespace printer;

TEST_CASE("commands_without_comments_and_layers_from_marks") {
  const GcodeFile f = parse_gcode(
      "; header\nG28 ; home\n\nM109 S210\n;LAYER:0\n;Z:0.2\nG1 Z0.2\nG1 X1 E1\n;LAYER:1\n;Z:0.4\nG1 X2 E2\n",
      "t.gcode");
  REQUIRE(f.size() == 5);
  CHECK(f.command(0) == "G28");
  CHECK(f.command(4) == "G1 X2 E2");
  REQUIRE(f.layers.size() == 2);
  CHECK(f.layers[0].number == 0);
  CHECK(f.layers[0].first_command == 2);
  CHECK(f.layers[0].z == 0.2);
  CHECK(f.layers[1].first_command == 4);
  CHECK(f.layer_index_of(1) == -1);
  CHECK(f.layer_index_of(3) == 0);
  CHECK(f.layer_starting_at(4) == 1);
  CHECK(f.layer_starting_at(3) == -1);
}

TEST_CASE("hash_changes_with_one_byte") {
  CHECK(content_hash("G1 X1\n") != content_hash("G1 X2\n"));
  CHECK(content_hash("G1 X1\n") == parse_gcode("G1 X1\n", "a").hash);
}

TEST_CASE("binary_and_overlong_lines_are_refused_naming_the_line") {
  CHECK_THROWS_WITH_AS(parse_gcode(std::string("G1\nG1 X\0", 8), "b.gcode"),
                       "b.gcode: line 2 contains NUL bytes: this is not a G-code text file", ConfigError);
  CHECK_THROWS_AS(parse_gcode("G1 X1 ; fine\n" + std::string(100, 'X') + "\n", "c.gcode"), ConfigError);
  CHECK_THROWS_AS(read_gcode_file("/nonexistent/x.gcode"), ConfigError);
}

TEST_CASE("print_state_follows_marlin_modes") {
  PrintState s;
  for (const char* c : {"G90", "M82", "G1 X10 Y5 Z0.2 E1 F1800", "G91", "G1 X1 E0.5", "G90",
                        "M83", "G1 E-1", "G92 E0", "M104 S215", "M140 S60", "M106 S128"}) {
    apply(s, c);
  }
  CHECK(s.x == 11);
  CHECK(s.y == 5);
  CHECK(s.e == 0);
  CHECK(s.relative_e);
  CHECK_FALSE(s.relative_xyz);
  CHECK(s.feedrate == 1800);
  CHECK(s.hotend_target == 215);
  CHECK(s.fan == 128);
  CHECK(s.filament_fed == doctest::Approx(1.5 - 1.0));
  CHECK(restore_modes(s) == std::vector<std::string>{"G90", "M83", "G1 F1800"});
}

TEST_CASE("a_file_that_is_not_gcode_is_refused_at_its_first_line") {
  std::string bytes;
  for (int line = 0; line < 50; ++line) {
    for (int b = 0x80; b <= 0xff; b += 7) bytes += static_cast<char>(b);
    bytes += '\n';
  }
  CHECK_THROWS_WITH_AS(parse_gcode(bytes, "noise.gcode"),
                       doctest::Contains("noise.gcode: line 1 is not G-code (it holds bytes that are not text"),
                       ConfigError);
  CHECK_THROWS_WITH_AS(parse_gcode("hello world\n", "hello.gcode"),
                       "hello.gcode: line 1 is not G-code (it does not start with a command word (G, M "
                       "or T and a number): \"hello world\"); every line must be a command such as G1 X10 "
                       "E0.5, or a ;comment: fix the line, or print with --force to leave such lines out",
                       ConfigError);
}

TEST_CASE("one_bad_line_among_valid_gcode_is_refused_by_its_number_or_skipped_and_counted") {
  const std::string text = "; start\nG28\nM109 S210\nG1 X1 E1\nG1 X2 E2,5\nG1 X3 E3\n;LAYER:0\nhello\nG1 X4\n";
  CHECK_THROWS_WITH_AS(parse_gcode(text, "one.gcode"), doctest::Contains("one.gcode: line 5 is not G-code"),
                       ConfigError);
  const GcodeFile kept = parse_gcode(text, "one.gcode", GcodeReading{true});
  CHECK(kept.size() == 5);
  CHECK(kept.command(3) == "G1 X3 E3");
  CHECK(kept.skipped_lines == 2);
  CHECK(kept.skipped_line_numbers == std::vector<std::size_t>{5, 8});
  REQUIRE(kept.layers.size() == 1);
  CHECK(kept.layers[0].first_command == 4);  // the layer starts at G1 X4, "hello" left out
}

TEST_CASE("a_file_read_in_pieces_is_the_file_parsed_whole_line_numbers_and_all") {
  // Over three pieces of kGcodePiece bytes: layer marks with their ;Z:, comments, blank
  // lines, lines that are not G-code (skipped or refused with their number in the file), and a
  // last line with no line end.
  std::string text = "; header\nG28\n";
  for (int layer = 0; text.size() < 2 * kGcodePiece + 100000; ++layer) {
    text += ";LAYER:" + std::to_string(layer) + "\n;Z:" + std::to_string(0.2 * (layer + 1)) + "\n";
    for (int i = 0; i < 2000; ++i) text += "G1 X" + std::to_string(i % 100) + " Y1 E0.01 ; move\n\n";
    if (layer % 3 == 2) text += "hello\n";
  }
  text += "M84";
  const std::string path = test_support::scratch_dir("gcode_file_pieces") + "/big.gcode";
  const auto write = [&](const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; };
  write(text);
  const GcodeReading skip{.skip_invalid = true};
  const GcodeFile whole = parse_gcode(text, path, skip);
  const GcodeFile pieces = read_gcode_file(path, skip);
  REQUIRE(pieces.size() == whole.size());
  bool same_commands = true;
  for (std::size_t i = 0; i < whole.size(); ++i) same_commands &= pieces.command(i) == whole.command(i);
  CHECK(same_commands);
  REQUIRE(pieces.layers.size() == whole.layers.size());
  bool same_layers = true;
  for (std::size_t l = 0; l < whole.layers.size(); ++l) {
    const GcodeLayer &a = pieces.layers[l], &b = whole.layers[l];
    same_layers &= a.number == b.number && a.first_command == b.first_command && a.z == b.z;
  }
  CHECK(same_layers);
  CHECK(pieces.hash == whole.hash);
  CHECK(pieces.skipped_lines == whole.skipped_lines);
  CHECK(pieces.skipped_line_numbers == whole.skipped_line_numbers);
  CHECK(whole.skipped_lines > 3);
  // Without skip_invalid, a bad line deep in the third piece (the only one): the same
  // message, the same line number, from both.
  std::string message_whole, message_pieces;
  std::string bad;
  for (std::size_t at = 0, end; at < text.size(); at = end) {
    end = std::min(text.find('\n', at), text.size() - 1) + 1;
    if (text.compare(at, 6, "hello\n") != 0) bad.append(text, at, end - at);
  }
  bad.insert(bad.find('\n', 2 * kGcodePiece + 1000) + 1, "G1 X1e999\n");
  write(bad);
  try {
    parse_gcode(bad, path);
  } catch (const ConfigError& e) {
    message_whole = e.what();
  }
  try {
    read_gcode_file(path);
  } catch (const ConfigError& e) {
    message_pieces = e.what();
  }
  CHECK(message_whole.find(" is not G-code (X1e999") != std::string::npos);
  CHECK(message_pieces == message_whole);
}

}  // namespace gcode_file_test
