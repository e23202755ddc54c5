#include "host/check_while_connecting.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <future>
#include <string>

#include <doctest/doctest.h>
#include <fmt/core.h>

#include "printer/error.h"
#include "printer/gcode_file.h"
#include "printer/line_protocol.h"
#include "printer/test_program.h"
#include "sim/sim_link.h"
#include "support/run_command.h"

namespace check_while_connecting_test {

using host::check_while_connecting;

// Only a guard against a hang: each side waits for the other to have begun, which it has at
// once when the two run together, and never when one runs after the other.
constexpr auto kHangGuard = std::chrono::seconds(60);

TEST_CASE("the_file_is_checked_while_the_printer_connects") {
  std::promise<void> check_began, connect_began;
  std::future<void> check_begun = check_began.get_future(), connect_begun = connect_began.get_future();
  bool check_saw_connect = false, connect_saw_check = false;
  const int checked = check_while_connecting(
      [&] {
        check_began.set_value();
        check_saw_connect = connect_begun.wait_for(kHangGuard) == std::future_status::ready;
        return 7;
      },
      [&] {
        connect_began.set_value();
        connect_saw_check = check_begun.wait_for(kHangGuard) == std::future_status::ready;
      });
  CHECK(checked == 7);
  CHECK(check_saw_connect);
  CHECK(connect_saw_check);
}

// A printer that cannot be reached: every use of the port fails.
struct MissingPort : printer::Link {
  void write(std::string_view) override { throw printer::LinkError("/dev/ttyUSB9: no such port"); }
  std::string read(std::chrono::milliseconds) override { throw printer::LinkError("/dev/ttyUSB9: no such port"); }
  std::chrono::nanoseconds now() const override { return {}; }
  std::string name() const override { return "/dev/ttyUSB9"; }
};

TEST_CASE("a_file_whose_last_line_is_bad_is_refused_with_nothing_of_it_sent") {
  std::string program = test_support::ring_program(4, 40);
  const std::size_t lines = static_cast<std::size_t>(std::count(program.begin(), program.end(), '\n'));
  program += "G1 X10 Y=5\n";
  const std::string path = test_support::scratch_dir("check_while_connecting") + "/last_bad.gcode";
  std::ofstream(path, std::ios::binary) << program;
  const std::string refusal =
      fmt::format("{}: line {} is not G-code (it has a parameter whose value is not a number", path, lines + 1);

  sim::SimLink link;
  printer::LineProtocol protocol(link);
  std::string message;
  try {
    check_while_connecting([&] { return printer::read_gcode_file(path); }, [&] { protocol.connect(); });
  } catch (const printer::ConfigError& e) {
    message = e.what();
  }
  CHECK(message.starts_with(refusal));
  // The printer was connected meanwhile: it ran connect's own lines and nothing of the file.
  const std::vector<std::string>& executed = link.printer().executed_commands();
  CHECK(std::count(executed.begin(), executed.end(), "M115") == 1);
  CHECK(std::all_of(executed.begin(), executed.end(), [](const std::string& c) { return c == "M110 N0" || c == "M115"; }));

  // A port that cannot be opened as well: the file's refusal is still what is said; with a
  // good file, the port's failure.
  MissingPort missing;
  printer::LineProtocol unreachable(missing);
  message.clear();
  try {
    check_while_connecting([&] { return printer::read_gcode_file(path); }, [&] { unreachable.connect(); });
  } catch (const printer::ConfigError& e) {
    message = e.what();
  }
  CHECK(message.starts_with(refusal));
  std::ofstream(path, std::ios::binary) << test_support::ring_program(4, 40);
  CHECK_THROWS_AS(
      check_while_connecting([&] { return printer::read_gcode_file(path); }, [&] { unreachable.connect(); }),
      printer::LinkError);
}

}  // namespace check_while_connecting_test
