// Fault specs (sim/faults.h): what parses, what is refused and how, and what each fault does
// to the literal byte stream, reproducibly from its seed.
#include <doctest/doctest.h>
#include <fmt/core.h>

#include <cmath>
#include <string>
#include <vector>

#include "printer/error.h"
#include "printer/gcode_line.h"
#include "sim/fault_injector.h"
#include "sim/faults.h"
#include "sim/printer.h"

namespace faults_test {

namespace {

std::string message_of(std::string_view spec) {
  try {
    sim::parse_fault_spec(spec);
  } catch (const printer::ConfigError& e) {
    return e.what();
  }
  return "";
}

sim::Printer quiet_printer(std::string_view faults) {
  sim::Config config;
  config.faults = sim::parse_fault_spec(faults);
  sim::Printer printer(config);
  printer.run_until(0.5);  // past the banner, delayed or not
  printer.take_output();
  return printer;
}

std::string send(sim::Printer& printer, std::string_view bytes, double seconds = 0.5) {
  printer.receive(bytes);
  printer.run_until(printer.now() + seconds);
  return printer.take_output();
}

// A minimal ping-pong host written for these tests: one numbered line in flight, rewinds on
// "Resend: n", skips the ok that follows a Resend. Returns false if the printer went silent.
bool stream(sim::Printer& printer, const std::vector<std::string>& commands) {
  std::size_t next = 0;  // index of the command to send; its line number is next + 1
  bool skip_ok = false;
  std::string pending;
  while (next < commands.size()) {
    printer.receive(printer::frame_line(static_cast<long>(next + 1), commands[next]) + "\n");
    for (bool answered = false; !answered;) {
      if (!printer.run_until_output(printer.now() + 60)) return false;
      pending += printer.take_output();
      for (std::size_t end; (end = pending.find('\n')) != std::string::npos;) {
        const std::string line = pending.substr(0, end);
        pending.erase(0, end + 1);
        if (line.starts_with("Resend: ")) {
          next = std::stoul(line.substr(8)) - 1;
          skip_ok = true;
          answered = true;
        } else if (line.starts_with("ok")) {
          if (skip_ok) {
            skip_ok = false;
          } else {
            ++next;
            answered = true;
          }
        }
      }
    }
  }
  return true;
}

}  // namespace

TEST_CASE("fault_spec_parses_every_key") {
  const sim::FaultSpec f = sim::parse_fault_spec(
      "corrupt=0.01, drop-ok=0.02,dup-ok=0.005,resend=0.03,delay=50ms,disconnect-at-line=5000,"
      "disconnect-at-time=2min,late-ok-at-line=20,halt-at-line=300,freeze-at-line=7,runaway-at-line=200,"
      "from-line=0,seed=42");
  CHECK(f.corrupt == 0.01);
  CHECK(f.drop_ok == 0.02);
  CHECK(f.dup_ok == 0.005);
  CHECK(f.resend == 0.03);
  CHECK(f.delay == doctest::Approx(0.05));
  CHECK(f.disconnect_at_line == 5000u);
  CHECK(f.disconnect_at_time == doctest::Approx(120));
  CHECK(f.late_ok_at_line == 20u);
  CHECK(f.halt_at_line == 300u);
  CHECK(f.freeze_at_line == 7u);
  CHECK(f.runaway_at_line == 200u);
  CHECK(f.from_line == 0);
  CHECK(f.seed == 42u);
  CHECK(sim::to_string(f) ==
        "corrupt=0.01,drop-ok=0.02,dup-ok=0.005,resend=0.03,delay=50ms,disconnect-at-line=5000,"
        "disconnect-at-time=120s,late-ok-at-line=20,halt-at-line=300,freeze-at-line=7,runaway-at-line=200,"
        "from-line=0,seed=42");
  CHECK_FALSE(sim::parse_fault_spec("").any());
  CHECK(sim::to_string(sim::parse_fault_spec("")).empty());
}

TEST_CASE("bad_fault_spec_names_the_key_and_what_is_allowed") {
  CHECK(message_of("corrupt=2") == "fault spec 'corrupt=2': give a probability from 0 to 1, e.g. 0.01");
  CHECK(message_of("drop-ok=x") == "fault spec 'drop-ok=x': give a probability from 0 to 1, e.g. 0.01");
  CHECK(message_of("delay=50") ==
        "fault spec 'delay=50': give a time of 0 or more with its unit, e.g. 50ms, 60s or 2min");
  CHECK(message_of("halt-at-line=0") == "fault spec 'halt-at-line=0': give a whole number of 1 or more");
  CHECK(message_of("seed=-1") == "fault spec 'seed=-1': give a whole number of 0 or more");
  CHECK(message_of("corrupt") ==
        "fault spec 'corrupt': write key=value, e.g. corrupt=0.01 (keys: corrupt, drop-ok, "
        "drop-blocking-ok, dup-ok, resend, delay, disconnect-at-line, disconnect-at-time, "
        "late-ok-at-line, halt-at-line, freeze-at-line, runaway-at-line, from-line, seed)");
  CHECK(message_of("explode=1").starts_with("fault spec: unknown fault 'explode' (known: corrupt,"));
}

TEST_CASE("drop_ok_sends_no_ok") {
  sim::Printer printer = quiet_printer("drop-ok=1");
  CHECK(send(printer, "G92 X1\n").empty());
  CHECK(printer.executed_commands() == std::vector<std::string>{"G92 X1"});
  CHECK(printer.counters().faults_injected == 1);
}

TEST_CASE("dup_ok_sends_ok_twice") {
  sim::Printer printer = quiet_printer("dup-ok=1");
  CHECK(send(printer, "G92 X1\n") == "ok\nok\n");
  CHECK(send(printer, "M105\n") == "ok T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n"
                                   "ok T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n");
}

TEST_CASE("resend_fault_refuses_an_intact_line") {
  sim::Printer printer = quiet_printer("resend=1");
  CHECK(send(printer, "N1 M105*38\n") == "Error:checksum mismatch, Last Line: 0\nResend: 1\nok\n");
  CHECK(printer.executed_commands().empty());
  CHECK(send(printer, "M105\n").starts_with("ok T:"));  // unnumbered lines are not checked
}

TEST_CASE("late_ok_at_line_sends_the_ok_right_after_the_next_resend_request") {
  for (const bool ok_after_resend : {true, false}) {
    CAPTURE(ok_after_resend);
    sim::Config config;
    config.ok_after_resend = ok_after_resend;
    config.faults = sim::parse_fault_spec("late-ok-at-line=1");
    sim::Printer printer(config);
    printer.run_until(0.5);
    printer.take_output();
    CHECK(send(printer, "G92 X1\n").empty());  // line 1: its ok held
    CHECK(send(printer, "G92 X2\n") == "ok\n");
    CHECK(send(printer, printer::frame_line(5, "M105") + "\n") ==
          fmt::format("Error:Line Number is not Last Line Number+1, Last Line: 0\nResend: 1\n{}ok\n",
                      ok_after_resend ? "ok\n" : ""));
    CHECK(printer.executed_commands() == std::vector<std::string>{"G92 X1", "G92 X2"});
  }
}

TEST_CASE("delay_fault_delays_every_reply") {
  sim::Printer printer = quiet_printer("delay=50ms");
  const double sent = printer.now();
  printer.receive("M105\n");
  REQUIRE(printer.run_until_output(sent + 1));
  CHECK(printer.now() - sent == doctest::Approx(0.05));
  CHECK(printer.take_output() == "ok T:20.00 /0.00 B:20.00 /0.00 @:0 B@:0\n");
}

TEST_CASE("from_line_keeps_the_handshake_clean") {
  sim::Printer printer = quiet_printer("drop-ok=1,from-line=1");
  CHECK(send(printer, "N-1 M110*15\n") == "ok\n");  // before line 1: no fault
  CHECK(send(printer, "N0 M105*39\n").starts_with("ok T:"));
  CHECK(send(printer, "N1 M105*38\n").empty());      // line 1 accepted: faults on
  CHECK(send(printer, "M105\n").empty());
}

TEST_CASE("halt_at_line_kills_before_executing_it") {
  sim::Printer printer = quiet_printer("halt-at-line=2");
  CHECK(send(printer, "G92 X1\nG92 X2\nG92 X3\n") == "ok\nError:Printer halted. kill() called!\n");
  CHECK(printer.executed_commands() == std::vector<std::string>{"G92 X1"});
  CHECK(printer.state() == sim::PrinterState::halted);
  CHECK(printer.stop_reason() == "halted at line 2 (fault halt-at-line)");
}

TEST_CASE("disconnect_at_line_cuts_the_link_and_the_board_runs_on") {
  sim::Printer printer = quiet_printer("disconnect-at-line=2");
  CHECK(send(printer, "G92 X1\nG92 X2\nG92 X3\n").empty());
  CHECK(printer.state() == sim::PrinterState::disconnected);
  CHECK(printer.stop_reason() == "disconnected at line 2 (fault disconnect-at-line)");
  // What reached the queue runs; what came after is lost with the link.
  CHECK(printer.executed_commands() == std::vector<std::string>{"G92 X1", "G92 X2"});
  CHECK(send(printer, "G92 X4\n").empty());
  printer.reconnect();
  CHECK(send(printer, "M114\n").ends_with("X:0.00 Y:0.00 Z:0.00 E:0.00 Count X:0 Y:0 Z:0\nok\n"));
}

TEST_CASE("freeze_at_line_stalls_the_link_with_the_port_open_until_a_reset") {
  sim::Printer printer = quiet_printer("freeze-at-line=2");
  // Line 2 is accepted and then nothing more is read or said: no ok, M112 ignored.
  CHECK(send(printer, "G92 X1\nG92 X2\nG92 X3\n", 5).empty());
  CHECK(send(printer, "M112\n", 5).empty());
  CHECK(printer.state() == sim::PrinterState::running);
  CHECK(printer.executed_commands() == std::vector<std::string>{"G92 X1", "G92 X2"});
  printer.reset();
  printer.run_until(printer.now() + 2);
  printer.take_output();
  CHECK(send(printer, "M114\n").ends_with("X:0.00 Y:0.00 Z:0.00 E:0.00 Count X:0 Y:0 Z:0\nok\n"));
}

TEST_CASE("disconnect_at_time_cuts_the_link_on_the_sim_clock") {
  sim::Printer printer = quiet_printer("disconnect-at-time=10s");
  printer.receive("G4 S20\n");
  printer.run_until(9.9);
  CHECK(printer.take_output().find("busy") != std::string::npos);
  CHECK(printer.state() == sim::PrinterState::running);
  printer.run_until(10.0);
  CHECK(printer.state() == sim::PrinterState::disconnected);
}

TEST_CASE("runaway_at_line_fails_the_heater_and_protection_stops_the_printer") {
  // Heater fails at line 3 while holding 200 °C: the temperature falls as
  // 20 + 180 e^(-t/120) and is 4 °C below target after 120 ln(180/176); 40 s later Marlin's
  // thermal protection fires.
  sim::Printer printer = quiet_printer("runaway-at-line=3");
  send(printer, "M109 S200\nM105\n", 100);
  const double failed_at = printer.now();
  CHECK(send(printer, "M105\n") == "ok T:200.00 /200.00 B:20.00 /0.00 @:0 B@:0\n");
  const double fires = failed_at + 120 * std::log(180.0 / 176.0) + 40;
  printer.run_until(fires - 1e-6);
  CHECK(printer.take_output().empty());
  printer.run_until(fires + 1e-6);
  CHECK(printer.take_output() ==
        "Error:Thermal Runaway, system stopped! Heater_ID: 0\n"
        "Error:Printer halted. kill() called!\n");
  CHECK(printer.state() == sim::PrinterState::halted);
  CHECK(printer.hotend_target() == 0);
}

TEST_CASE("corruption_is_always_detected_and_a_resending_host_loses_nothing") {
  std::vector<std::string> commands;
  for (int i = 0; i < 2000; ++i) {
    commands.push_back("G1 X" + std::to_string(i % 100) + ".25 Y" + std::to_string(i % 37) +
                       " E" + std::to_string(i) + ".5 F1800");
  }
  sim::Printer printer = quiet_printer("corrupt=0.02,seed=3");
  REQUIRE(stream(printer, commands));
  CHECK(printer.executed_commands() == commands);
  const sim::Counters& n = printer.counters();
  CHECK(n.faults_injected > 100);          // about 2% of ~60 000 bytes, one per line at most
  CHECK(n.errors <= n.faults_injected);    // a flip inside a "*0" checksum can go unseen
  CHECK(n.errors >= n.faults_injected - n.faults_injected / 20);
}

TEST_CASE("corrupt_changes_one_byte_a_line_and_a_digit_into_another_digit") {
  sim::FaultInjector faults(sim::parse_fault_spec("corrupt=0.05,seed=9"));
  const std::string line = "N123 G1 X45.678 Y90.123 E4.56789*77\n";
  int digits = 0, others = 0;
  for (int i = 0; i < 2000; ++i) {
    std::string sent = line;
    if (faults.corrupt(sent) == 0) continue;
    std::vector<std::size_t> changed;
    for (std::size_t k = 0; k < line.size(); ++k) {
      if (sent[k] != line[k]) changed.push_back(k);
    }
    REQUIRE(changed.size() == 1);
    const std::size_t at = changed.front();
    if (line[at] >= '0' && line[at] <= '9') {
      CHECK((sent[at] >= '0' && sent[at] <= '9'));  // a number changed, still a number
      ++digits;
    } else {
      ++others;
    }
  }
  CHECK(digits > others);  // most bytes of a G-code line are digits
  CHECK(others > 0);
}

TEST_CASE("faults_repeat_exactly_with_the_same_seed") {
  const auto run = [](std::string_view spec) {
    sim::Printer printer = quiet_printer(spec);
    std::string said;
    for (int i = 0; i < 200; ++i) said += send(printer, "G92 X" + std::to_string(i) + "\n", 0.01);
    return said;
  };
  const std::string a = run("drop-ok=0.3,dup-ok=0.3,seed=5");
  CHECK(a == run("drop-ok=0.3,dup-ok=0.3,seed=5"));
  CHECK(a != run("drop-ok=0.3,dup-ok=0.3,seed=6"));
}

}  // namespace faults_test
