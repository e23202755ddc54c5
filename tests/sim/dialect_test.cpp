// The simulated printer in Teacup's and Repetier's dialects, against their literal replies
// (Teacup's gcode_parse.c, gcode_process.c and mendel.c; Repetier's gcode.cpp and
// Communication.cpp). Checksums worked out by hand (XOR of the bytes before '*').
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "sim/printer.h"

namespace dialect_test {

namespace {

struct Bench {
  sim::Printer printer;
  std::string banner;
  explicit Bench(sim::Dialect dialect, std::string faults = "") : printer(config(dialect, faults)) {
    printer.run_until(0.5);
    banner = printer.take_output();
  }
  static sim::Config config(sim::Dialect dialect, const std::string& faults) {
    sim::Config c;
    c.dialect = dialect;
    c.faults = sim::parse_fault_spec(faults);
    return c;
  }
  std::string send(std::string_view bytes, double seconds = 0.5) {
    printer.receive(bytes);
    printer.run_until(printer.now() + seconds);
    return printer.take_output();
  }
};

}  // namespace

TEST_CASE("dialect_names_parse") {
  CHECK(sim::parse_dialect("teacup") == sim::Dialect::teacup);
  CHECK(sim::parse_dialect("repetier") == sim::Dialect::repetier);
  CHECK(sim::parse_dialect("marlin") == sim::Dialect::marlin);
  CHECK_FALSE(sim::parse_dialect("klipper"));
}

TEST_CASE("teacup_puts_the_output_on_its_ok_line") {
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.banner == "Start\nok\n");
  CHECK(bench.send("N1 M105*38\n") == "ok T:20.0 B:20.0\n");
  CHECK(bench.send("N2 M114*37\n") == "ok X:0.000,Y:0.000,Z:0.000,E:0.000,F:1500\n");
  CHECK(bench.send("N3 M115*37\n").starts_with("ok FIRMWARE_NAME:Teacup FIRMWARE_URL:"));
}

TEST_CASE("teacup_refuses_m190_on_the_ok_line_and_waits_with_m116") {
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.send("N1 M140 S60*82\n") == "ok\n");
  CHECK(bench.send("N2 M190 S60*92\n") == "ok E: Bad M-code 190\n");
  CHECK(bench.send("N3 M116*38\n", 1) == "ok\n");  // ok first, then the wait
  // The bed (sim/config.h: 300 s, 0.6 °C/s) from 20 to 60 °C, within the 1 °C window for 10 s.
  const double tmax = 20 + 0.6 * 300;
  const double reach = 300 * std::log((tmax - 20) / (tmax - 60));
  CHECK(bench.send("N4 G1 X2*102\n", reach + 10 + 1) == "ok\n");
  CHECK(bench.printer.bed_temperature() == doctest::Approx(60).epsilon(1e-6));
}

TEST_CASE("teacup_takes_skipped_line_numbers_and_asks_with_rs_without_ok") {
  Bench bench(sim::Dialect::teacup);
  CHECK(bench.send("N5 G1 X1*100\n") == "ok\n");        // N1..N4 never came: taken all the same
  CHECK(bench.send("N5 G1 X1*100\n") == "rs N6 Expected line number 6\n");
  CHECK(bench.send("N6 G1 X1*101\n") == "rs N6 Expected checksum 103\n");  // the checksum of what came
  CHECK(bench.printer.executed_commands() == std::vector<std::string>{"G1 X1"});
}

TEST_CASE("repetier_answers_ok_when_queued_and_the_output_after") {
  Bench bench(sim::Dialect::repetier);
  CHECK(bench.banner == "start\nExternal Reset\nFree RAM:3420\n");
  CHECK(bench.send("N1 M105*38\n", 0.2) == "ok\n T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n");
  CHECK(bench.send("N2 M73 P1*84\n", 0.2) == "ok\nUnknown command:M73 P1\n");
}

TEST_CASE("repetier_resend_has_its_ok_and_skips_what_was_in_flight") {
  Bench bench(sim::Dialect::repetier);
  CHECK(bench.send("N1 M105*39\n", 0.2) == "Resend:1\nok\n");
  CHECK(bench.send("N3 G1 X3*96\n", 0.2) == "skip 3\nok\n");  // sent before the request came
  CHECK(bench.send("N1 M105*38\n", 0.2).starts_with("ok\n"));
}

TEST_CASE("repetier_says_wait_when_idle") {
  Bench bench(sim::Dialect::repetier);
  CHECK(bench.send("", 1.2) == "wait\n");
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
