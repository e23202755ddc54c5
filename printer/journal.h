// The job journal: one small file per print job, rewritten durably at every layer start, so
// that `mahost resume` can finish a job after the host process, the link or the printer died
// (DESIGN.md §4).
//
// Written as JSON to a temporary file, fsync'ed, renamed over the journal, and the directory
// fsync'ed: a crash at any moment leaves either the old record or the new one, never half of
// one. It records the G-code file and its hash (a changed file is refused on resume), the
// layer being printed and the command it starts at (resume reprints that layer from its
// start), and the printer state at that command: position, E, modes, units (G20/G21),
// feedrate, temperatures, fan. Units: mm, mm/min, °C.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "printer/job_state.h"
#include "printer/print_state.h"

namespace printer {

struct JournalRecord {
  std::string job;            // the job's name: "<model>-<time>"
  std::string gcode_path;     // absolute
  std::string gcode_hash;     // content_hash of the file
  std::size_t commands = 0;   // commands in the file
  std::size_t layers = 0;     // layers in the file
  std::string printer;        // the printer profile it was sliced and timed for (name or
                              // absolute path); "" when not known
  std::string firmware;       // the profile's firmware as the job ran it ("teacup", after any
                              // --set); "" when not known
  std::string port;           // where it printed; "" for a dry run
  int baud = 0;
  JobState state = JobState::printing;  // printing, paused, completed, cancelled, stopped, failed
  std::string reason;         // why it ended, when it did not complete
  int layer_index = -1;       // the layer a resume reprints (index into the file's layers); -1: start
  std::size_t resume_command = 0;  // its first command: where a resume continues
  PrintState state_at_resume;      // what the printer held just before that command
  std::string updated;        // local time of this record, ISO 8601
  int pid = 0;                // the host process that wrote it
};

// Writes the record durably (temp + fsync + rename + fsync of the directory; `durable` false
// skips the fsyncs, for dry runs). Throws ConfigError naming the path when it cannot.
void write_journal(const std::string& path, const JournalRecord& record, bool durable = true);

// Reads a journal. Throws ConfigError naming the file for a missing, unreadable or malformed
// one, saying which key is wrong.
JournalRecord read_journal(const std::string& path);

// The command that finishes an interrupted job: "mahost resume JOURNAL --port PORT"; for
// `port` "" a rehearsal on the simulated printer ("--dry-run"). Where the port is not known,
// pass the placeholder kAnyPort.
inline constexpr std::string_view kAnyPort = "PORT";
std::string resume_command(std::string_view journal_path, std::string_view port);

// Where jobs keep their journals and control sockets: $XDG_RUNTIME_DIR/mahost, or
// /tmp/mahost-<uid> where that is unset; created with mode 0700. Throws ConfigError when it
// cannot be created or belongs to someone else.
std::string job_directory();

}  // namespace printer
