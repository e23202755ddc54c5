#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "support/run_command.h"

namespace {

// A test process that dies says where its files are kept, then dies of the same signal
// (doctest's own handler, which names the test case, has run by then).
void on_fatal_signal(int signal) {
  test_support::say_scratch_kept_after_death();
  ::signal(signal, SIG_DFL);
  ::raise(signal);
}

}  // namespace

int main(int argc, char** argv) {
  // Every mahost a test runs finds the shipped profiles only, never the developer's own
  // (~/.config/mahost) nor the machine's (/etc/xdg/mahost); a test that wants a user's or a
  // system's folder sets these itself.
  ::setenv("XDG_CONFIG_HOME", "/nonexistent/mahost-tests/user", 1);
  ::setenv("XDG_CONFIG_DIRS", "/nonexistent/mahost-tests/system", 1);
  // A write to a socket or pipe the other end closed (a server that dropped a connection) is
  // an error the test sees and reports, not a silent death.
  ::signal(SIGPIPE, SIG_IGN);
  for (const int fatal : {SIGSEGV, SIGABRT, SIGBUS, SIGFPE, SIGILL, SIGTERM}) ::signal(fatal, on_fatal_signal);
  doctest::Context context(argc, argv);
  const int failed = context.run();
  // A failure's evidence (what a server or a simulated printer said) in the test's output,
  // its files kept: a failure seen once under load is read, not guessed at. A process that
  // dies before here keeps its files too (test_support::scratch_dir).
  if (failed != 0 && !context.shouldExit()) {
    const std::string kept = test_support::keep_scratch_after_failure();
    std::fputs(kept.c_str(), stderr);
  }
  test_support::mark_scratch_ended();
  return failed;
}
