// Firmware reply lines, as Marlin 2.x prints them, classified (DESIGN.md §4).
#include "printer/replies.h"

#include <doctest/doctest.h>

namespace replies_test {

using printer::classify_reply;
using printer::ReplyKind;

TEST_CASE("ok_plain_and_advanced") {
  CHECK(classify_reply("ok").kind == ReplyKind::ok);
  CHECK(classify_reply("ok\r").kind == ReplyKind::ok);
  const auto advanced = classify_reply("ok N12 P15 B3");
  CHECK(advanced.kind == ReplyKind::ok);
  CHECK(advanced.line_number == 12);
  CHECK(advanced.planner_free == 15);
  CHECK(advanced.queue_free == 3);
  CHECK_FALSE(classify_reply("ok").line_number);
  CHECK(classify_reply("okay then").kind == ReplyKind::other);
}

TEST_CASE("ok_with_temperatures_is_not_advanced_ok") {
  const auto r = classify_reply("ok T:200.24 /200.00 B:65.01 /65.00 @:73 B@:22");
  CHECK(r.kind == ReplyKind::ok);
  CHECK_FALSE(r.queue_free);  // B:65.01 is the bed, not ADVANCED_OK's B
  REQUIRE(r.temperatures);
  CHECK(r.temperatures->hotend == doctest::Approx(200.24));
  CHECK(r.temperatures->hotend_target == doctest::Approx(200.0));
  CHECK(r.temperatures->bed == doctest::Approx(65.01));
  CHECK(r.temperatures->bed_target == doctest::Approx(65.0));
}

TEST_CASE("resend_forms") {
  CHECK(classify_reply("Resend: 12").line_number == 12);
  CHECK(classify_reply("Resend:12").line_number == 12);
  CHECK(classify_reply("Resend:N12").line_number == 12);
  CHECK(classify_reply("rs N2 Expected checksum 67").line_number == 2);
  CHECK(classify_reply("rs 7").kind == ReplyKind::resend);
  CHECK(classify_reply("Resend: garbage").kind == ReplyKind::other);
}

TEST_CASE("errors_recoverable_and_fatal") {
  CHECK(classify_reply("Error:checksum mismatch, Last Line: 4").kind == ReplyKind::error);
  CHECK(classify_reply("Error:Line Number is not Last Line Number+1, Last Line: 4").kind == ReplyKind::error);
  CHECK(classify_reply("Error:No Checksum with line number, Last Line: 4").kind == ReplyKind::error);
  CHECK(classify_reply("Error:Printer halted. kill() called!").kind == ReplyKind::fatal);
  CHECK(classify_reply("Error:Thermal Runaway, system stopped! Heater_ID: 0").kind == ReplyKind::fatal);
  CHECK(classify_reply("Error:MAXTEMP triggered, system stopped! Heater_ID: bed").kind == ReplyKind::fatal);
  CHECK(classify_reply("Error:Printer stopped due to errors. Fix the error and use M999 to restart.").kind ==
        ReplyKind::fatal);
  CHECK(classify_reply("!! emergency").kind == ReplyKind::fatal);
}

TEST_CASE("busy_wait_start_echo") {
  CHECK(classify_reply("echo:busy: processing").kind == ReplyKind::busy);
  CHECK(classify_reply("busy: paused for user").kind == ReplyKind::busy);
  CHECK(classify_reply("echo:busy: paused for user").kind == ReplyKind::busy);
  CHECK(classify_reply("wait").kind == ReplyKind::wait);
  CHECK(classify_reply("start").kind == ReplyKind::start);
  const auto unknown = classify_reply("echo:Unknown command: \"G999\"");
  CHECK(unknown.kind == ReplyKind::echo);
  CHECK(unknown.unknown_command);
  CHECK(classify_reply("FIRMWARE_NAME:Marlin 2.1.2").kind == ReplyKind::other);
}

TEST_CASE("temperature_reports_without_ok") {
  const auto auto_report = classify_reply(" T:185.23 /210.00 B:59.80 /60.00 @:127 B@:0");
  CHECK(auto_report.kind == ReplyKind::temperature);
  CHECK(auto_report.temperatures->hotend == doctest::Approx(185.23));
  const auto waiting = classify_reply("T:185.2 /210.0 B:60.0 /60.0 @:127 B@:0 W:?");
  CHECK(waiting.kind == ReplyKind::temperature);
  CHECK(waiting.temperatures->bed_target == doctest::Approx(60.0));
  const auto multi = classify_reply("T0:200.0 /200.0 T1:25.0 /0.0 B:60.0 /60.0");
  CHECK(multi.temperatures->hotend == doctest::Approx(200.0));
}

TEST_CASE("position_report") {
  const auto r = classify_reply("X:10.00 Y:20.50 Z:0.30 E:5.12 Count X:800 Y:1640 Z:120");
  CHECK(r.kind == ReplyKind::position);
  REQUIRE(r.position);
  CHECK(r.position->x == doctest::Approx(10.0));
  CHECK(r.position->y == doctest::Approx(20.5));
  CHECK(r.position->z == doctest::Approx(0.3));
  CHECK(r.position->e == doctest::Approx(5.12));
}

TEST_CASE("garbage_is_other_and_never_throws") {
  CHECK(classify_reply("").kind == ReplyKind::other);
  CHECK(classify_reply("\x93\xfe\x11x\xc4\x80").kind == ReplyKind::other);
  CHECK(classify_reply("T:").kind == ReplyKind::other);
  CHECK(classify_reply("X:").kind == ReplyKind::other);
}

TEST_CASE("teacup_ok_lines_carry_refusals_positions_and_temperatures") {
  const auto refused = classify_reply("ok E: Bad M-code 190");
  CHECK(refused.kind == ReplyKind::ok);
  CHECK(refused.refusal == "E: Bad M-code 190");
  const auto at = classify_reply("ok X:10.000,Y:20.500,Z:0.300,E:5.120,F:1500");
  CHECK(at.kind == ReplyKind::ok);
  REQUIRE(at.position);
  CHECK(at.position->y == doctest::Approx(20.5));
  CHECK(at.position->e == doctest::Approx(5.12));
  const auto t = classify_reply("ok T:25.0 B:20.0");
  REQUIRE(t.temperatures);
  CHECK(t.temperatures->hotend == doctest::Approx(25.0));
  CHECK_FALSE(t.temperatures->hotend_target);
  CHECK(classify_reply("Start").kind == ReplyKind::start);
}

TEST_CASE("errors_of_other_dialects") {
  CHECK(classify_reply("E: Bad M-code 107").kind == ReplyKind::error);
  CHECK(classify_reply("fatal:Heater decoupled").kind == ReplyKind::fatal);
  CHECK(classify_reply("skip 14").kind == ReplyKind::skip);
  const auto unknown = classify_reply("Unknown command:M73 P10");
  CHECK(unknown.kind == ReplyKind::echo);
  CHECK(unknown.unknown_command);
  // An extruder position is not an error.
  CHECK(classify_reply("E:1.20").kind != ReplyKind::error);
}

TEST_CASE("a_heating_wait_report_is_told_from_an_auto_report") {
  CHECK(classify_reply("T:185.2 /210.0 B:60.0 /60.0 @:127 B@:0 W:?").heating_wait);
  CHECK(classify_reply("T:185.2 /210.0 B:60.0 /60.0 @:127 B@:0 W:4").heating_wait);
  CHECK_FALSE(classify_reply(" T:185.23 /210.00 B:59.80 /60.00 @:127 B@:0").heating_wait);
}

}  // namespace replies_test
