#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <cstdlib>

int main(int argc, char** argv) {
  // Every mahost a test runs finds the shipped profiles only, never the developer's own
  // (~/.config/mahost) nor the machine's (/etc/xdg/mahost); a test that wants a user's or a
  // system's folder sets these itself.
  ::setenv("XDG_CONFIG_HOME", "/nonexistent/mahost-tests/user", 1);
  ::setenv("XDG_CONFIG_DIRS", "/nonexistent/mahost-tests/system", 1);
  return doctest::Context(argc, argv).run();
}
