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

// The one-line refusal of a journal ".../ring.journal" written, then edited: `from` replaced by
// `to`.
std::string refusal_of_edited_journal(const std::string& test, const std::string& from,
                                      const std::string& to) {
  const std::string path = test_support::scratch_dir(test) + "/ring.journal";
  write_journal(path, JournalRecord{}, false);
  std::string text = read_text(path);
  text.replace(text.find(from), from.size(), to);
  std::ofstream(path) << text;
  try {
    read_journal(path);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
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
  const std::string message =
      refusal_of_edited_journal("journal_bad_state", "\"printing\"", "\"sleeping\"");
  CHECK(message.ends_with("/ring.journal: the journal's state \"sleeping\" is not one a job records"));
}

TEST_CASE("journal_with_units_other_than_mm_or_inches_is_refused_naming_them") {
  const std::string message =
      refusal_of_edited_journal("journal_bad_units", "\"units\": \"mm\"", "\"units\": \"cubits\"");
  CHECK(message.ends_with("/ring.journal: the journal's units \"cubits\" are neither \"mm\" nor \"inches\""));
}

TEST_CASE("resume_command_names_the_port_or_a_dry_run") {
  CHECK(resume_command("/run/j.journal", "/dev/ttyUSB0") == "mahost resume /run/j.journal --port /dev/ttyUSB0");
  CHECK(resume_command("/run/j.journal", kAnyPort) == "mahost resume /run/j.journal --port PORT");
  CHECK(resume_command("/run/j.journal", "") == "mahost resume /run/j.journal --dry-run");
}

}  // namespace journal_test
