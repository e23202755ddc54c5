// The simulated printer in Teacup's and Repetier's dialects, against their literal replies.
// Teacup's transcripts are what its own host-side simulator (Traumflug/Teacup_Firmware,
// Makefile-SIM, stock config.default.h) answered to the same bytes over a pseudo-terminal;
// its source says why (mendel.c, gcode_parse.c, gcode_process.c, temp.c, clock.c). Repetier's
// come from its source (src/ArduinoAVR/Repetier/gcode.cpp, Commands.cpp, Communication.cpp).
// Checksums worked out by hand (XOR of the bytes before '*').
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "printer/gcode_line.h"
#include "sim/printer.h"

namespace dialect_test {

namespace {

struct Bench {
  sim::Printer printer;
  std::string banner;
  explicit Bench(sim::Config config) : printer(std::move(config)) {
    printer.run_until(0.05);
    banner = printer.take_output();
  }
  explicit Bench(sim::Dialect dialect, std::string faults = "") : Bench(config(dialect, faults)) {}
  static sim::Config config(sim::Dialect dialect, const std::string& faults) {
    sim::Config c;
    c.dialect = dialect;
    c.faults = sim::parse_fault_spec(faults);
    return c;
  }
  std::string send(std::string_view bytes, double seconds = 0.1) {
    printer.receive(bytes);
    printer.run_until(printer.now() + seconds);
    return printer.take_output();
  }
  // A numbered line with its checksum, as a host frames it.
  std::string line(long n, std::string_view command) { return send(printer::frame_line(n, command) + "\n"); }
};

}  // namespace

TEST_CASE("dialect_names_parse") {
  CHECK(sim::parse_dialect("teacup") == sim::Dialect::teacup);
  CHECK(sim::parse_dialect("repetier") == sim::Dialect::repetier);
  CHECK(sim::parse_dialect("marlin") == sim::Dialect::marlin);
  CHECK_FALSE(sim::parse_dialect("klipper"));
}

TEST_CASE("teacup_prints_a_commands_output_then_its_ok_on_a_line_of_its_own") {
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.banner == "start\nok\n");  // mendel.c: "start\nok\n"
  CHECK(bench.line(1, "M110 N1") == "ok\n");
  CHECK(bench.line(2, "M105") == "T:20.0/0.0 B:20.0/0.0\nok\n");
  CHECK(bench.line(3, "M114") == "X:0.000,Y:0.000,Z:0.000,E:0.000,F:1500\nok\n");
  CHECK(bench.line(4, "M115") ==
        "FIRMWARE_NAME:Teacup FIRMWARE_URL:http://github.com/traumflug/Teacup_Firmware/ "
        "PROTOCOL_VERSION:1.0 MACHINE_TYPE:Mendel EXTRUDER_COUNT:1 TEMP_SENSOR_COUNT:2 "
        "HEATER_COUNT:2\ncap:AUTOREPORT_TEMP:1\nok\n");
  CHECK(bench.send("\n") == "ok\n");  // an empty line is a line too
}

TEST_CASE("teacup_g92_reads_a_bare_axis_as_zero_and_no_axis_as_all_four_zero") {
  // gcode_process.c case 92: a seen axis takes the parsed value (0 for "X" alone); with no
  // axis seen, X, Y, Z and E are all set to 0. Marlin's G92 changes neither.
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.line(1, "G92 X5 Y6 Z7 E8") == "ok\n");
  CHECK(bench.line(2, "M114") == "X:5.000,Y:6.000,Z:7.000,E:8.000,F:1500\nok\n");
  CHECK(bench.line(3, "G92 X") == "ok\n");
  CHECK(bench.line(4, "M114") == "X:0.000,Y:6.000,Z:7.000,E:8.000,F:1500\nok\n");
  CHECK(bench.line(5, "G92") == "ok\n");
  CHECK(bench.line(6, "M114") == "X:0.000,Y:0.000,Z:0.000,E:0.000,F:1500\nok\n");
}

TEST_CASE("teacup_reads_x_y_z_e_and_f_in_inches_after_g20") {
  // gcode_process.c case 20 sets option_inches; gcode_parse.c then reads X Y Z E in inches
  // and F times 25.4 (254/10). The sim kept millimetres.
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.line(1, "G20") == "ok\n");
  CHECK(bench.line(2, "G1 X1 Y0.5 F60") == "ok\n");
  CHECK(bench.line(3, "M114") == "X:25.400,Y:12.700,Z:0.000,E:0.000,F:1524\nok\n");
  CHECK(bench.line(4, "G21") == "ok\n");
  CHECK(bench.line(5, "G1 X1") == "ok\n");
  CHECK(bench.printer.position().x == 1);
}

TEST_CASE("teacup_and_repetier_keep_e_relative_while_g91_or_m83_holds") {
  // Teacup's gcode_process.c: E is relative when option_all_relative || option_e_relative;
  // Repetier's Printer.cpp: relativeCoordinateMode || relativeExtruderCoordinateMode. So
  // G90 after M83 leaves E relative, where Marlin's G90 makes it absolute.
  for (const sim::Dialect dialect : {sim::Dialect::teacup, sim::Dialect::repetier}) {
    CAPTURE(sim::to_string(dialect));
    Bench bench(dialect);
    bench.line(1, "M83");
    bench.line(2, "G90");
    bench.line(3, "G1 X1 E1");
    bench.line(4, "G1 X2 E1");
    bench.send("", 5);
    CHECK(bench.printer.position().e == 2);
  }
  Bench marlin(sim::Dialect::marlin);
  marlin.send("M83\nG90\nG1 X1 E1\nG1 X2 E1\n", 5);
  CHECK(marlin.printer.position().e == 1);
}

TEST_CASE("teacup_g161_homes_only_the_axes_it_names") {
  // gcode_process.c case 161: home_x_negative() if seen_X, and so on; no axis, no homing.
  // The sim homed all three for a bare G161.
  Bench bench(sim::Dialect::teacup);
  bench.line(1, "G1 X10 Y10 Z5");
  bench.line(2, "G161 X");
  bench.send("", 30);
  CHECK(bench.printer.position().x == 0);
  CHECK(bench.printer.position().y == 10);
  bench.line(3, "G161");
  bench.send("", 30);
  CHECK(bench.printer.position().y == 10);
  CHECK(bench.printer.position().z == 5);
}

TEST_CASE("repetier_reads_inches_after_g20") {
  // Commands.cpp case 20 sets unitIsInches; Printer.cpp's convertToMM then reads X Y Z E in
  // inches. The sim kept millimetres.
  Bench bench(sim::Dialect::repetier);
  bench.line(1, "G20");
  bench.line(2, "G1 X2 F60");
  bench.send("", 5);
  CHECK(bench.printer.position().x == doctest::Approx(50.8));
}

TEST_CASE("repetier_reports_m114_in_inches_after_g20") {
  // Commands.cpp printCurrentPosition: each coordinate times 0.03937 while unitIsInches.
  Bench bench(sim::Dialect::repetier);
  bench.line(1, "G20");
  bench.line(2, "G1 X2 Y1 Z0.5 F60");
  CHECK(bench.line(3, "M114").find("X:2.00 Y:1.00 Z:0.500 E:0.0000") != std::string::npos);
  bench.line(4, "G21");
  CHECK(bench.line(5, "M114").find("X:50.80 Y:25.40 Z:12.700 E:0.0000") != std::string::npos);
}

TEST_CASE("teacup_refuses_what_it_does_not_have_and_still_says_ok") {
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.line(1, "M107") == "E: Bad M-code 107\nok\n");
  CHECK(bench.send("M190 S60\n") == "E: Bad M-code 190\nok\n");
  CHECK(bench.line(2, "G2 X1 Y1 I1") == "E: Bad G-code 2\nok\n");
  CHECK(bench.line(3, "M400") == "E: Bad M-code 400\nok\n");
  CHECK(bench.line(4, "T0") == "ok\n");
  CHECK(bench.printer.counters().unknown_commands == 4);
}

TEST_CASE("teacup_ignores_line_numbers_and_runs_a_line_sent_twice_twice") {
  // Without REQUIRE_LINENUMBER (gcode_parse.h) N is never looked at: the Teacup simulator
  // moved to X2 for "N5 G1 X1" then "N5 G1 X2" and ran "N3 M115" after N7.
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.line(5, "G1 X1 F3000") == "ok\n");
  CHECK(bench.line(5, "G1 X2") == "ok\n");
  CHECK(bench.line(5, "G91") == "ok\n");
  CHECK(bench.line(5, "G1 X1") == "ok\n");
  CHECK(bench.line(5, "G1 X1") == "ok\n");
  CHECK(bench.printer.executed_commands() ==
        std::vector<std::string>{"G1 X1 F3000", "G1 X2", "G91", "G1 X1", "G1 X1"});
  bench.printer.finish();
  CHECK(bench.printer.position().x == 4.0);  // the relative move ran twice
}

TEST_CASE("teacup_asks_again_with_rs_and_still_says_ok") {
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.line(5, "G1 X2") == "ok\n");
  // A wrong checksum: N_expected follows the last numbered line run (gcode_parse.c).
  CHECK(bench.send("N6 G1 X3*1\n") == "rs N6 Expected checksum 101\nok\n");
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"G1 X2"});
}

TEST_CASE("teacup_with_require_linenumber_takes_any_number_from_the_expected_one") {
  sim::Config config = Bench::config(sim::Dialect::teacup, "");
  config.teacup_require_linenumber = true;
  Bench bench(config);
  CHECK(bench.line(1, "M110 N1") == "ok\n");
  CHECK(bench.line(5, "G1 X1") == "ok\n");  // N2..N4 never came: taken all the same
  CHECK(bench.line(5, "G1 X2") == "rs N6 Expected line number 6\nok\n");
  CHECK(bench.send("G1 X3\n") == "rs N6 Expected line number 6\nok\n");  // unnumbered
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"M110 N1", "G1 X1"});
}

TEST_CASE("teacup_m116_lets_the_next_move_wait_saying_so_each_second") {
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.line(1, "M140 S60") == "ok\n");
  CHECK(bench.line(2, "M116") == "ok\n");  // ok at once: only a flag (temp_set_wait)
  CHECK(bench.send("", 2.05) == "Waiting for target temp\nWaiting for target temp\n");
  bench.printer.receive(printer::frame_line(3, "G1 X2") + "\n");
  // The bed (sim/config.h: 300 s, 0.6 °C/s) from 20 to 50 °C (TEMP_HYSTERESIS 10 below the
  // target), then TEMP_RESIDENCY_TIME 60 s.
  const double tmax = 20 + 0.6 * 300;
  const double settled = 300 * std::log((tmax - 20) / (tmax - 50)) + 60;
  bench.printer.run_until(settled - 0.5);
  std::string said = bench.printer.take_output();
  CHECK(said.find("ok") == std::string::npos);  // the G1 waits (temp_wait)
  CHECK(said.find("Waiting for target temp") != std::string::npos);
  bench.printer.run_until(settled + 1.5);
  said = bench.printer.take_output();
  CHECK(said.find("ok\n") != std::string::npos);
  CHECK(said.find("Temp achieved\n") != std::string::npos);
  CHECK(bench.printer.bed_temperature() > 50);
}

TEST_CASE("teacup_m112_freezes_without_a_word") {
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.line(1, "M104 S200") == "ok\n");
  CHECK(bench.send("M112\n").empty());
  CHECK(bench.send("M105\n").empty());
  CHECK(bench.printer.hotend_target() == 0);
}

TEST_CASE("repetier_answers_ok_with_the_line_number_when_queued_and_the_output_after") {
  Bench bench(sim::Dialect::repetier);
  CHECK(bench.banner == "start\nInfo:External Reset\nFree RAM:3420\n");
  CHECK(bench.line(1, "M105") == "ok 1\nT:20.00 /0 B:20.00 /0 B@:0 @:0\n");
  CHECK(bench.line(2, "M113 S1") == "ok 2\nUnknown command:N2 M113  S1\n");
  CHECK(bench.line(3, "M110 N3") == "ok\n");  // taken as it is read, a plain ok
  CHECK(bench.line(4, "G21") == "ok 4\n");  // units, in every build (Commands.cpp processGCode)
  CHECK(bench.printer.counters().unknown_commands == 1);
}

TEST_CASE("repetier_resend_request_has_its_ok_skips_what_it_has_and_repeats") {
  Bench bench(sim::Dialect::repetier);
  CHECK(bench.line(1, "G1 X1") == "ok 1\n");
  CHECK(bench.send("N2 G1 X2*1\n", 0.05) == "Error:Wrong checksum\n\nResend:2\nok\n");
  CHECK(bench.line(4, "G1 X4") == "skip 4\nok\n");  // sent before the request came
  CHECK(bench.line(2, "G1 X2") == "ok 2\n");
  // A line it has already is not run again (the host's probe of a lost ok).
  CHECK(bench.line(2, "G1 X2") == "skip 2\nok\n");
  CHECK(bench.line(5, "G1 X5") == "Error:expected line 3 got 5\n\nResend:3\nok\n");
  // No input for 200 ms while it waits for line 3: it asks again.
  CHECK(bench.send("", 0.25) == "\nResend:3\nok\n");
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"G1 X1", "G1 X2"});
}

TEST_CASE("repetier_says_wait_after_a_second_without_input") {
  Bench bench(sim::Dialect::repetier);
  CHECK(bench.send("", 1.2) == "wait\n");
  CHECK(bench.line(1, "G1 X1") == "ok 1\n");
  CHECK(bench.send("", 0.8).empty());
  CHECK(bench.send("", 0.3) == "wait\n");
}

TEST_CASE("repetier_m112_stops_as_it_is_read") {
  Bench bench(sim::Dialect::repetier);
  CHECK(bench.line(1, "M104 S200") == "ok 1\n");
  CHECK(bench.send("M112\n").empty());
  CHECK(bench.printer.state() == sim::PrinterState::halted);
  CHECK(bench.printer.hotend_target() == 0);
}

TEST_CASE("drop_blocking_ok_loses_the_ok_of_the_next_blocking_commands_only") {
  Bench bench(sim::Dialect::marlin, "drop-blocking-ok=1");
  bench.send("N1 G28*18\n", 60);
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"G28"});
  const std::string after = bench.send("N2 M105*37\n");
  CHECK(after.find("ok T:") != std::string::npos);  // the next one has its ok
  CHECK(bench.printer.counters().faults_injected == 1);
  // The firmware sat idle from the end of homing to the M105: that wait is the lost ok's.
  REQUIRE(bench.printer.lost_ok_waits().size() == 1);
  CHECK(bench.printer.lost_ok_waits()[0] > 30);
  CHECK(bench.printer.counters().longest_idle >= bench.printer.lost_ok_waits()[0]);
}

}  // namespace dialect_test
