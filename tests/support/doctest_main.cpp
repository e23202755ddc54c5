#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "support/run_command.h"

int main(int argc, char** argv) {
  // Every mahost a test runs finds the shipped profiles only, never the developer's own
  // (~/.config/mahost) nor the machine's (/etc/xdg/mahost); a test that wants a user's or a
  // system's folder sets these itself.
  ::setenv("XDG_CONFIG_HOME", "/nonexistent/mahost-tests/user", 1);
  ::setenv("XDG_CONFIG_DIRS", "/nonexistent/mahost-tests/system", 1);
  doctest::Context context(argc, argv);
  const int failed = context.run();
  // A failure's evidence (what a server or a simulated printer said) in the test's output,
  // its files kept: a failure seen once under load is read, not guessed at.
  if (failed != 0 && !context.shouldExit()) {
    const std::string kept = test_support::keep_scratch_after_failure();
    std::fputs(kept.c_str(), stderr);
  }
  return failed;
}
