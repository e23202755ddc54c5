// Loading G-code for a job: commands as sent, layer marks, the hash, refusals.
#include "printer/gcode_file.h"

#include <doctest/doctest.h>
#include <fmt/core.h>

#include <filesystem>
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
  CHECK_FALSE(pieces.held());
  GcodeReader reader(pieces);
  bool same_commands = true;
  for (std::size_t i = 0; i < whole.size(); ++i) {
    same_commands &= reader.command(i) == whole.command(i) && reader.command_end(i) == whole.command_end(i);
  }
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

namespace gcode_file_test {

TEST_CASE("a_commands_end_is_the_byte_after_its_line_as_octoprints_filepos_counts") {
  const std::string text = "; header\nG28 ; home\n\n   \nG1 X1 Y2 E0.5\r\n;LAYER:0\nG1 X3\nM84";
  const GcodeFile file = parse_gcode(text, "t.gcode");
  REQUIRE(file.size() == 4);
  CHECK(file.command_end(0) == std::string("; header\nG28 ; home\n").size());
  CHECK(file.command_end(1) == text.find(";LAYER:0"));
  CHECK(file.command_end(2) == text.find("M84"));
  CHECK(file.command_end(3) == text.size());
}

TEST_CASE("a_file_on_disk_is_read_a_block_at_a_time_in_any_order_as_parsed_whole") {
  std::string text = "; header\nG28\n\n";
  for (int i = 0; i < 1000; ++i) {
    if (i % 90 == 0) text += fmt::format(";LAYER:{}\n;Z:{}\n", i / 90, 0.2 * (i / 90 + 1));
    text += fmt::format("G1 X{} Y1 E{} ; move\n", i % 100, i);
  }
  text += "; end\n";
  const std::string path = test_support::scratch_dir("gcode_file_blocks") + "/blocks.gcode";
  std::ofstream(path, std::ios::binary) << text;
  const GcodeFile whole = parse_gcode(text, path);
  const GcodeFile file = read_gcode_file(path, {}, 64);
  REQUIRE(file.size() == whole.size());
  CHECK(file.blocks().size() == (whole.size() + 63) / 64);
  // The blocks follow each other through the file, each to its last command's line end.
  bool adjacent = file.blocks().front().begin == 0;
  for (std::size_t b = 1; b < file.blocks().size(); ++b) adjacent &= file.blocks()[b].begin == file.blocks()[b - 1].end;
  CHECK(adjacent);
  CHECK(file.blocks().back().end == whole.command_end(whole.size() - 1));
  // Backwards, a block at a time: what a reader holds is one block.
  GcodeReader reader(file);
  bool same = true;
  for (std::size_t i = whole.size(); i-- > 0;) {
    same &= reader.command(i) == whole.command(i) && reader.command_end(i) == whole.command_end(i);
    same &= reader.commands_held() <= 64;
  }
  CHECK(same);
  CHECK(reader.command(700) == whole.command(700));
}

TEST_CASE("a_file_changed_in_place_is_refused_block_by_block_and_one_replaced_is_read_as_checked") {
  std::string text;
  for (int i = 0; i < 300; ++i) text += fmt::format("G1 X{} E{}\n", i % 10, i);
  const std::string dir = test_support::scratch_dir("gcode_file_changed");
  const std::string path = dir + "/c.gcode";
  std::ofstream(path, std::ios::binary) << text;
  const GcodeFile whole = parse_gcode(text, path);
  {
    // Replaced by another file under the same name (as an upload is renamed into place): the
    // reader opened before reads the file it checked.
    const GcodeFile file = read_gcode_file(path, {}, 64);
    GcodeReader reader(file);
    CHECK(reader.command(0) == "G1 X0 E0");
    std::ofstream(dir + "/other.gcode", std::ios::binary) << "G28\n";
    std::filesystem::rename(dir + "/other.gcode", path);
    bool same = true;
    for (std::size_t i = 0; i < whole.size(); ++i) same &= reader.command(i) == whole.command(i);
    CHECK(same);
  }
  std::ofstream(path, std::ios::binary) << text;
  const GcodeFile file = read_gcode_file(path, {}, 64);
  GcodeReader reader(file);
  CHECK(reader.command(10) == "G1 X0 E10");
  // Changed in place: one digit of command 200 (block 3); then a line added in block 0.
  std::string changed = text;
  changed.replace(changed.find("G1 X0 E200"), 10, "G1 X9 E200");
  std::ofstream(path, std::ios::binary | std::ios::in | std::ios::out) << changed;
  CHECK(reader.command(150) == "G1 X0 E150");  // block 2: as it was
  CHECK_THROWS_WITH_AS(reader.command(200),
                       (path + ": the file changed on disk while it printed (commands 193 to 256 are not "
                               "what was checked): nothing of it was sent from there; print the file "
                               "again once it stays as it is")
                           .c_str(),
                       GcodeFileChanged);
  changed = text;
  changed.replace(changed.find("G1 X0 E20\n"), 10, "G1 X0 E20\nG1 X0 E20\n");  // a line more
  std::ofstream(path, std::ios::binary) << changed;
  GcodeReader late(file);
  CHECK_THROWS_AS(late.command(0), GcodeFileChanged);
}

}  // namespace gcode_file_test
