// The protocol engine against a scripted firmware, one reply case at a time, and against the
// simulated printer where a fault needs the firmware's own timing (DESIGN.md §4).
#include "printer/line_protocol.h"

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "printer/error.h"
#include "printer/gcode_line.h"
#include "printer/scripted_firmware.h"
#include "sim/faults.h"
#include "sim/sim_link.h"

namespace line_protocol_test {

using printer::LineProtocol;
using printer::ProtocolOptions;
using test_support::ScriptedFirmware;
using namespace std::chrono_literals;

namespace {

std::vector<std::string> moves(int count) {
  std::vector<std::string> commands;
  for (int i = 1; i <= count; ++i) {
    commands.push_back(fmt::format("G1 X{} Y{} E{:.1f}", i, 2 * i, 0.1 * i));
  }
  return commands;
}

// What the firmware executed of the job: without the host's own M110, M115 and M105 probes.
std::vector<std::string> job_part(const ScriptedFirmware& firmware) {
  std::vector<std::string> out;
  for (const std::string& c : firmware.executed) {
    const printer::GcodeCommand parsed = printer::parse_gcode_line(c);
    if (parsed.is('M', 110) || parsed.is('M', 115) || parsed.is('M', 105)) continue;
    out.push_back(c);
  }
  return out;
}

void stream(LineProtocol& protocol, const std::vector<std::string>& commands) {
  protocol.connect();
  for (const std::string& c : commands) protocol.send(c);
  protocol.wait_acknowledged();
}

}  // namespace

TEST_CASE("every_line_is_numbered_with_its_checksum") {
  ScriptedFirmware firmware(false);  // no banner: the first M110 is answered (banners: below)
  LineProtocol protocol(firmware);
  stream(protocol, {"G28", "G1 X10 Y5 E0.3"});
  REQUIRE(firmware.received.size() == 4);
  CHECK(firmware.received[0] == printer::frame_line(0, "M110 N0"));
  CHECK(firmware.received[1] == printer::frame_line(1, "M115"));
  CHECK(firmware.received[2] == "N2 G28*17");
  CHECK(firmware.received[3] == printer::frame_line(3, "G1 X10 Y5 E0.3"));
  CHECK(firmware.bad_frames == 0);
  CHECK(protocol.firmware().name == "ScriptedFirmware");
  CHECK(protocol.firmware().emergency_parser);
}

TEST_CASE("ping_pong_keeps_one_line_in_flight") {
  ScriptedFirmware firmware;
  LineProtocol protocol(firmware);
  stream(protocol, moves(200));
  CHECK(job_part(firmware) == moves(200));
  CHECK(firmware.max_ahead == 1);
}

TEST_CASE("resend_rewinds_exactly") {
  ScriptedFirmware firmware;
  firmware.corrupt = {5, 17, 18, 40};
  LineProtocol protocol(firmware);
  stream(protocol, moves(60));
  CHECK(job_part(firmware) == moves(60));
  CHECK(protocol.stats().resend_requests == 4);
  CHECK(protocol.stats().lines_resent == 4);
  CHECK(protocol.stats().probes == 0);
}

TEST_CASE("resend_without_ok_is_learned_and_loses_nothing") {
  ScriptedFirmware firmware;
  firmware.ok_after_resend = false;
  firmware.corrupt = {5, 9, 13, 30, 31};
  LineProtocol protocol(firmware);
  stream(protocol, moves(50));
  CHECK(job_part(firmware) == moves(50));
  CHECK(protocol.stats().lines_resent == 5);
  CHECK(protocol.stats().probes == 0);
}

TEST_CASE("a_rejected_m110_at_connect_does_not_teach_an_ok_after_resend_the_firmware_never_sends") {
  // Marlin 2.0.9 refuses a line with "Error:..., Last Line: n" then "Resend: n+1" and no ok
  // (Marlin/src/gcode/queue.cpp, gcode_line_error and flush_and_request_resend). On the wire
  // the two lines come one after the other: were the next M110 written between them, its ok
  // would follow the resend request and pass for an ok after it, and every later resend
  // would swallow the resent line's own ok (each a lost ok, probed for).
  for (const bool banner : {true, false}) {
    CAPTURE(banner);
    ScriptedFirmware firmware(banner);
    firmware.ok_after_resend = false;
    firmware.byte_time = std::chrono::microseconds(87);  // 115200 baud
    // With a banner the probe is answered with it and the M110 after the banner is refused;
    // without, the probe itself.
    firmware.corrupt_writes = {banner ? 1U : 0U};
    firmware.corrupt = {5, 9, 13};
    LineProtocol protocol(firmware);
    stream(protocol, moves(20));
    CHECK(job_part(firmware) == moves(20));
    CHECK(protocol.stats().lines_resent == 3);
    CHECK(protocol.stats().probes == 0);
  }
}

TEST_CASE("an_ok_that_comes_late_after_a_resend_request_teaches_nothing_and_costs_no_probe_per_resend") {
  // The move's ok at line 20 comes only after the resend request the host's probe for it
  // draws (sim/faults.h late-ok-at-line): on Marlin 2.0.9, which sends no ok after "Resend:",
  // it looks like one. Taken for one, every later request would swallow the resent line's
  // own ok, each then a lost ok probed for. The faults from line 100 on: a corrupted line now
  // and then, each answered by a request.
  for (const bool ok_after_resend : {false, true}) {
    CAPTURE(ok_after_resend);
    sim::Config config;
    config.ok_after_resend = ok_after_resend;
    config.faults = sim::parse_fault_spec("late-ok-at-line=20,corrupt=0.002,from-line=100,seed=5");
    sim::SimLink link(config);
    LineProtocol protocol(link);
    protocol.connect();
    const std::vector<std::string> commands = moves(3000);
    for (const std::string& c : commands) protocol.send(c);
    protocol.wait_acknowledged();
    link.printer().finish();
    std::vector<std::string> executed;
    for (const std::string& c : link.printer().executed_commands()) {
      if (c.starts_with("G1")) executed.push_back(c);
    }
    CHECK(executed == commands);
    const printer::ProtocolStats& stats = protocol.stats();
    MESSAGE("resend requests " << stats.resend_requests << ", probes " << stats.probes);
    CHECK(stats.resend_requests >= 20);
    // The one probe for the late ok; a request's own ok is never taken for another line's.
    CHECK(stats.probes == 1);
  }
}

TEST_CASE("lost_ok_is_recovered_by_an_m105_probe") {
  ScriptedFirmware firmware;
  firmware.drop_ok = {7, 30};
  LineProtocol protocol(firmware);
  const auto start = firmware.now();
  stream(protocol, moves(40));
  CHECK(job_part(firmware) == moves(40));
  CHECK(protocol.stats().probes == 2);
  CHECK(protocol.stats().lines_resent == 0);
  // Each lost ok costs one probe interval, not OctoPrint's 30 s.
  CHECK(firmware.now() - start < 2 * ProtocolOptions{}.probe_after + 5s);
}

TEST_CASE("lost_line_is_replayed_after_the_probe") {
  ScriptedFirmware firmware;
  firmware.lose = {12};
  LineProtocol protocol(firmware);
  stream(protocol, moves(30));
  CHECK(job_part(firmware) == moves(30));
  CHECK(protocol.stats().probes == 1);
}

TEST_CASE("duplicate_ok_loses_and_repeats_nothing") {
  ScriptedFirmware firmware;
  firmware.duplicate_ok = {3, 4, 10};
  LineProtocol protocol(firmware);
  stream(protocol, moves(30));
  CHECK(job_part(firmware) == moves(30));
  CHECK(protocol.stats().duplicate_oks == 3);
}

TEST_CASE("resend_of_an_accepted_line_repeats_nothing") {
  for (const bool reject : {true, false}) {
    CAPTURE(reject);
    ScriptedFirmware firmware;
    firmware.reject_duplicates = reject;
    firmware.resend_after_accept = {6, 20};
    LineProtocol protocol(firmware);
    stream(protocol, moves(30));
    CHECK(job_part(firmware) == moves(30));
  }
}

TEST_CASE("window_needs_advanced_ok") {
  ScriptedFirmware firmware;
  ProtocolOptions options;
  options.window = 4;
  LineProtocol protocol(firmware, options);
  stream(protocol, moves(50));
  CHECK(job_part(firmware) == moves(50));
  CHECK_FALSE(protocol.advanced_ok());
  CHECK(firmware.max_ahead == 1);
}

TEST_CASE("window_fills_with_advanced_ok_and_queue_space") {
  ScriptedFirmware firmware;
  firmware.advanced_ok = true;
  firmware.queue_free = 3;
  ProtocolOptions options;
  options.window = 8;
  LineProtocol protocol(firmware, options);
  stream(protocol, moves(100));
  CHECK(job_part(firmware) == moves(100));
  CHECK(protocol.advanced_ok());
  CHECK(firmware.max_ahead == 3);  // the window, capped by the queue space the firmware reports
}

TEST_CASE("stale_resends_from_the_window_are_ignored") {
  ScriptedFirmware firmware;
  firmware.advanced_ok = true;
  firmware.queue_free = 4;
  firmware.corrupt = {18, 50};
  ProtocolOptions options;
  options.window = 4;
  LineProtocol protocol(firmware, options);
  stream(protocol, moves(80));
  CHECK(job_part(firmware) == moves(80));
  CHECK(protocol.stats().resend_requests == 2);
  // Every line written behind a corrupted one draws one stale request and is resent once:
  // no second replay, no loop.
  CHECK(protocol.stats().stale_resends > 0);
  CHECK(protocol.stats().lines_resent ==
        protocol.stats().resend_requests + protocol.stats().stale_resends);
}

TEST_CASE("window_survives_every_fault_at_once") {
  for (const bool reject : {true, false}) {
    for (const bool ok_after : {true, false}) {
      CAPTURE(reject);
      CAPTURE(ok_after);
      ScriptedFirmware firmware;
      firmware.advanced_ok = true;
      firmware.reject_duplicates = reject;
      firmware.ok_after_resend = ok_after;
      firmware.corrupt = {11, 12, 40, 77, 78, 79};
      firmware.drop_ok = {20, 90, 140};
      firmware.duplicate_ok = {33, 34};
      firmware.lose = {60, 120};
      firmware.resend_after_accept = {100};
      ProtocolOptions options;
      options.window = 3;
      LineProtocol protocol(firmware, options);
      stream(protocol, moves(150));
      CHECK(job_part(firmware) == moves(150));
    }
  }
}

TEST_CASE("busy_keepalive_extends_the_wait") {
  ScriptedFirmware firmware;
  firmware.busy_interval = 2s;
  LineProtocol protocol(firmware);
  stream(protocol, {"M109 S210", "G1 X1"});
  CHECK(job_part(firmware) == std::vector<std::string>{"M109 S210", "G1 X1"});
  CHECK(protocol.stats().probes == 0);
  CHECK(protocol.stats().busy_reports >= 25);
}

TEST_CASE("m109_without_busy_keepalive_does_not_time_out") {
  ScriptedFirmware firmware;
  firmware.heat_time = 10min;
  LineProtocol protocol(firmware);
  stream(protocol, {"M109 S210", "G1 X1", "G1 X2", "M190 S60", "G1 X3"});
  CHECK(job_part(firmware) ==
        std::vector<std::string>{"M109 S210", "G1 X1", "G1 X2", "M190 S60", "G1 X3"});
  // At most two probes wait behind each heat-up (a lost ok of M109 then costs seconds, not
  // the long timeout); none is answered before the heater is ready.
  CHECK(protocol.stats().probes <= 4);
  CHECK(firmware.now() >= 20min);
}

TEST_CASE("silence_ends_with_a_link_error_naming_the_port") {
  ScriptedFirmware firmware;
  firmware.silent_after = 10;
  LineProtocol protocol(firmware);
  protocol.connect();
  std::string message;
  try {
    for (const std::string& c : moves(30)) protocol.send(c);
    protocol.wait_acknowledged();
  } catch (const printer::LinkError& e) {
    message = e.what();
  }
  CHECK(message.starts_with("fake printer: the printer stopped answering"));
  CHECK(protocol.stats().probes == ProtocolOptions{}.max_probes);
}

TEST_CASE("printer_halted_throws_with_the_firmware_reason") {
  ScriptedFirmware firmware;
  firmware.halt_at = 8;
  LineProtocol protocol(firmware);
  protocol.connect();
  std::string message;
  try {
    for (const std::string& c : moves(30)) protocol.send(c);
    protocol.wait_acknowledged();
  } catch (const printer::PrinterError& e) {
    message = e.what();
  }
  CHECK(message == "fake printer: the printer stopped: Error:Printer halted. kill() called!");
}

TEST_CASE("restart_mid_job_throws") {
  ScriptedFirmware firmware;
  firmware.restart_at = 9;
  LineProtocol protocol(firmware);
  protocol.connect();
  CHECK_THROWS_AS(
      {
        for (const std::string& c : moves(30)) protocol.send(c);
        protocol.wait_acknowledged();
      },
      printer::PrinterError);
  CHECK(protocol.restart_seen());
}

TEST_CASE("resend_loop_gives_up_with_a_link_error") {
  ScriptedFirmware firmware;
  firmware.reject_always = {4};
  LineProtocol protocol(firmware);
  protocol.connect();
  std::string message;
  try {
    for (const std::string& c : moves(10)) protocol.send(c);
    protocol.wait_acknowledged();
  } catch (const printer::LinkError& e) {
    message = e.what();
  }
  CHECK(message.find(fmt::format("asked for line 4 {} times in a row", ProtocolOptions{}.max_resends_of_one_line + 1)) !=
        std::string::npos);
}

TEST_CASE("emergency_stop_bypasses_a_full_window") {
  ScriptedFirmware firmware;
  firmware.heat_time = 5min;
  LineProtocol protocol(firmware);
  protocol.connect();
  bool stopped = false;
  protocol.on_wait = [&] {
    if (!stopped && firmware.now() > 10s) {
      stopped = true;
      protocol.emergency("M112");
    }
  };
  std::string message;
  try {
    protocol.send("M109 S210");
    protocol.send("G1 X1");
    protocol.wait_acknowledged();
  } catch (const printer::PrinterError& e) {
    message = e.what();
  }
  CHECK(stopped);
  CHECK(firmware.received.back() == "M112");
  CHECK(message.find("Printer halted") != std::string::npos);
  CHECK(firmware.now() < 1min);
}

TEST_CASE("temperatures_come_from_every_report") {
  ScriptedFirmware firmware;
  LineProtocol protocol(firmware);
  stream(protocol, {"M105"});
  REQUIRE(protocol.temperatures());
  CHECK(protocol.temperatures()->hotend == 210.0);
  CHECK(protocol.temperatures()->bed_target == 60.0);
}

TEST_CASE("query_position_reads_m114") {
  ScriptedFirmware firmware;
  LineProtocol protocol(firmware);
  protocol.connect();
  const auto position = protocol.query_position();
  REQUIRE(position);
  CHECK(position->x == 10.0);
  CHECK(position->z == 0.3);
  CHECK(position->e == 5.0);
}

TEST_CASE("a_printer_without_a_banner_is_connected_by_the_first_probe_not_after_the_boot_wait") {
  // A board that does not reset as its port opens (native USB) says nothing until asked.
  ScriptedFirmware firmware(false);
  LineProtocol protocol(firmware);
  const auto start = firmware.now();
  protocol.connect(std::chrono::milliseconds(3000));
  CHECK(firmware.now() - start < std::chrono::milliseconds(1000));  // the simulated clock
  REQUIRE(firmware.received.size() == 2);  // one M110, answered, then M115
  CHECK(firmware.received[0] == printer::frame_line(0, "M110 N0"));
  CHECK(firmware.received[1] == printer::frame_line(1, "M115"));
  protocol.send("G1 X1");
  protocol.send("G1 X2");
  protocol.wait_acknowledged();
  CHECK(firmware.executed == std::vector<std::string>{"M110 N0", "M115", "G1 X1", "G1 X2"});
  CHECK(protocol.stats().resend_requests == 0);
}

TEST_CASE("a_board_that_boots_as_its_port_opens_is_connected_after_its_banner") {
  // The probe answered along with the banner (Teacup's ends with an ok of its own) is not taken
  // for the end of the boot: the banner's silence is waited for, then M110 again.
  for (const bool teacup_ok : {false, true}) {
    CAPTURE(teacup_ok);
    ScriptedFirmware firmware(true, teacup_ok);
    LineProtocol protocol(firmware);
    protocol.connect(std::chrono::milliseconds(3000));
    REQUIRE(firmware.received.size() == 3);
    CHECK(firmware.received[0] == printer::frame_line(0, "M110 N0"));
    CHECK(firmware.received[1] == printer::frame_line(0, "M110 N0"));
    CHECK(firmware.received[2] == printer::frame_line(1, "M115"));
    protocol.send("G1 X1");
    protocol.wait_acknowledged();
    CHECK(firmware.executed.back() == "G1 X1");
    CHECK(protocol.stats().resend_requests == 0);
  }
}

TEST_CASE("unanswered_connect_names_the_port") {
  ScriptedFirmware firmware(false);
  firmware.mute = true;
  LineProtocol protocol(firmware);
  std::string message;
  try {
    protocol.connect();
  } catch (const printer::LinkError& e) {
    message = e.what();
  }
  CHECK(message.starts_with("fake printer: the printer does not answer (no 'ok' to M110 in 5 tries)"));
}

TEST_CASE("noise_at_connect_points_at_the_baud_rate") {
  ScriptedFirmware firmware(false);
  firmware.noise = true;
  LineProtocol protocol(firmware);
  std::string message;
  try {
    protocol.connect();
  } catch (const printer::LinkError& e) {
    message = e.what();
  }
  CHECK(message.find("unreadable reply lines: likely the wrong --baud") != std::string::npos);
}

// ---- progress guarantees -----------------------------------------------------------------

TEST_CASE("lost_ok_of_m109_costs_seconds_not_the_long_timeout") {
  for (const bool keepalive : {true, false}) {
    CAPTURE(keepalive);
    ScriptedFirmware firmware;
    if (keepalive) firmware.busy_interval = 2s;
    firmware.heat_time = 60s;
    firmware.drop_ok_of_blocking = {3};  // N3 is M109 (N1 is M115, N2 the G28 before it)
    LineProtocol protocol(firmware);
    const auto start = firmware.now();
    stream(protocol, {"G28", "M109 S210", "G1 X1", "G1 X2"});
    CHECK(job_part(firmware) == std::vector<std::string>{"G28", "M109 S210", "G1 X1", "G1 X2"});
    // Heating takes 60 s; the lost ok adds one probe interval and the probe's round trip.
    CHECK(firmware.now() - start < 60s + ProtocolOptions{}.probe_after + 1s);
    CHECK(protocol.stats().probes >= 1);
    // With keepalives, never more than a probe interval without news; without, the heat-up
    // itself is silent (the engine cannot tell it from a lost ok, and probes behind it).
    if (keepalive) {
      CHECK(protocol.stats().longest_silence <= ProtocolOptions{}.probe_after + ProtocolOptions{}.tick);
    }
  }
}

TEST_CASE("lost_ok_three_lines_after_g28_is_probed_within_the_probe_interval") {
  ScriptedFirmware firmware;
  firmware.busy_interval = 2s;  // Marlin's default keepalive
  firmware.home_time = 15s;
  firmware.drop_ok = {5};  // G28 is N2; N5 is the third line after it
  LineProtocol protocol(firmware);
  stream(protocol, moves(1));
  const auto start = firmware.now();
  std::vector<std::string> commands{"G28"};
  for (const std::string& m : moves(6)) commands.push_back(m);
  for (const std::string& c : commands) protocol.send(c);
  protocol.wait_acknowledged();
  CHECK(firmware.now() - start < 15s + ProtocolOptions{}.probe_after + 1s);
  CHECK(protocol.stats().probes == 1);
}

TEST_CASE("probe_answered_by_a_temperature_line_then_ok_frees_its_own_slot") {
  // A firmware that does not name itself and prints M105's temperatures on their own line,
  // then a bare ok: the probe's ok must not be taken for the lost one and leave the probe
  // waiting (which made the host probe for ever).
  ScriptedFirmware firmware;
  firmware.firmware_name = "";
  firmware.temperatures_before_ok = true;
  firmware.drop_ok = {6, 20, 33};
  LineProtocol protocol(firmware);
  const auto start = firmware.now();
  stream(protocol, moves(40));
  CHECK(protocol.firmware().firmware == printer::Firmware::unknown);
  CHECK(job_part(firmware) == moves(40));
  CHECK(protocol.stats().probes == 3);  // one per lost ok, answered
  CHECK(firmware.now() - start < 3 * (ProtocolOptions{}.probe_after + 1s));
}

TEST_CASE("a_firmware_that_talks_but_takes_no_lines_ends_the_job_in_bounded_time") {
  ScriptedFirmware firmware;
  firmware.silent_after = 10;
  firmware.chatter = 1s;  // temperature reports keep coming, no ok, no resend
  LineProtocol protocol(firmware);
  protocol.connect();
  std::string message;
  const auto start = firmware.now();
  try {
    for (const std::string& c : moves(30)) protocol.send(c);
    protocol.wait_acknowledged();
  } catch (const printer::LinkError& e) {
    message = e.what();
  }
  CHECK(message.starts_with("fake printer: the printer stopped answering"));
  CHECK(protocol.stats().probes == ProtocolOptions{}.max_probes);
  CHECK(firmware.now() - start < (ProtocolOptions{}.max_probes + 2) * ProtocolOptions{}.probe_after);
}

TEST_CASE("wait_with_lines_in_flight_probes_at_once") {
  ScriptedFirmware firmware;
  firmware.wait_when_idle = true;  // Repetier's and NO_TIMEOUTS' "wait"
  firmware.drop_ok = {9};
  LineProtocol protocol(firmware);
  const auto start = firmware.now();
  stream(protocol, moves(20));
  CHECK(job_part(firmware) == moves(20));
  CHECK(protocol.stats().probes == 1);
  CHECK(firmware.now() - start < 2s);  // the "wait" 1 s after, not the 3 s probe interval
}

TEST_CASE("teacups_probe_runs_nothing_and_tells_a_lost_line_from_a_lost_ok") {
  // Teacup ignores line numbers (or, with REQUIRE_LINENUMBER, takes any from the next one up):
  // the unanswered line sent again would run twice, and an M105 probe would be taken in place
  // of a lost line. A line with a checksum wrong on purpose is refused with "rs N<n>": line 12
  // never came and is sent again; line 25 ran, its ok lost, and is not.
  for (const bool require_linenumber : {false, true}) {
    CAPTURE(require_linenumber);
    ScriptedFirmware firmware;
    firmware.firmware_name = "Teacup";
    firmware.ignores_line_numbers = !require_linenumber;
    firmware.accepts_skipped_numbers = require_linenumber;
    firmware.resend_as_rs = true;
    firmware.ok_after_resend = true;
    firmware.lose = {12};
    firmware.drop_ok = {25};
    LineProtocol protocol(firmware);
    stream(protocol, moves(40));
    CHECK(protocol.dialect().firmware == printer::Firmware::teacup);
    CHECK(job_part(firmware) == moves(40));
    CHECK(protocol.stats().probes == 2);
    CHECK(protocol.stats().lines_resent == 1);
    CHECK(firmware.bad_frames == 2);  // the probes, refused
  }
}

TEST_CASE("a_refused_heating_command_throws_command_refused_saying_what_to_set") {
  ScriptedFirmware firmware;
  firmware.firmware_name = "";
  firmware.refuse = {"M190"};
  LineProtocol protocol(firmware);
  protocol.connect();
  std::string message;
  try {
    protocol.send("M140 S60");
    protocol.send("M190 S60");
    protocol.send("G28");
    protocol.wait_acknowledged();
  } catch (const printer::CommandRefused& e) {
    message = e.what();
  }
  CHECK(message ==
        "fake printer: the printer refused M190 S60 (\"echo:Unknown command: \"M190 S60\"\"), so "
        "the print stopped: this firmware has no M190; if it waits "
        "for temperatures with M116 (as Teacup does), set firmware = \"teacup\" in the printer "
        "profile (or --set firmware=teacup) and slice again");
  CHECK(job_part(firmware) == std::vector<std::string>{"M140 S60", "M190 S60"});  // no G28
}

TEST_CASE("a_refused_command_the_print_can_do_without_is_counted_and_named") {
  ScriptedFirmware firmware;
  firmware.refuse = {"M73"};
  LineProtocol protocol(firmware);
  stream(protocol, {"M73 P10 R5", "G1 X1", "M73 P20 R4"});
  CHECK(protocol.stats().refused_commands == 2);
  CHECK(protocol.refused() == std::vector<std::string>{"M73 P10 R5", "M73 P20 R4"});
}

TEST_CASE("abandoned_lines_are_given_up_and_numbering_goes_on_after_an_m110") {
  ScriptedFirmware firmware;
  firmware.drop_ok = {6};
  firmware.lose = {7};  // the probe (a numbered M105, N7) is lost too
  LineProtocol protocol(firmware);
  protocol.connect();
  for (const std::string& c : moves(4)) protocol.send(c);  // N2..N5; N5's ok is lost (N6 is the next)
  protocol.send("G1 X99");                                // N6: ok lost
  CHECK_FALSE(protocol.wait_acknowledged_for(500ms));
  protocol.abandon_unacknowledged();
  protocol.send("M104 S0");
  protocol.wait_acknowledged();
  CHECK(firmware.received.back() == printer::frame_line(9, "M104 S0"));
  CHECK(firmware.received[firmware.received.size() - 2] == printer::frame_line(8, "M110 N8"));
  CHECK(firmware.executed.back() == "M104 S0");
}

TEST_CASE("temperature_requests_use_m155_where_the_firmware_reports_by_itself") {
  ScriptedFirmware firmware;
  LineProtocol protocol(firmware);
  protocol.connect();
  CHECK_FALSE(protocol.request_temperatures());  // no Cap:AUTOREPORT_TEMP: an M105
  protocol.send("G1 X1");
  protocol.wait_acknowledged();
  CHECK(firmware.executed == std::vector<std::string>{"M110 N0", "M110 N0", "M115", "M105", "G1 X1"});
  CHECK(protocol.temperatures_at());
}

TEST_CASE("with_marlins_keepalive_a_lost_ok_is_probed_after_the_interval_and_a_half_second") {
  ScriptedFirmware firmware;
  firmware.firmware_name = "Marlin 2.1.2";
  firmware.busy_interval = 1s;  // as M113 S1 asks
  firmware.home_time = 5s;      // homing shows the keepalive
  firmware.drop_ok = {7};
  LineProtocol protocol(firmware);
  protocol.connect();
  protocol.use_keepalive(1s);
  protocol.send("G28");
  const auto before = firmware.now();
  for (const std::string& c : moves(6)) protocol.send(c);
  protocol.wait_acknowledged();
  const auto m115 = std::find(firmware.executed.begin(), firmware.executed.end(), "M115");
  REQUIRE(m115 + 1 < firmware.executed.end());
  CHECK(*(m115 + 1) == "M113 S1");
  CHECK(protocol.stats().probes == 1);
  CHECK(firmware.now() - before < 5s + 1500ms + ProtocolOptions{}.tick + 100ms);
}

TEST_CASE("marlins_lost_ok_is_probed_with_a_skipped_line_number_that_runs_nothing") {
  // "N<next + 1> M105" is refused with "Resend: <next>": it says exactly which lines Marlin
  // has, whatever oks were lost, and is never executed nor counted as the firmware's error.
  ScriptedFirmware firmware;
  firmware.firmware_name = "Marlin 2.1.2";
  LineProtocol protocol(firmware);
  protocol.connect();
  const long first = protocol.last_sent() + 1;
  const std::size_t before = firmware.executed.size();
  firmware.drop_ok = {first + 5, first + 6, first + 20};  // two oks in a row, then one more
  for (const std::string& c : moves(30)) protocol.send(c);
  protocol.wait_acknowledged();
  CHECK(job_part(firmware) == moves(30));
  CHECK(protocol.stats().probes >= 2);
  CHECK(protocol.stats().lines_resent == 0);
  CHECK(protocol.stats().recoverable_errors == 0);
  CHECK(std::vector<std::string>(firmware.executed.begin() + static_cast<long>(before), firmware.executed.end()) ==
        moves(30));
}

TEST_CASE("unknown_firmwares_m105_probe_whose_own_ok_is_lost_is_followed_by_a_skipped_number") {
  // A numbered M105 probe whose answer is lost too: the host used to credit the older line
  // with the next answer, stay one behind and probe for ever. The second probe skips a
  // number, and its "Resend:" settles both.
  ScriptedFirmware firmware;
  firmware.firmware_name = "";
  LineProtocol protocol(firmware);
  protocol.connect();
  const long first = protocol.last_sent() + 1;
  firmware.drop_ok = {first + 5, first + 6};  // a move's ok, then the M105 probe's
  const auto start = firmware.now();
  for (const std::string& c : moves(20)) protocol.send(c);
  protocol.wait_acknowledged();
  CHECK(job_part(firmware) == moves(20));
  CHECK(protocol.stats().probes == 2);
  CHECK(firmware.now() - start < 2 * (ProtocolOptions{}.probe_after + 1s) + 2s);
}

}  // namespace line_protocol_test
