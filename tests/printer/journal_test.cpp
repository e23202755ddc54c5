// The job journal's file format and the resume command built from it (DESIGN.md §4).
#include "printer/journal.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include <doctest/doctest.h>

#include "printer/error.h"
#include "support/run_command.h"

namespace journal_test {

using namespace printer;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST_CASE("journal_state_is_written_as_its_word_and_read_back_as_the_state") {
  const std::string dir = test_support::scratch_dir("journal_state");
  for (const JobState state : {JobState::printing, JobState::paused, JobState::completed,
                               JobState::cancelled, JobState::stopped, JobState::failed}) {
    CAPTURE(to_string(state));
    JournalRecord record;
    record.job = "ring";
    record.state = state;
    const std::string path = dir + "/ring.journal";
    write_journal(path, record, false);
    CHECK(read_text(path).find(std::string("\"state\": \"") + std::string(to_string(state)) + "\"") !=
          std::string::npos);
    CHECK(read_journal(path).state == state);
  }
}

TEST_CASE("journal_with_a_state_no_job_records_is_refused_naming_it") {
  const std::string dir = test_support::scratch_dir("journal_bad_state");
  const std::string path = dir + "/ring.journal";
  JournalRecord record;
  write_journal(path, record, false);
  std::string text = read_text(path);
  text.replace(text.find("\"printing\""), 10, "\"sleeping\"");
  std::ofstream(path) << text;
  std::string message;
  try {
    read_journal(path);
  } catch (const ConfigError& e) {
    message = e.what();
  }
  CHECK(message == path + ": the journal's state \"sleeping\" is not one a job records");
}

TEST_CASE("resume_command_names_the_port_or_a_dry_run") {
  CHECK(resume_command("/run/j.journal", "/dev/ttyUSB0") == "mahost resume /run/j.journal --port /dev/ttyUSB0");
  CHECK(resume_command("/run/j.journal", kAnyPort) == "mahost resume /run/j.journal --port PORT");
  CHECK(resume_command("/run/j.journal", "") == "mahost resume /run/j.journal --dry-run");
}

}  // namespace journal_test
