// The help of the commands a user prints with: one short line each in `mahost --help`, and
// every option saying its default (or that it is required), so nobody has to read the source.
#include <sstream>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "support/run_command.h"

namespace help_cli_test {

using test_support::run_mahost;

namespace {

// The options of a command's help: each entry is the option's line with its continuation
// lines (CLI11 puts a long description on the next line).
std::vector<std::string> option_entries(const std::string& help) {
  std::vector<std::string> entries;
  std::istringstream in(help);
  std::string line;
  bool in_option = false;
  while (std::getline(in, line)) {
    if (line.starts_with("  -")) {
      entries.push_back(line);
      in_option = true;
    } else if (in_option && line.starts_with("     ")) {
      entries.back() += " " + line;
    } else {
      in_option = false;  // a heading, a positional or a blank line
    }
  }
  std::erase_if(entries, [](const std::string& e) { return e.starts_with("  -h,--help"); });
  return entries;
}

const std::vector<std::string> kCommands{"info", "slice", "print", "resume", "ctl", "ports"};

}  // namespace

TEST_CASE("every_option_of_the_printing_commands_says_its_default") {
  for (const std::string& command : kCommands) {
    CAPTURE(command);
    const auto r = run_mahost({command, "--help"});
    REQUIRE(r.exit_code == 0);
    for (const std::string& entry : option_entries(r.out)) {
      CAPTURE(entry);
      CHECK((entry.find("default") != std::string::npos || entry.find("required") != std::string::npos));
    }
  }
}

TEST_CASE("command_summaries_are_short_capitalised_lines_without_a_period") {
  const auto r = run_mahost({"--help"});
  REQUIRE(r.exit_code == 0);
  for (const std::string& command : kCommands) {
    CAPTURE(command);
    const std::size_t at = r.out.find("\n  " + command + " ");
    REQUIRE(at != std::string::npos);
    const std::size_t end = r.out.find('\n', at + 1);
    std::string summary = r.out.substr(at + 3 + command.size(), end - at - 3 - command.size());
    summary.erase(0, summary.find_first_not_of(' '));
    CAPTURE(summary);
    CHECK(!summary.empty());
    CHECK(summary.size() <= 60);
    CHECK(std::isupper(static_cast<unsigned char>(summary.front())));
    CHECK(summary.back() != '.');
  }
}

TEST_CASE("print_help_groups_the_slice_options_and_says_how_layers_are_numbered") {
  const auto r = run_mahost({"print", "--help"});
  REQUIRE(r.exit_code == 0);
  const std::size_t group = r.out.find("\nSlicing (a model; see mahost slice --help):\n");
  REQUIRE(group != std::string::npos);
  // Every slice option is listed under that heading, after the link and job options.
  for (const char* option : {"--units", "--scale", "--height", "--up", "--printer", "--material",
                             "--layer", "--contour", "--perimeters", "--infill", "--set", "-o,--output"}) {
    CAPTURE(option);
    const std::size_t at = r.out.find(std::string("\n  ") + option);
    REQUIRE(at != std::string::npos);
    CHECK(at > group);
  }
  for (const char* option : {"--port", "--dry-run", "--pause-at-layer", "--journal", "--keep"}) {
    CAPTURE(option);
    const std::size_t at = r.out.find(std::string("\n  ") + option);
    REQUIRE(at != std::string::npos);
    CHECK(at < group);
  }
  CHECK(r.out.find("numbered from 1 as the progress line shows them (layer n is the file's "
                   ";LAYER:n-1)") != std::string::npos);
}

}  // namespace help_cli_test
