// The fixture's way of starting `mahost serve` and `mahost sim` (support/run_command.h's
// spawn_tied): a program that cannot start is an error naming it, not a child that exits 127
// and a test left waiting for a line it never prints.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "support/run_command.h"

namespace {

std::vector<char*> c_strings(std::vector<std::string>& strings) {
  std::vector<char*> out;
  for (std::string& s : strings) out.push_back(s.data());
  out.push_back(nullptr);
  return out;
}

}  // namespace

TEST_CASE("spawn_tied_says_which_program_it_could_not_start") {
  std::vector<std::string> argv{"/nonexistent/mahost", "serve"}, env{"PATH=/usr/bin"};
  const std::string log = std::filesystem::temp_directory_path() / "spawn_tied_test_missing.log";
  int out[2];
  REQUIRE(pipe(out) == 0);
  std::string what;
  try {
    test_support::spawn_tied(c_strings(argv), c_strings(env), out[1], log);
  } catch (const std::runtime_error& e) {
    what = e.what();
  }
  close(out[0]);
  close(out[1]);
  std::filesystem::remove(log);
  CHECK(what == "cannot start /nonexistent/mahost: No such file or directory");
}

TEST_CASE("spawn_tied_runs_the_program_with_its_output_on_the_descriptor_and_stderr_in_the_file") {
  std::vector<std::string> argv{"/bin/sh", "-c", "echo out; echo err >&2; exit 3"};
  std::vector<std::string> env{"PATH=/usr/bin:/bin"};
  const std::string log = std::filesystem::temp_directory_path() / "spawn_tied_test_runs.log";
  std::filesystem::remove(log);
  int out[2];
  REQUIRE(pipe(out) == 0);
  const int pid = test_support::spawn_tied(c_strings(argv), c_strings(env), out[1], log);
  close(out[1]);
  std::string text;
  char buffer[64];
  for (ssize_t n; (n = read(out[0], buffer, sizeof buffer)) > 0;) text.append(buffer, n);
  close(out[0]);
  int status = 0;
  REQUIRE(waitpid(pid, &status, 0) == pid);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 3);
  CHECK(text == "out\n");
  std::ifstream in(log);
  std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(err == "err\n");
  std::filesystem::remove(log);
}
