// `mahost sim` as a user runs it: the port on the first line, a summary on SIGINT, one clear
// line for a bad flag, the `start` banner again when a host reopens the port, and Printrun's
// printcore (a real third-party host) printing a file through it, with the sim's executed
// commands equal to the file's, with and without 1% byte corruption.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

extern char** environ;

namespace cmd_sim_test {

using test_support::run_command;
using test_support::run_mahost;

namespace {

// `mahost sim ...` in the background: its port, then its summary after SIGINT.
class SimProcess {
 public:
  explicit SimProcess(std::vector<std::string> args) {
    int out[2];
    REQUIRE(pipe2(out, O_CLOEXEC) == 0);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, out[1], 1);
    args.insert(args.begin(), {MAHOST_BINARY, "sim"});
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    REQUIRE(posix_spawn(&pid_, MAHOST_BINARY, &actions, nullptr, argv.data(), environ) == 0);
    posix_spawn_file_actions_destroy(&actions);
    close(out[1]);
    out_ = out[0];
    port_ = read_line(std::chrono::seconds(10));
  }
  ~SimProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) close(out_);
  }

  const std::string& port() const { return port_; }

  // Reads the sim's output up to the line `line` (each host coming or going is one); false if
  // it does not come within a minute or the sim exits.
  bool wait_for_line(const std::string& line) {
    for (;;) {
      const std::string got = read_line(std::chrono::seconds(60));
      if (got == line) return true;
      if (got.empty() && pending_.find('\n') == std::string::npos) return false;
    }
  }

  // SIGINT, then everything it printed after the port; its exit code in `code`.
  std::string stop(int& code) {
    kill(pid_, SIGINT);
    std::string rest;
    char buffer[4096];
    for (;;) {
      pollfd fd{out_, POLLIN, 0};
      if (poll(&fd, 1, 20000) <= 0) break;
      const ssize_t n = read(out_, buffer, sizeof buffer);
      if (n <= 0) break;
      rest.append(buffer, static_cast<std::size_t>(n));
    }
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return pending_ + rest;
  }

 private:
  std::string read_line(std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (pending_.find('\n') == std::string::npos && std::chrono::steady_clock::now() < deadline) {
      pollfd fd{out_, POLLIN, 0};
      if (poll(&fd, 1, 100) <= 0) continue;
      char buffer[256];
      const ssize_t n = read(out_, buffer, sizeof buffer);
      if (n <= 0) break;
      pending_.append(buffer, static_cast<std::size_t>(n));
    }
    const auto end = pending_.find('\n');
    if (end == std::string::npos) return "";
    std::string line = pending_.substr(0, end);
    pending_.erase(0, end + 1);
    return line;
  }

  pid_t pid_ = -1;
  int out_ = -1;
  std::string port_;
  std::string pending_;
};

// Opens a port raw, as a host's serial library does.
int open_port(const std::string& path) {
  const int fd = open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) return fd;
  termios raw{};
  tcgetattr(fd, &raw);
  cfmakeraw(&raw);
  tcsetattr(fd, TCSANOW, &raw);
  return fd;
}

// Reads until `text` has come, or `seconds` pass: a guard against a hang, long enough for a
// loaded machine, never a measure of speed.
constexpr double kHangGuard = 60;
std::string read_until(int fd, const std::string& text, double seconds = kHangGuard) {
  std::string got;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (got.find(text) == std::string::npos && std::chrono::steady_clock::now() < deadline) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 50) <= 0) continue;
    char buffer[1024];
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n > 0) got.append(buffer, static_cast<std::size_t>(n));
  }
  return got;
}

// A small real print: heat, home, five layers of a 20 mm square (two perimeters each) with
// relative E, retraction, fan, end code; with comments and blank lines as slicers write them.
std::string test_print() {
  std::string g = "; generated for the printcore test\n"
                  "M140 S60 ; bed\nM104 S200\nG28 ; home all\nM190 S60\nM109 S200\n"
                  "G90\nM83\nG92 E0\nG1 Z0.3 F600\n\n";
  for (int layer = 0; layer < 5; ++layer) {
    const double z = 0.3 + 0.2 * layer;
    g += fmt::format(";LAYER:{}\nG1 Z{:.2f} F600\n", layer, z);
    if (layer == 1) g += "M106 S255\n";
    for (int loop = 0; loop < 2; ++loop) {
      const double a = 90 + 0.4 * loop, b = 110 - 0.4 * loop;
      g += fmt::format("G1 X{:.1f} Y{:.1f} F6000\nG1 E0.8 F2400\n", a, a);
      g += fmt::format(";TYPE:WALL\nG1 X{0:.1f} Y{1:.1f} E0.67 F1800\nG1 X{0:.1f} Y{0:.1f} E0.67\n"
                       "G1 X{1:.1f} Y{0:.1f} E0.67\nG1 X{1:.1f} Y{1:.1f} E0.67\nG1 E-0.8 F2400\n",
                       b, a);
    }
  }
  g += "M107\nM104 S0\nM140 S0\nG91\nG1 Z10 F600\nG90\nM84\n; end\n";
  return g;
}

// What printcore sends of a file: each line without ';' comments, blank ones skipped.
std::vector<std::string> file_commands(const std::string& gcode) {
  std::vector<std::string> commands;
  std::size_t start = 0;
  while (start < gcode.size()) {
    const std::size_t end = std::min(gcode.find('\n', start), gcode.size());
    std::string line = gcode.substr(start, end - start);
    line = line.substr(0, line.find(';'));
    line.erase(0, line.find_first_not_of(" \t"));
    line.erase(line.find_last_not_of(" \t\r") + 1);
    if (!line.empty()) commands.push_back(line);
    start = end + 1;
  }
  return commands;
}

// The executed log from printcore's "N-1 M110" (after its M105 handshake) up to its closing
// M110: exactly the file's commands if nothing was lost or repeated.
std::vector<std::string> printed_commands(const nlohmann::json& record) {
  std::vector<std::string> log = record.at("commands").get<std::vector<std::string>>();
  const auto first = std::find(log.begin(), log.end(), "M110");
  REQUIRE(first != log.end());
  std::vector<std::string> printed(first + 1, log.end());
  if (!printed.empty() && printed.back() == "M110") printed.pop_back();
  return printed;
}

void print_with_printcore(const std::string& faults, const std::string& name) {
  const std::string dir = test_support::scratch_dir(name);
  const std::string gcode_path = dir + "/print.gcode", record_path = dir + "/record.json";
  const std::string gcode = test_print();
  std::ofstream(gcode_path) << gcode;

  std::vector<std::string> args{"--pty", "--time-scale", "max", "--record", record_path};
  if (!faults.empty()) args.insert(args.end(), {"--faults", faults});
  SimProcess sim(args);
  REQUIRE(sim.port().starts_with("/dev/pts/"));

  const auto printcore = run_command({"printcore", "-v", sim.port(), gcode_path}, "",
                                     std::chrono::seconds(180));
  INFO("printcore stderr: " << printcore.err.substr(0, 3000));
  REQUIRE_MESSAGE(printcore.exit_code != 127, "printcore is not installed: run scripts/setup");
  CHECK_FALSE(printcore.timed_out);
  CHECK(printcore.exit_code == 0);

  int code = -1;
  const std::string summary = sim.stop(code);
  CHECK(code == 0);
  CHECK(summary.find("print time") != std::string::npos);
  // The squares stand on one another: nothing laid on air (the unsupported-extrusion check,
  // on what the simulated firmware deposited). 5 layers x (80 + 76.8) mm of bead, walls only.
  CHECK(summary.find("deposited   unsupported extrusion: 0.0 mm of 0.8 m (0.00%; bridges up to "
                     "10 mm, contact gap 0.2 mm)") != std::string::npos);
  std::ifstream in(record_path);
  REQUIRE(in.good());
  const nlohmann::json record = nlohmann::json::parse(in);
  CHECK(printed_commands(record) == file_commands(gcode));
  if (faults.empty()) {
    CHECK(record["counters"]["resends"] == 0);
  } else {
    CHECK(record["counters"]["faults_injected"].get<int>() > 0);
    CHECK(record["counters"]["resends"].get<int>() >= record["counters"]["faults_injected"].get<int>());
  }
  // Five layers of two 20 mm and 19.2 mm squares laid down.
  CHECK(record["layers"].size() == 5);
  CHECK(record["moves"].size() == 5 * 8);
}

}  // namespace

TEST_CASE("sim_prints_its_port_first_and_a_summary_on_sigint") {
  SimProcess sim({"--time-scale", "max"});
  CHECK(sim.port().starts_with("/dev/pts/"));
  int code = -1;
  const std::string summary = sim.stop(code);
  CHECK(code == 0);
  CHECK(summary.find("lines       0 accepted") != std::string::npos);
  CHECK(summary.find("print time  ") != std::string::npos);
  CHECK(summary.find("deposited   unsupported extrusion: 0.0 mm of 0.0 m") != std::string::npos);
}

TEST_CASE("sim_says_start_again_when_a_host_reopens_the_port") {
  SimProcess sim({"--time-scale", "max"});
  int fd = open_port(sim.port());
  REQUIRE(fd >= 0);
  CHECK(read_until(fd, "Author").starts_with("start\n"));
  CHECK(write(fd, "M114\n", 5) == 5);
  CHECK(read_until(fd, "ok\n") == "X:0.00 Y:0.00 Z:0.00 E:0.00 Count X:0 Y:0 Z:0\nok\n");
  close(fd);
  REQUIRE(sim.wait_for_line("host closed the port"));
  fd = open_port(sim.port());
  REQUIRE(fd >= 0);
  CHECK(read_until(fd, "Author").starts_with("start\n"));
  close(fd);
  int code = -1;
  CHECK(sim.stop(code).find("port opened 2 times") != std::string::npos);
}

TEST_CASE("sim_refuses_a_bad_fault_spec_in_one_line") {
  const auto result = run_mahost({"sim", "--faults", "corrupt=2"});
  CHECK(result.exit_code == 2);
  CHECK(result.out.empty());
  CHECK(result.err ==
        "mahost: fault spec 'corrupt=2': give a probability from 0 to 1, e.g. 0.01\n");
  const auto unknown = run_mahost({"sim", "--faults", "explode=1"});
  CHECK(unknown.exit_code == 2);
  CHECK(unknown.err.starts_with("mahost: fault spec: unknown fault 'explode' (known: corrupt,"));
}

TEST_CASE("sim_refuses_an_unwritable_record_before_serving") {
  const auto result = run_mahost({"sim", "--record", "/nonexistent-dir/record.json"});
  CHECK(result.exit_code == 2);
  CHECK(result.out.empty());
  CHECK(result.err == "mahost: cannot write the record /nonexistent-dir/record.json: No such file "
                      "or directory; check the folder exists and is writable\n");
}

TEST_CASE("sim_refuses_an_unknown_printer_profile") {
  const auto result = run_mahost({"sim", "--printer", "nosuch"});
  CHECK(result.exit_code == 2);
  CHECK(result.out.empty());
  CHECK(std::count(result.err.begin(), result.err.end(), '\n') == 1);
  CHECK(result.err.find("'nosuch'") != std::string::npos);
}

TEST_CASE("sim_refuses_a_bad_time_scale_and_baud") {
  const auto scale = run_mahost({"sim", "--time-scale", "fast"});
  CHECK(scale.exit_code == 2);
  CHECK(scale.err == "mahost: --time-scale fast: give a speed-up factor above 0 (1 = real "
                     "time, 10 = ten times faster) or max\n");
  const auto baud = run_mahost({"sim", "--baud", "0"});
  CHECK(baud.exit_code == 2);
  CHECK(std::count(baud.err.begin(), baud.err.end(), '\n') == 1);
  CHECK(baud.err.find("--baud") != std::string::npos);
  CHECK(baud.err.find("0 is not a serial speed; give one of 9600, 19200, 38400, 57600, 115200, ") !=
        std::string::npos);
}

TEST_CASE("printcore_prints_a_file_and_the_sim_executes_exactly_its_commands") {
  print_with_printcore("", "printcore_clean");
}

TEST_CASE("printcore_through_one_percent_byte_corruption_loses_and_repeats_nothing") {
  print_with_printcore("corrupt=0.01,from-line=0,seed=7", "printcore_corrupt");
}

TEST_CASE("sim_without_reset_on_open_keeps_its_state_across_hosts") {
  SimProcess sim({"--time-scale", "max", "--no-reset-on-open"});
  int fd = open_port(sim.port());
  REQUIRE(fd >= 0);
  CHECK(write(fd, "G92 X5\n", 7) == 7);
  // (The power-on banner comes too if the port was opened before the server first looked.)
  CHECK(read_until(fd, "ok\n").ends_with("ok\n"));
  close(fd);
  REQUIRE(sim.wait_for_line("host closed the port"));
  fd = open_port(sim.port());
  REQUIRE(fd >= 0);
  CHECK(write(fd, "M114\n", 5) == 5);
  CHECK(read_until(fd, "ok\n") == "X:5.00 Y:0.00 Z:0.00 E:0.00 Count X:400 Y:0 Z:0\nok\n");
  close(fd);
  int code = -1;
  sim.stop(code);
  CHECK(code == 0);
}

TEST_CASE("sim_baud_paces_replies_no_faster_than_the_uart") {
  // A lower bound only: a slow machine takes longer, never less.
  SimProcess sim({"--time-scale", "max", "--baud", "9600"});
  const int fd = open_port(sim.port());
  REQUIRE(fd >= 0);
  read_until(fd, "Author");
  const auto start = std::chrono::steady_clock::now();
  CHECK(write(fd, "M115\n", 5) == 5);
  const std::string reply = read_until(fd, "ok\n");
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  REQUIRE(reply.ends_with("ok\n"));
  CHECK(took >= (5 + reply.size()) * 10 / 9600.0 * 0.98);
  close(fd);
  int code = -1;
  sim.stop(code);
}

TEST_CASE("sim_speaks_the_dialect_it_is_told") {
  SimProcess sim({"--time-scale", "max", "--dialect", "teacup"});
  const int fd = open_port(sim.port());
  REQUIRE(fd >= 0);
  read_until(fd, "start\nok\n");
  CHECK(write(fd, "M115\n", 5) == 5);
  CHECK(read_until(fd, "ok\n").starts_with("FIRMWARE_NAME:Teacup "));
  CHECK(write(fd, "M190 S60\n", 9) == 9);
  CHECK(read_until(fd, "ok\n") == "E: Bad M-code 190\nok\n");
  close(fd);
  int code = -1;
  sim.stop(code);
  CHECK(code == 0);
  const auto bad = run_mahost({"sim", "--dialect", "klipper"});
  CHECK(bad.exit_code == 2);
  CHECK(bad.err.find("--dialect") != std::string::npos);
}

}  // namespace cmd_sim_test
