// One line of G-code as host and firmware read it (printer/gcode_line.h). Checksums worked
// out by hand: XOR of the bytes before '*'.
#include <doctest/doctest.h>

#include "printer/gcode_line.h"

namespace gcode_line_test {

TEST_CASE("checksum_is_the_xor_of_the_bytes") {
  CHECK(printer::gcode_checksum("") == 0);
  CHECK(printer::gcode_checksum("N1 M105") == 38);
  CHECK(printer::gcode_checksum("N-1 M110") == 15);
  CHECK(printer::gcode_checksum("AA") == 0);
}

TEST_CASE("frame_line_numbers_and_checksums") {
  CHECK(printer::frame_line(1, "M105") == "N1 M105*38");
  CHECK(printer::frame_line(-1, "M110") == "N-1 M110*15");
}

TEST_CASE("parse_gcode_line_reads_command_words_and_comment") {
  const auto c = printer::parse_gcode_line("  G1 X10 Y-5.5 E.3 F1800 ; TYPE:WALL-OUTER ");
  CHECK(c.letter == 'G');
  CHECK(c.code == 1);
  CHECK(c.is('G', 1));
  CHECK(c.text == "G1 X10 Y-5.5 E.3 F1800");
  CHECK(c.comment == "TYPE:WALL-OUTER");
  REQUIRE(c.words.size() == 4);
  CHECK(c.get('X') == 10);
  CHECK(c.get('Y') == -5.5);
  CHECK(c.get('E') == doctest::Approx(0.3));
  CHECK(c.get('F') == 1800);
  CHECK_FALSE(c.has('Z'));
}

TEST_CASE("parse_gcode_line_is_case_blind_and_total") {
  const auto lower = printer::parse_gcode_line("g1 x2");
  CHECK(lower.is('G', 1));
  CHECK(lower.get('X') == 2);
  CHECK(printer::parse_gcode_line("").empty());
  CHECK(printer::parse_gcode_line("   ").empty());
  const auto comment = printer::parse_gcode_line(";LAYER:3");
  CHECK(comment.empty());
  CHECK(comment.comment == "LAYER:3");
  const auto no_command = printer::parse_gcode_line("X10");
  CHECK(no_command.letter == 'X');
  CHECK(no_command.code == -1);
  CHECK(printer::parse_gcode_line("T0").is('T', 0));
  const auto sub = printer::parse_gcode_line("G29.1 S2");
  CHECK(sub.is('G', 29));
  CHECK(sub.subcode == 1);
  CHECK(sub.get('S') == 2);
  CHECK(printer::parse_gcode_line("G29 S2").subcode == 0);
  // A letter without a value is seen (parser.seen) but has none (parser.seenval).
  const auto bare = printer::parse_gcode_line("M84 X");
  CHECK(bare.has('X'));
  CHECK_FALSE(bare.get('X'));
}

TEST_CASE("parse_numbered_line_splits_number_command_and_checksum") {
  const auto good = printer::parse_numbered_line("N12 G1 X5*86 ; note");
  CHECK(good.line_number == 12);
  CHECK(good.command == "G1 X5");
  CHECK(good.checksum == 86);
  CHECK(good.checksum_ok);
  const auto framed = printer::parse_numbered_line(printer::frame_line(7, "M105"));
  CHECK(framed.line_number == 7);
  CHECK(framed.checksum_ok);
  CHECK(framed.command == "M105");
  const auto bad = printer::parse_numbered_line("N1 M105*39");
  CHECK_FALSE(bad.checksum_ok);
  const auto garbage = printer::parse_numbered_line("N1 M105*x");
  CHECK(garbage.checksum == -1);
  CHECK_FALSE(garbage.checksum_ok);
  const auto plain = printer::parse_numbered_line("M105");
  CHECK_FALSE(plain.line_number.has_value());
  CHECK_FALSE(plain.checksum.has_value());
  CHECK(plain.checksum_ok);
  CHECK(plain.command == "M105");
  CHECK(printer::parse_numbered_line("N-1 M110*15").line_number == -1);
  CHECK(printer::parse_numbered_line("N-1 M110*15").checksum_ok);
}

TEST_CASE("gcode_problem_passes_what_slicers_write") {
  for (const char* line :
       {"G1 X10.5 Y-3 E.25 F1800", "G1X10Y20", "G28 X Y", "M84 X Y E", "T0", "M104 S215 T0",
        "M862.3 P \"MK3S\"", "M862.1 P0.4", "M115 U3.9.0", "M117 Printing layer 3 of 40!",
        "M486 S-1", "G29.1", "m105", "M0 Click to resume", "G1 E1e-3", "M205 X8.00 Y8.00 Z0.40"}) {
    CAPTURE(line);
    CHECK_FALSE(printer::gcode_problem(line));
  }
}

TEST_CASE("gcode_problem_names_what_is_wrong") {
  CHECK(printer::gcode_problem("hello world") == "it does not start with a command word (G, M or T and a number)");
  CHECK(printer::gcode_problem("G hello") == "its command word has no number");
  CHECK(printer::gcode_problem("\x80\x81\xfe") == "it holds bytes that are not text");
  CHECK(printer::gcode_problem("N12 G1 X1") == "line numbers are for the host to add");
  CHECK(printer::gcode_problem("G1 X1*25") == "checksums are for the host to add");
  CHECK(printer::gcode_problem("G1 X=10") == "it has a parameter whose value is not a number");
  CHECK(printer::gcode_problem("G1 X10 #5") == "it has a parameter that does not start with a letter");
  CHECK(printer::gcode_problem("M862.3 P \"MK3S") == "a quoted parameter is not closed");
  CHECK(printer::gcode_problem("G1- X1") == "its command word is followed by something that is not a parameter");
  // Past a 32-bit float, which is what firmware reads a number into.
  CHECK(printer::gcode_problem("G1 X1e999 Y5") == "X1e999 is too large for a printer's numbers");
  CHECK(printer::gcode_problem("M104 S-4e38") == "S-4e38 is too large for a printer's numbers");
  CHECK_FALSE(printer::gcode_problem("G1 X3e38 E+1e-300"));
  // Without an exponent: 38 digits before the point stay below 3.4e38 whatever they are, 39 may not.
  const std::string nines38(38, '9'), nines39(39, '9');
  CHECK_FALSE(printer::gcode_problem("G1 X-" + nines38 + ".9 Y+" + nines38));
  CHECK_FALSE(printer::gcode_problem("G1 X" + std::string(39, '1') + ".5"));  // 1.1e38
  CHECK(printer::gcode_problem("G1 X" + nines39) == "X" + nines39 + " is too large for a printer's numbers");
  CHECK(printer::gcode_problem("G1 E-" + nines39 + ".5") == "E-" + nines39 + ".5 is too large for a printer's numbers");
}

}  // namespace gcode_line_test
