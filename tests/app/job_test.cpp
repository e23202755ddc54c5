// A job resumed from its journal (app/job.h), the one set-up `mahost resume` and `mahost
// serve` share.
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "app/job.h"
#include "printer/error.h"
#include "printer/print_state.h"
#include "support/run_command.h"

namespace job_test {

printer::JournalRecord interrupted_record(const printer::GcodeFile& file) {
  printer::JournalRecord record;
  record.job = "cube-20261206-041500";
  record.gcode_path = "/jobs/cube.gcode";
  record.gcode_hash = file.hash;
  record.commands = file.size();
  record.printer = "generic-marlin";
  record.firmware = "teacup";
  record.port = "/dev/ttyUSB0";
  record.baud = 250000;
  record.state = printer::JobState::failed;
  record.layer_index = 1;
  record.resume_command = 4;
  record.state_at_resume.z = 0.5;
  record.pid = 4242;
  return record;
}

const char* const kProgram =
    "G28\nM104 S200\n;LAYER:0\nG1 Z0.3 F600\nG1 X10 Y10 E1\n;LAYER:1\nG1 Z0.5\nG1 X20 E2\n";

TEST_CASE("a_resume_continues_at_the_recorded_command_from_the_state_before_it") {
  const printer::GcodeFile file = printer::parse_gcode(kProgram, "cube.gcode");
  const printer::JournalRecord record = interrupted_record(file);
  printer::PrinterProfile machine;
  machine.motion.max_acceleration[0] = 1234;
  printer::PauseOptions pause;
  pause.lift = 7;

  const printer::JobOptions kept =
      app::resume_job_options(record, machine, pause, "/jobs/cube.journal", "/dev/ttyACM1", 115200, true);
  CHECK(kept.first_command == 4);
  REQUIRE(kept.recover_from);
  CHECK(kept.recover_from->z == 0.5);
  CHECK(kept.pause.lift == 7);
  CHECK(kept.motion.max_acceleration[0] == 1234);
  CHECK(kept.journal_path == "/jobs/cube.journal");
  CHECK(kept.journal_durable);
  // The journal goes on from the record, at the port it now prints on, by no process yet.
  CHECK(kept.journal.job == record.job);
  CHECK(kept.journal.port == "/dev/ttyACM1");
  CHECK(kept.journal.baud == 115200);
  CHECK(kept.journal.pid == 0);
  CHECK_FALSE(kept.resume_command);

  // A rehearsal keeps no journal; a resume of a job interrupted before its first layer
  // starts from the top with nothing to recover.
  printer::JournalRecord early = record;
  early.layer_index = -1;
  early.resume_command = 0;
  const printer::JobOptions rehearsal = app::resume_job_options(early, machine, pause, "", "", 0, false);
  CHECK(rehearsal.journal_path.empty());
  CHECK(rehearsal.first_command == 0);
  CHECK_FALSE(rehearsal.recover_from);
}

TEST_CASE("a_resume_after_g20_goes_on_in_inches") {
  // The journal records the units with the modes: a file in inches resumed from its
  // journal is sent G20 before its next line, and F as the file wrote it.
  const printer::GcodeFile file = printer::parse_gcode(kProgram, "cube.gcode");
  printer::JournalRecord record = interrupted_record(file);
  for (const char* command : {"G20", "G90", "M83", "G1 X1 Y1 Z0.02 F60"}) {
    printer::apply(record.state_at_resume, command);
  }
  const std::string path = test_support::scratch_dir("job_inches") + "/cube.journal";
  printer::write_journal(path, record, false);
  const printer::JournalRecord read = printer::read_journal(path);

  const printer::JobOptions resumed =
      app::resume_job_options(read, printer::PrinterProfile{}, printer::PauseOptions{}, "", "", 0, false);
  REQUIRE(resumed.recover_from);
  CHECK(resumed.recover_from->unit == 25.4);
  CHECK(resumed.recover_from->x == doctest::Approx(25.4));
  const std::vector<std::string> modes = printer::restore_modes(*resumed.recover_from);
  CHECK(modes == std::vector<std::string>{"G90", "M83", "G20", "G1 F60"});
}

TEST_CASE("a_changed_file_is_not_resumed") {
  const printer::GcodeFile file = printer::parse_gcode(kProgram, "cube.gcode");
  const printer::JournalRecord record = interrupted_record(file);
  CHECK_NOTHROW(app::check_resumable_file(record, file));
  const printer::GcodeFile edited = printer::parse_gcode(std::string(kProgram) + "G1 X30 E3\n", "cube.gcode");
  CHECK_THROWS_WITH_AS(app::check_resumable_file(record, edited),
                       doctest::Contains("/jobs/cube.gcode: the file changed since the job started"),
                       printer::ConfigError);
  printer::JournalRecord other = record;
  other.commands = file.size() + 1;
  CHECK_THROWS_AS(app::check_resumable_file(other, file), printer::ConfigError);
}

TEST_CASE("a_resume_times_the_rest_with_the_printer_and_firmware_the_job_ran") {
  printer::JournalRecord record;
  record.printer = "generic-marlin";
  record.firmware = "teacup";
  std::string heard;
  const auto note = [&](const std::string& line) { heard += line; };
  const printer::PrinterProfile machine = app::resume_profile(record, note);
  CHECK(machine.name != printer::PrinterProfile{}.name);
  CHECK(machine.firmware == printer::Firmware::teacup);
  CHECK(heard.empty());
  // No printer named: the default one.
  record.printer.clear();
  record.firmware.clear();
  CHECK(app::resume_profile(record, note).source.find(printer::kDefaultPrinter) != std::string::npos);
  // One that is gone: Marlin's default motion limits, and why.
  record.printer = "/nowhere/gone.toml";
  const printer::PrinterProfile fallback = app::resume_profile(record, note);
  CHECK(fallback.motion.max_acceleration == printer::PrinterProfile{}.motion.max_acceleration);
  CHECK(heard.find("the remaining time uses Marlin's default motion limits") != std::string::npos);
}

}  // namespace job_test
