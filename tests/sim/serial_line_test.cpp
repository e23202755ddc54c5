// Marlin's reading of a serial line (sim/serial_line.h), piece by piece, literal.
#include <doctest/doctest.h>

#include <string>

#include "sim/serial_line.h"

namespace serial_line_test {

namespace {
std::string assemble(std::string_view bytes, int max_cmd_size = 96) {
  sim::LineAssembler line(max_cmd_size);
  for (char c : bytes) line.feed(c);
  return line.take();
}
}  // namespace

TEST_CASE("strtol_as_marlin_calls_it") {
  CHECK(sim::marlin_strtol("42") == 42);
  CHECK(sim::marlin_strtol(" -1 M110") == -1);
  CHECK(sim::marlin_strtol("x") == 0);
  CHECK(sim::marlin_strtol("") == 0);
  CHECK(sim::marlin_strtol("4u") == 4);
}

TEST_CASE("assembler_strips_comments_escapes_and_backspaces") {
  CHECK(assemble("G1 X1 ; move") == "G1 X1 ");
  CHECK(assemble("M117 a\\;b") == "M117 a;b");
  CHECK(assemble("G92 X9\b7") == "G92 X7");
  CHECK(assemble("\b\bM105") == "M105");
  CHECK(assemble(std::string(200, 'x'), 10) == std::string(9, 'x'));
}

TEST_CASE("check_line_in_marlins_order") {
  using V = sim::LineVerdict;
  CHECK(sim::check_line("M105", 0).verdict == V::unnumbered);
  CHECK(sim::check_line("M105*99", 0).verdict == V::unnumbered);
  CHECK(sim::check_line("N1 M105*38", 0).verdict == V::accepted);
  CHECK(sim::check_line("  N1 M105*38", 0).verdict == V::accepted);  // blanks skipped first
  CHECK(sim::check_line("N1 M105*39", 0).verdict == V::checksum_mismatch);
  CHECK(sim::check_line("N1 M105", 0).verdict == V::no_checksum);
  CHECK(sim::check_line("N2 M105*37", 0).verdict == V::wrong_line_number);
  CHECK(sim::check_line("N2 M105", 0).verdict == V::wrong_line_number);  // number first
  // M110 skips the number check and takes the N after it.
  const sim::LineCheck reset = sim::check_line("N1 M110 N100*125", 50);
  CHECK(reset.verdict == V::accepted);
  CHECK(reset.number == 100);
  CHECK(sim::check_line("N-1 M110*15", 7).number == -1);
  CHECK(sim::check_line("N-1 M110*15", 7).verdict == V::accepted);
  CHECK(sim::check_line("n1 M105*6", 0).verdict == V::unnumbered);  // only a capital N counts
}

TEST_CASE("error_texts_are_marlins") {
  CHECK(sim::error_text(sim::LineVerdict::wrong_line_number) ==
        "Line Number is not Last Line Number+1, Last Line: ");
  CHECK(sim::error_text(sim::LineVerdict::no_checksum) == "No Checksum with line number, Last Line: ");
  CHECK(sim::error_text(sim::LineVerdict::checksum_mismatch) == "checksum mismatch, Last Line: ");
}

TEST_CASE("command_text_is_what_the_parser_sees") {
  CHECK(sim::command_text("N5 G1 X1 *23") == "G1 X1");
  CHECK(sim::command_text("N-1 M110*15") == "M110");
  CHECK(sim::command_text("  M105  ") == "M105");
  CHECK(sim::command_text("N12") == "");
  CHECK(sim::command_text("NX") == "NX");
}

TEST_CASE("emergency_parser_sees_m112_in_any_line_form") {
  const auto last = [](std::string_view bytes) {
    sim::EmergencyParser parser;
    sim::Emergency seen = sim::Emergency::none;
    for (char c : bytes) {
      if (const auto e = parser.update(c); e != sim::Emergency::none) seen = e;
    }
    return seen;
  };
  CHECK(last("M112\n") == sim::Emergency::m112);
  CHECK(last("N7 M112*38\n") == sim::Emergency::m112);
  CHECK(last("M108\r") == sim::Emergency::m108);
  CHECK(last("M410\n") == sim::Emergency::m410);
  CHECK(last("M112") == sim::Emergency::none);  // not until the line ends
  CHECK(last("G1 M112\n") == sim::Emergency::none);
  CHECK(last("M1120\n") == sim::Emergency::m112);  // as Marlin's: what follows is not read
  CHECK(last("M105\nM112\n") == sim::Emergency::m112);
}

}  // namespace serial_line_test
