// Runs a program (by default the built mahost) as a user would, for CLI integration tests.
#pragma once

#include <chrono>
#include <string>
#include <vector>

namespace test_support {

struct CommandResult {
  int exit_code = -1;      // the process's exit code; 128 + signal if it was killed
  bool timed_out = false;  // killed after `timeout`
  std::string out, err;
};

// Runs `argv` (argv[0] a path or a name looked up in PATH) with `input` on stdin, collecting
// stdout and stderr; kills it after `timeout`.
CommandResult run_command(const std::vector<std::string>& argv, const std::string& input = {},
                          std::chrono::seconds timeout = std::chrono::seconds(300));

// The same for the mahost binary under test: run_mahost({"info", "cube.stl"}).
CommandResult run_mahost(const std::vector<std::string>& args, const std::string& input = {},
                         std::chrono::seconds timeout = std::chrono::seconds(300));

// Starts `argv` (argv[0] a path) with `envp` as a process that dies with the thread calling
// this (Linux's parent-death signal, SIGKILL), so that a server or simulated printer a test
// started does not outlive a test process killed before its destructors ran. Its stdin is
// /dev/null, its stdout `stdout_fd`, its stderr appended to `stderr_path`. Returns its pid;
// throws when it cannot be started. Call it from the thread that stays for the child's life
// (the test's own).
int spawn_tied(const std::vector<char*>& argv, const std::vector<char*>& envp, int stdout_fd,
               const std::string& stderr_path);

// Path of a fresh, empty scratch directory for one test (removed by the next run's cleanup).
std::string scratch_dir(const std::string& test_name);

// After a failed test: the ends of the logs in this process's scratch folders (a server's,
// a simulated printer's), and the folder kept for a day where they say; "" when the process
// made none. The tests' main calls it when a test fails.
std::string keep_scratch_after_failure();
// After the tests ran to their end, failed or not: the process did not die, and the next
// process's clean-up removes its folders (a folder without this mark, its process gone, is
// kept for a day as died-PID).
void mark_scratch_ended();
// For a signal handler (async-signal-safe): says on stderr where the dying process's files
// are kept; nothing when it made none.
void say_scratch_kept_after_death();

}  // namespace test_support
