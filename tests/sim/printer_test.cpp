// The simulated printer against hand-written byte streams: every reply compared literally
// with what Marlin 2.x sends (Marlin/src/gcode/queue.cpp, gcode.cpp, temperature.cpp).
// Checksums in the streams were worked out by hand (XOR of the bytes before '*').
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "printer/print_time.h"
#include "sim/gcode_deposition.h"
#include "sim/printer.h"

namespace printer_test {

namespace {

// A printer past its power-on banner.
struct Bench {
  sim::Printer printer;
  explicit Bench(sim::Config config = {}) : printer(std::move(config)) {
    printer.run_until(0.5);
    printer.take_output();
  }
  // Sends bytes, lets `seconds` of sim time pass, returns what the firmware said.
  std::string send(std::string_view bytes, double seconds = 0.5) {
    printer.receive(bytes);
    printer.run_until(printer.now() + seconds);
    return printer.take_output();
  }
};

}  // namespace

TEST_CASE("start_banner_on_power_on") {
  sim::Printer printer;
  printer.run_until(1e-3);
  CHECK(printer.take_output() ==
        "start\n"
        "echo:Marlin 2.1.2\n"
        "echo: Last Updated: 2021-12-25 | Author: (mahost simulated printer)\n");
  CHECK(printer.counters().resets == 1);
}

TEST_CASE("input_during_boot_is_lost") {
  sim::Config config;
  config.boot_time = 1.5;
  sim::Printer printer(config);
  printer.receive("M105\n");
  printer.run_until(1.0);
  CHECK(printer.take_output().empty());
  printer.run_until(2.0);
  CHECK(printer.take_output().starts_with("start\n"));
  CHECK(printer.executed_commands().empty());
}

TEST_CASE("numbered_line_with_good_checksum_gets_ok") {
  Bench bench;
  CHECK(bench.send("N1 M105*38\n") == "ok T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n");
  CHECK(bench.send("N2 M114*37\n") == "X:0.00 Y:0.00 Z:0.00 E:0.00 Count X:0 Y:0 Z:0\nok\n");
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"M105", "M114"});
}

TEST_CASE("checksum_mismatch_answers_error_resend_ok") {
  Bench bench;
  CHECK(bench.send("N1 M105*39\n") ==
        "Error:checksum mismatch, Last Line: 0\nResend: 1\nok\n");
  CHECK(bench.printer.executed_commands().empty());
  CHECK(bench.printer.counters().errors == 1);
  CHECK(bench.printer.counters().resends == 1);
}

TEST_CASE("skipped_line_number_answers_line_number_error") {
  Bench bench;
  CHECK(bench.send("N2 M105*37\n") ==
        "Error:Line Number is not Last Line Number+1, Last Line: 0\nResend: 1\nok\n");
}

TEST_CASE("line_number_is_checked_before_checksum") {
  // Marlin checks the number first: a bad number with a bad checksum reports the number.
  Bench bench;
  CHECK(bench.send("N3 M105*0\n") ==
        "Error:Line Number is not Last Line Number+1, Last Line: 0\nResend: 1\nok\n");
}

TEST_CASE("numbered_line_without_checksum_is_refused") {
  Bench bench;
  CHECK(bench.send("N1 M105\n") ==
        "Error:No Checksum with line number, Last Line: 0\nResend: 1\nok\n");
}

TEST_CASE("resend_without_ok_when_configured") {
  sim::Config config;
  config.ok_after_resend = false;
  Bench bench(config);
  CHECK(bench.send("N1 M105*39\n") == "Error:checksum mismatch, Last Line: 0\nResend: 1\n");
}

TEST_CASE("repeated_line_is_refused_and_not_executed_twice") {
  Bench bench;
  CHECK(bench.send("N1 M105*38\n").starts_with("ok T:"));
  CHECK(bench.send("N1 M105*38\n") ==
        "Error:Line Number is not Last Line Number+1, Last Line: 1\nResend: 2\nok\n");
  CHECK(bench.printer.executed_commands().size() == 1);
}

TEST_CASE("printrun_m110_reset_sets_next_line_to_zero") {
  Bench bench;
  CHECK(bench.send("N1 M105*38\n").starts_with("ok"));
  CHECK(bench.send("N-1 M110*15\n") == "ok\n");
  CHECK(bench.send("N0 M105*39\n").starts_with("ok T:"));
}

TEST_CASE("m110_with_n_sets_the_line_number") {
  Bench bench;
  CHECK(bench.send("N1 M110 N100*125\n") == "ok\n");
  CHECK(bench.send("N101 M105*39\n").starts_with("ok T:"));
  CHECK(bench.send("M110 N0\n") == "ok\n");
  CHECK(bench.send("N1 M105*38\n").starts_with("ok T:"));
}

TEST_CASE("unnumbered_lines_are_not_checked") {
  Bench bench;
  CHECK(bench.send("M105*99\n").starts_with("ok T:"));
  CHECK(bench.send("  G92 X1\n") == "ok\n");
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"M105", "G92 X1"});
}

TEST_CASE("comments_blank_lines_and_carriage_returns") {
  Bench bench;
  CHECK(bench.send("; only a comment\n\n\r\nG92 X5 ; set x\rM114\r\n") ==
        "ok\nX:5.00 Y:0.00 Z:0.00 E:0.00 Count X:400 Y:0 Z:0\nok\n");
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"G92 X5", "M114"});
}

TEST_CASE("backspace_erases_the_previous_character") {
  Bench bench;
  CHECK(bench.send("G92 X9\b7\n") == "ok\n");
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"G92 X7"});
}

TEST_CASE("over_long_line_is_cut_at_max_cmd_size") {
  Bench bench;
  const std::string text = "M117 " + std::string(200, 'x');
  CHECK(bench.send(text + "\n") == "ok\n");
  REQUIRE(bench.printer.executed_commands().size() == 1);
  CHECK(bench.printer.executed_commands()[0] == text.substr(0, 95));
  CHECK(bench.printer.counters().long_lines == 1);
}

TEST_CASE("unknown_command_echo_then_ok") {
  Bench bench;
  CHECK(bench.send("M9999 X1\n") == "echo:Unknown command: \"M9999 X1\"\nok\n");
  CHECK(bench.send("G20\n") == "echo:Unknown command: \"G20\"\nok\n");
  CHECK(bench.printer.counters().unknown_commands == 2);
}

// Marlin/src/gcode/gcode.cpp, process_parsed_command, built without INCH_MODE_SUPPORT (the
// stock configuration): "case 21: NOOP; break; // No error on unknown G21", while G20 falls to
// unknown_command_warning().
TEST_CASE("g21_is_taken_without_a_word_and_g20_is_unknown_without_inch_mode") {
  Bench bench;
  CHECK(bench.send("G21\n") == "ok\n");
  CHECK(bench.printer.counters().unknown_commands == 0);
  CHECK(bench.send("G20\n") == "echo:Unknown command: \"G20\"\nok\n");
  CHECK(bench.printer.counters().unknown_commands == 1);
}

TEST_CASE("second_extruder_is_invalid") {
  Bench bench;
  CHECK(bench.send("T0\n") == "ok\n");
  CHECK(bench.send("T1\n") == "echo:T1 Invalid extruder\nok\n");
}

TEST_CASE("m114_reports_position_and_step_counts") {
  Bench bench;
  CHECK(bench.send("G92 X10 Y20 Z0.3 E1.5\nM114\n") ==
        "ok\nX:10.00 Y:20.00 Z:0.30 E:1.50 Count X:800 Y:1600 Z:120\nok\n");
}

TEST_CASE("m115_reports_firmware_and_capabilities") {
  Bench bench;
  const std::string reply = bench.send("M115\n");
  CHECK(reply.starts_with(
      "FIRMWARE_NAME:Marlin 2.1.2 (mahost simulated printer) "
      "SOURCE_CODE_URL:github.com/MarlinFirmware/Marlin PROTOCOL_VERSION:1.0 "
      "MACHINE_TYPE:mahost sim EXTRUDER_COUNT:1 UUID:cede2a2f-41a2-4748-9b12-c55c62f367ff\n"
      "Cap:SERIAL_XON_XOFF:0\n"));
  CHECK(reply.find("\nCap:AUTOREPORT_TEMP:1\n") != std::string::npos);
  CHECK(reply.find("\nCap:EMERGENCY_PARSER:1\n") != std::string::npos);
  CHECK(reply.ends_with("\nCap:MEATPACK:0\nok\n"));
}

TEST_CASE("advanced_ok_reports_line_planner_and_queue_space") {
  sim::Config config;
  config.advanced_ok = true;
  Bench bench(config);
  // One move planned of the 15 Marlin takes (planner.h moves_free(): BLOCK_BUFFER_SIZE 16
  // less one less those planned); the command itself still holds one of 4 slots.
  CHECK(bench.send("N1 G1 X10 F6000*48\n") == "ok N1 P14 B3\n");
  CHECK(bench.send("G92 E0\n") == "ok P14 B3\n");
  // M105 prints its own ok, with temperatures and without the buffer fields.
  CHECK(bench.send("M105\n") == "ok T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n");
}

TEST_CASE("m155_autoreports_temperatures") {
  Bench bench;
  CHECK(bench.send("M155 S1\n", 3.5) ==
        "ok\n"
        " T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n"
        " T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n"
        " T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n");
  CHECK(bench.send("M155 S0\n", 3) == "ok\n");
}

TEST_CASE("m109_waits_the_closed_form_heating_time") {
  // Full power: T(t) = 500 - 480 e^(-t/120) (ambient 20, 4 °C/s, 120 s). Within 1 °C of 210
  // at t1 = 120 ln(480/291), then 10 s of residency.
  Bench bench;
  const double start = bench.printer.now();
  bench.printer.receive("M109 S210\n");
  const double expected = 120 * std::log(480.0 / 291.0) + 10;
  std::string said;
  double ok_at = 0;
  while (bench.printer.run_until_output(start + 200)) {
    const std::string out = bench.printer.take_output();
    said += out;
    if (out.find("ok\n") != std::string::npos) {
      ok_at = bench.printer.now() - start;
      break;
    }
  }
  CHECK(ok_at == doctest::Approx(expected).epsilon(1e-9));
  CHECK(bench.printer.hotend_temperature() == doctest::Approx(210));
  // A report at once and every second, busy every 2 s (Marlin's BUSY_WHILE_HEATING).
  CHECK(said.starts_with(" T:20.00 /210.00 B:20.00 /0.00 @:127 B@:0 W:?\n"
                         " T:23.98 /210.00 B:20.00 /0.00 @:127 B@:0 W:?\n"
                         "echo:busy: processing\n"
                         " T:27.93 /210.00 B:20.00 /0.00 @:127 B@:0 W:?\n"));
  int busy = 0, reports = 0;
  for (std::size_t at = 0; (at = said.find("busy: processing", at)) != std::string::npos; ++at) {
    ++busy;
  }
  for (std::size_t at = 0; (at = said.find(" W:", at)) != std::string::npos; ++at) ++reports;
  CHECK(busy == static_cast<int>(std::floor(expected / 2)));
  CHECK(reports == static_cast<int>(std::floor(expected)) + 1);
  // Holding power at 210: 127 * 190 / 480.
  CHECK(bench.send("M105\n") == "ok T:210.00 /210.00 B:20.00 /0.00 @:50 B@:0\n");
}

TEST_CASE("m109_s_does_not_wait_for_cooling") {
  Bench bench;
  bench.send("M109 S200\n", 200);
  CHECK(bench.send("M109 S180\n") == " T:200.00 /180.00 B:20.00 /0.00 @:0 B@:0 W:?\nok\n");
}

TEST_CASE("m190_waits_for_the_bed") {
  // Bed: ceiling 20 + 0.6 * 300 = 200 °C; within 1 °C of 60 at 300 ln(180/141), then 10 s.
  Bench bench;
  const double start = bench.printer.now();
  bench.printer.receive("M190 S60\nM105\n");
  const double expected = 300 * std::log(180.0 / 141.0) + 10;
  bench.printer.run_until(start + expected - 0.01);
  CHECK(bench.printer.take_output().find("ok") == std::string::npos);
  bench.printer.run_until(start + expected + 0.01);
  CHECK(bench.printer.take_output().ends_with("ok\nok T:20.00 /0.00 B:60.00 /60.00 @:0 B@:28\n"));
}

TEST_CASE("m108_ends_a_heating_wait") {
  Bench bench;
  bench.send("M109 S210\n", 5);
  const std::string said = bench.send("M108\n", 0.1);
  CHECK(said == "ok\nok\n");  // M109's ok at once, then M108's own
  CHECK(bench.printer.hotend_target() == 210);
}

TEST_CASE("m0_pauses_for_user_until_m108") {
  Bench bench;
  CHECK(bench.send("M0\n", 4.5) == "echo:busy: paused for user\necho:busy: paused for user\n");
  CHECK(bench.send("M108\n") == "ok\nok\n");
}

TEST_CASE("m112_halts_and_nothing_but_a_reset_helps") {
  Bench bench;
  CHECK(bench.send("M104 S200\nM112\n") == "ok\nError:Printer halted. kill() called!\n");
  CHECK(bench.printer.state() == sim::PrinterState::halted);
  CHECK(bench.printer.hotend_target() == 0);
  CHECK(bench.send("M999\nM105\n", 5).empty());
  bench.printer.reset();
  CHECK(bench.send("M105\n") ==
        "start\necho:Marlin 2.1.2\n"
        "echo: Last Updated: 2021-12-25 | Author: (mahost simulated printer)\n"
        "ok T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n");
  CHECK(bench.printer.counters().resets == 2);
}

TEST_CASE("m112_jumps_a_full_queue_with_the_emergency_parser") {
  Bench bench;
  // Four dwells fill the queue; M112 behind them still acts the moment it arrives.
  CHECK(bench.send("G4 S10\nG4 S10\nG4 S10\nG4 S10\nN7 M112*38\n", 1) ==
        "Error:Printer halted. kill() called!\n");
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"G4 S10", "M112"});
}

TEST_CASE("m112_waits_in_the_queue_without_the_emergency_parser") {
  sim::Config config;
  config.emergency_parser = false;
  Bench bench(config);
  CHECK(bench.send("G4 S1\nN1 M112*32\n", 0.5).empty());
  CHECK(bench.send("", 1) == "ok\nError:Printer halted. kill() called!\n");
}

TEST_CASE("m999_asks_for_the_next_line") {
  Bench bench;
  CHECK(bench.send("N1 M105*38\n").starts_with("ok"));
  CHECK(bench.send("M999\n") == "Resend: 2\nok\n");
  CHECK(bench.send("M999 S1\n") == "ok\n");
}

TEST_CASE("g4_dwells_and_reports_busy") {
  Bench bench;
  CHECK(bench.send("G4 S5\n", 4.9) == "echo:busy: processing\necho:busy: processing\n");
  CHECK(bench.send("", 0.2) == "ok\n");
  CHECK(bench.send("M113 S0\nG4 P3000\n", 3.1) == "ok\nok\n");  // keepalive off
}

TEST_CASE("g28_homes_through_the_motion_model_and_reports_position") {
  // Each homing move runs rest to rest: L/v + v/a. X from 50 at 50 mm/s, 1500 mm/s^2 (travel),
  // 5 mm back off, 5 mm at 25 mm/s; Y likewise from 40; Z from 10 at 4 mm/s, 100 mm/s^2
  // (Z's limit), 2 mm back off, 2 mm at 1 mm/s.
  const double x = (50 / 50.0 + 50 / 1500.0) + (5 / 50.0 + 50 / 1500.0) + (5 / 25.0 + 25 / 1500.0);
  const double y = (40 / 50.0 + 50 / 1500.0) + (5 / 50.0 + 50 / 1500.0) + (5 / 25.0 + 25 / 1500.0);
  const double z = (10 / 4.0 + 4 / 100.0) + (2 / 4.0 + 4 / 100.0) + (2 / 1.0 + 1 / 100.0);
  Bench bench;
  CHECK(bench.send("G92 X50 Y40 Z10\n") == "ok\n");
  const double start = bench.printer.now();
  CHECK(bench.send("G28\n", x + y + z - 1e-6) ==
        "echo:busy: processing\necho:busy: processing\necho:busy: processing\n");
  CHECK(bench.send("", 2e-6) == "X:0.00 Y:0.00 Z:0.00 E:0.00 Count X:0 Y:0 Z:0\nok\n");
  (void)start;
}

TEST_CASE("host_that_ignores_ok_overflows_the_rx_buffer_and_bytes_are_lost") {
  // 40 dwells of 8 bytes at once: one runs and three wait (BUFSIZE 4), 128 bytes (16 lines)
  // wait in the RX buffer, the other 20 lines (160 bytes) are lost, as on Marlin.
  Bench bench;
  std::string flood;
  for (int i = 0; i < 40; ++i) flood += "G4 P100\n";
  bench.send(flood, 10);
  const sim::Counters& n = bench.printer.counters();
  CHECK(n.overflows == 1);
  CHECK(n.overflow_bytes == 160);
  CHECK(bench.printer.executed_commands().size() == 20);
}

TEST_CASE("line_error_discards_what_waits_in_the_rx_buffer") {
  // The queue is full (a dwell and three more), so the next lines wait in the RX buffer;
  // the bad line's error empties it, as gcode_line_error does, and asks for line 1 again.
  Bench bench;
  CHECK(bench.send("G4 S1\nG4 S1\nG4 S1\nG4 S1\nN1 M105*0\nM114\nM114\n", 5) ==
        "ok\nError:checksum mismatch, Last Line: 0\nResend: 1\nok\nok\nok\nok\n");
  CHECK(bench.printer.executed_commands().size() == 4);
}

TEST_CASE("baud_rate_paces_bytes_both_ways_at_ten_bits_a_byte") {
  sim::Config config;
  config.baud = 115200;
  Bench bench(config);
  const double sent = bench.printer.now();
  bench.printer.receive("M105\n");  // 5 bytes in, 40 bytes back
  REQUIRE(bench.printer.run_until_output(sent + 1));
  CHECK(bench.printer.now() - sent == doctest::Approx((5 + 40) * 10 / 115200.0));
  CHECK(bench.printer.take_output() == "ok T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n");
}

TEST_CASE("g90_resets_m83_as_marlin_does") {
  // Marlin's G90 clears the E mode set by M83: E is absolute again.
  Bench bench;
  bench.send("G92 E0\nM83\nG1 X1 E1 F600\nG1 X2 E1\nG90\nG1 X3 E2\nG1 X4 E2\n", 5);
  const auto& moves = bench.printer.deposition().moves;
  CHECK(moves.size() == 2);  // with E still relative, X3 and X4 would extrude 2 mm each
  CHECK(bench.printer.position().e == 2);
}

TEST_CASE("relative_moves_feedrate_and_speed_and_flow_factors") {
  Bench bench;
  bench.send("G92 X10 Y10 Z0.2 E0\nG91\nG1 X5 E1 F1200\nM220 S50\nM221 S90\nG1 Y5 E1\n", 5);
  const auto& moves = bench.printer.deposition().moves;
  REQUIRE(moves.size() == 2);
  CHECK(moves[0].start.x == 10);
  CHECK(moves[0].end.x == 15);
  CHECK(moves[0].feedrate == 20);
  CHECK(moves[0].e == 1);
  CHECK(moves[1].end.y == 15);
  CHECK(moves[1].feedrate == 10);         // M220 S50 halves 20 mm/s
  CHECK(moves[1].e == doctest::Approx(0.9));  // M221 S90
  CHECK(bench.printer.position().e == 2);  // the commanded E, as M114 reports it
}

TEST_CASE("sim_clock_agrees_with_the_print_time_estimate") {
  // The same program through the firmware and through the estimate (printer/print_time.h):
  // one motion model, so the motion time is the same to rounding.
  std::string program = "G92 X0 Y0 Z0.2 E0\nM83\n";
  for (int i = 0; i < 300; ++i) {
    program += "G1 X" + std::to_string(20 + (i * 7) % 60) + " Y" + std::to_string(20 + (i * 13) % 50) +
               " E0.4 F" + std::to_string(1200 + 300 * (i % 5)) + "\n";
    if (i % 50 == 49) program += "M400\nG4 P200\n";
  }
  // Fed line by line, as a host waiting for each ok would (all at once would overflow).
  sim::Printer fed;
  fed.run_until(1e-3);
  std::size_t start = 0;
  while (start < program.size()) {
    const std::size_t end = program.find('\n', start);
    fed.receive(std::string_view(program).substr(start, end + 1 - start));
    while (!fed.idle()) fed.run_until(fed.next_event_time());
    start = end + 1;
  }
  fed.finish();
  CHECK(fed.executed_commands().size() == 2 + 300 + 12);
  const double estimate = printer::estimate_print_time(program, printer::MotionLimits{});
  CHECK(fed.motion_time() == doctest::Approx(estimate - 6 * 0.2).epsilon(1e-9));
  // The clock: the host keeps the planner fed, so the moves run back to back from the first
  // one (at 1 ms) but for the five dwells between them (the sixth ends the program).
  CHECK(fed.motion_end_time() == doctest::Approx(1e-3 + fed.motion_time() + 5 * 0.2).epsilon(1e-12));
}

TEST_CASE("full_planner_delays_the_ok_until_the_oldest_move_ends") {
  // Back and forth 10 mm at 10 mm/s: every move reverses, so each runs rest to rest in
  // L/v + v/a = 1 + 10/1500 s (travel acceleration). Fifteen fill the planner at once; the
  // sixteenth waits for the first to end.
  sim::Config config;
  config.advanced_ok = true;
  Bench bench(config);
  std::string moves;
  for (int i = 0; i < 17; ++i) moves += i % 2 ? "G1 X0\n" : "G1 X10 F600\n";
  const double start = bench.printer.now();
  bench.printer.receive(moves);
  bench.printer.run_until(start + 0.5);
  const std::string first = bench.printer.take_output();
  // B counts free queue slots as Marlin does (BUFSIZE less the commands held, this one
  // included): the queue stays full while lines wait in the RX buffer.
  CHECK(first.starts_with("ok P14 B0\nok P13 B0\n"));
  CHECK(first.ends_with("ok P2 B0\nok P1 B0\nok P0 B1\n"));
  CHECK(std::count(first.begin(), first.end(), '\n') == 15);
  REQUIRE(bench.printer.run_until_output(start + 5));
  CHECK(bench.printer.now() - start == doctest::Approx(1 + 10 / 1500.0).epsilon(1e-12));
  CHECK(bench.printer.take_output() == "ok P0 B2\n");
}

TEST_CASE("m204_travel_acceleration_changes_the_clock") {
  // One 10 mm travel from rest to rest: 10/10 + 10/a.
  for (const double a : {1500.0, 100.0}) {
    Bench bench;
    bench.send("M204 T" + std::to_string(static_cast<int>(a)) + "\nG1 X10 F600\nM400\n", 5);
    CHECK(bench.printer.motion_time() == doctest::Approx(1 + 10 / a).epsilon(1e-12));
  }
}

TEST_CASE("wait_when_idle_if_configured") {
  sim::Config config;
  config.idle_wait_interval = 1;
  Bench bench(config);
  CHECK(bench.send("", 2.2) == "wait\nwait\n");
  CHECK(bench.send("G4 S3\n", 4.5) == "echo:busy: processing\nok\nwait\n");
}

TEST_CASE("g3_full_circle_is_cut_into_chords_on_the_circle_at_least_72") {
  // Radius 10: 20 pi = 62.83 mm of arc, 62 whole millimetres but at least
  // MIN_CIRCLE_SEGMENTS 72 chords (Marlin 2.1's G2_G3.cpp and Configuration_adv.h), each
  // ending on the circle but for the small-angle rotation's drift (under 0.001 mm here).
  Bench bench;
  bench.send("G92 X10 Y0 Z0.2 E0\nG3 X10 Y0 I-10 J0 E6.2 F1200\n", 30);
  const auto& moves = bench.printer.deposition().moves;
  REQUIRE(moves.size() == 72);
  double filament = 0;
  for (const auto& m : moves) {
    CHECK(std::abs(std::hypot(m.end.x, m.end.y) - 10) < 1e-3);
    filament += m.e;
  }
  CHECK(filament == doctest::Approx(6.2));
  CHECK(moves[0].end.y > 0);  // counter-clockwise from (10, 0)
  CHECK(moves.back().end.x == 10);
  CHECK(moves.back().end.y == 0);
}

TEST_CASE("g2_with_radius_finds_the_centre_marlin_does") {
  // Clockwise from (10, 0) to (6, -8) with R10: centre (0, 0), through y < 0; 53.13
  // degrees, 9.27 mm, so ceil(72 x 53.13 / 360) = 11 chords.
  Bench bench;
  bench.send("G92 X10 Y0 Z0.2 E0\nG2 X6 Y-8 R10 E1 F1200\n", 30);
  const auto& moves = bench.printer.deposition().moves;
  REQUIRE(moves.size() == 11);
  for (const auto& m : moves) {
    CHECK(std::abs(std::hypot(m.end.x, m.end.y) - 10) < 1e-3);
    CHECK(m.end.y <= 1e-12);
    CHECK(m.end.x >= -1e-12);
  }
  CHECK(bench.printer.position().x == 6);
  CHECK(bench.printer.position().y == -8);
}

TEST_CASE("an_arc_without_a_centre_is_refused_with_marlins_error_and_does_not_move") {
  // G2_G3.cpp: no R, I or J (or all 0): SERIAL_ERROR_MSG(STR_ERR_ARC_ARGS), no move. The sim
  // went straight to the end point.
  Bench bench;
  CHECK(bench.send("G2 X10 Y10 E1 F600\n", 5) == "Error:G2/G3 bad parameters\nok\n");
  CHECK(bench.printer.position().x == 0);
  CHECK(bench.printer.position().e == 0);
  CHECK(bench.printer.deposition().moves.empty());
}

TEST_CASE("the_simulated_printer_lays_the_beads_the_interpreter_reads") {
  // One interpreter: the sim's moves are the deposition record's read from the same text.
  const std::vector<std::string> lines = {"G92 X10 Y0 Z0.2 E0", "G1 X20 E1 F1200", "G2 X30 Y0 I5 E2",
                                          "G3 X30 Y0 I-3 E3",   "G2 X40 Y10 R-10 E4", "G91",
                                          "G1 X5 E0.5"};
  Bench bench;
  std::string program;
  for (const std::string& line : lines) {
    bench.send(line + "\n", 30);
    program += line + "\n";
  }
  const auto& sim_moves = bench.printer.deposition().moves;
  const sim::DepositionRecord read = sim::deposition_from_gcode(program);
  REQUIRE(sim_moves.size() == read.moves.size());
  CHECK(sim_moves.size() > 100);
  for (std::size_t i = 0; i < read.moves.size(); ++i) {
    CAPTURE(i);
    CHECK(sim_moves[i].start.x == read.moves[i].start.x);
    CHECK(sim_moves[i].end.x == read.moves[i].end.x);
    CHECK(sim_moves[i].end.y == read.moves[i].end.y);
    CHECK(sim_moves[i].e == read.moves[i].e);
  }
}

TEST_CASE("bytes_at_a_baud_rate_still_arrive_after_hours_of_sim_time") {
  // A byte's arrival is compared with the clock in the same arithmetic that set the clock to
  // it: dividing by the byte time instead rounds the last byte of a line away after a few
  // thousand seconds, and the sim waited for it for ever.
  sim::Config config;
  config.baud = 115200;
  sim::Printer printer(config);
  for (const double t : {1.0, 5000.123, 20000.777, 86400.5}) {
    CAPTURE(t);
    printer.run_until(t);
    printer.take_output();
    printer.receive("N1 M105*38\n");
    CHECK(printer.run_until_output(t + 1));
    CHECK(printer.take_output().starts_with("ok T:"));
    printer.receive("M110 N0\n");
    printer.run_until(t + 2);
  }
}

}  // namespace printer_test
