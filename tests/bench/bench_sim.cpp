// bench_sim: how fast the simulated printer runs, and how honest its baud pacing is.
//
// 1. Commands per second processed as fast as possible (goal >= 200 000/s): a ping-pong host
//    in-process streams numbered, checksummed lines of a real-looking print (extruding moves
//    with feedrates, some travel, G92 and fan lines) straight into sim::Printer, waiting for
//    each ok; the sim clock runs the moves through the motion model meanwhile.
// 2. Bytes per second on `mahost sim --pty --baud 115200` (must be <= 11 520, the UART's
//    limit at 10 bits a byte): into the sim (a block of M117 lines) and out of it (M115).
//
// 3. With --gcode FILE: the file streamed as a host would (comments off, numbered lines, one
//    ok at a time) through the in-process sim: wall time, the sim's print time beside the
//    file's own estimate (;PRINT_TIME_S), layers and filament from the deposition record, and
//    the time and size of the record (JSON) and printed part (STL) written under /tmp.
//
//    --printer NAME takes the motion limits from that profile, as the slicer's estimate did.
//
// Usage: bench_sim [commands (default 500000)] [--no-pty] [--gcode FILE [--printer NAME]]
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "geometry/mesh/mesh.h"
#include "printer/gcode_line.h"
#include "printer/profile.h"
#include "sim/printed_part.h"
#include "sim/printer.h"
#include "sim/record.h"
#include "bench/bench_main.h"

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::vector<std::string> print_lines(std::size_t count) {
  std::vector<std::string> lines;
  lines.reserve(count);
  double e = 0;
  for (std::size_t i = 0; i < count; ++i) {
    std::string command;
    if (i % 1000 == 0) {
      command = fmt::format("G1 Z{:.2f} F600", 0.2 + 0.2 * static_cast<double>(i / 1000));
    } else if (i % 97 == 0) {
      command = "G92 E0";
      e = 0;
    } else if (i % 53 == 0) {
      command = fmt::format("G0 X{} Y{} F9000", 50 + (i * 7) % 100, 50 + (i * 11) % 100);
    } else if (i % 5000 == 1) {
      command = "M106 S255";
    } else {
      e += 0.05;
      command = fmt::format("G1 X{:.3f} Y{:.3f} E{:.5f} F{}", 50 + 0.3 * static_cast<double>(i % 300),
                            50 + 0.2 * static_cast<double>((i / 300) % 300), e, 1800 + 600 * (i % 3));
    }
    lines.push_back(printer::frame_line(static_cast<long>(i + 1), command) + "\n");
  }
  return lines;
}

void bench_in_process(std::size_t count) {
  const std::vector<std::string> lines = print_lines(count);
  std::size_t bytes = 0;
  for (const auto& l : lines) bytes += l.size();
  sim::Printer printer;
  printer.run_until(1e-3);
  printer.take_output();
  const auto start = Clock::now();
  std::size_t oks = 0;
  for (const std::string& line : lines) {
    printer.receive(line);
    while (printer.run_until_output(1e12)) {
      const std::string said = printer.take_output();
      if (said.find("ok") != std::string::npos) {
        ++oks;
        break;
      }
    }
  }
  printer.finish();
  const double wall = since(start);
  fmt::print("in-process: {} commands ({} bytes) in {:.3f} s wall = {:.0f} commands/s "
             "(goal >= 200000), {} ok, {} executed, sim clock {:.1f} s, motion {:.1f} s\n",
             count, bytes, wall, static_cast<double>(count) / wall, oks,
             printer.counters().commands, printer.motion_end_time(), printer.motion_time());
}

// Reads what is there within `seconds`, appending to `got`.
void drain(int fd, std::string& got, double seconds) {
  const auto until = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < until) {
    pollfd p{fd, POLLIN, 0};
    if (poll(&p, 1, 20) <= 0) continue;
    char buffer[8192];
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n > 0) got.append(buffer, static_cast<std::size_t>(n));
  }
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = 0; (at = text.find(what, at)) != std::string::npos; at += what.size()) ++n;
  return n;
}

void bench_pty(double baud) {
  int out[2];
  if (pipe(out) != 0) return;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  const std::string baud_text = fmt::format("{:.0f}", baud);
  std::vector<std::string> args{MAHOST_BINARY, "sim", "--pty", "--baud", baud_text, "--time-scale", "max"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, MAHOST_BINARY, &actions, nullptr, argv.data(), environ) != 0) {
    fmt::print("pty: cannot run {}\n", MAHOST_BINARY);
    return;
  }
  close(out[1]);
  std::string path;
  char c;
  while (read(out[0], &c, 1) == 1 && c != '\n') path += c;
  const int fd = open(path.c_str(), O_RDWR | O_NOCTTY);
  termios raw{};
  tcgetattr(fd, &raw);
  cfmakeraw(&raw);
  tcsetattr(fd, TCSANOW, &raw);
  std::string got;
  drain(fd, got, 0.3);  // the start banner

  // Into the sim: 2 s worth of M117 lines at the UART's rate, written at once; M117 runs at
  // once, so the firmware keeps up and nothing overflows.
  const std::string line = "M117 " + std::string(58, 'x') + "\n";  // 64 bytes
  std::string block;
  while (block.size() < static_cast<std::size_t>(baud / 10 * 2)) block += line;
  const std::size_t lines = block.size() / line.size();
  got.clear();
  auto start = Clock::now();
  std::size_t written = 0;
  double last_ok = 0;
  while (count_of(got, "ok\n") < lines && since(start) < 30) {
    if (written < block.size()) {
      const ssize_t n = write(fd, block.data() + written, block.size() - written);
      if (n > 0) written += static_cast<std::size_t>(n);
    }
    const std::size_t before = count_of(got, "ok\n");
    drain(fd, got, 0.005);
    if (count_of(got, "ok\n") > before) last_ok = since(start);
  }
  const double in_rate = static_cast<double>(block.size()) / last_ok;
  fmt::print("pty --baud {:.0f}: into the sim {} bytes ({} lines) in {:.3f} s = {:.0f} bytes/s "
             "(limit {:.0f}), {} ok\n",
             baud, block.size(), lines, last_ok, in_rate, baud / 10, count_of(got, "ok\n"));

  // Out of the sim: M115 answers about 1 KB each.
  got.clear();
  const int asks = 20;
  std::string m115;
  for (int i = 0; i < asks; ++i) m115 += "M115\n";
  start = Clock::now();
  if (write(fd, m115.data(), m115.size()) != static_cast<ssize_t>(m115.size())) return;
  double last = 0;
  while (count_of(got, "ok\n") < static_cast<std::size_t>(asks) && since(start) < 30) {
    const std::size_t before = got.size();
    drain(fd, got, 0.005);
    if (got.size() > before) last = since(start);
  }
  fmt::print("pty --baud {:.0f}: out of the sim {} bytes in {:.3f} s = {:.0f} bytes/s (limit {:.0f})\n",
             baud, got.size(), last, static_cast<double>(got.size()) / last, baud / 10);
  close(fd);
  kill(pid, SIGINT);
  std::string summary;
  while (read(out[0], &c, 1) == 1) summary += c;
  waitpid(pid, nullptr, 0);
}

// The value of a ";KEY:value" header comment, or 0.
double header(const std::string& gcode, const std::string& key) {
  const auto at = gcode.find(";" + key + ":");
  return at == std::string::npos ? 0 : std::atof(gcode.c_str() + at + key.size() + 2);
}

void bench_gcode(const std::string& path, const std::string& profile) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string gcode = text.str();
  std::vector<std::string> lines;
  std::istringstream stream(gcode);
  for (std::string line; std::getline(stream, line);) {
    line = line.substr(0, line.find(';'));
    line.erase(0, line.find_first_not_of(" \t"));
    line.erase(line.find_last_not_of(" \t\r") + 1);
    if (!line.empty()) lines.push_back(printer::frame_line(static_cast<long>(lines.size() + 1), line) + "\n");
  }
  sim::Config config;
  if (!profile.empty()) {
    const auto p = printer::load_printer_profile(profile, MAHOST_DATA_DIR "/../configs");
    config.motion = p.motion;
    config.filament_diameter = p.filament_diameter;
  }
  sim::Printer printer(config);
  printer.run_until(1);
  printer.take_output();
  const auto start = Clock::now();
  for (const std::string& line : lines) {
    printer.receive(line);
    while (printer.run_until_output(1e12)) {
      if (printer.take_output().find("ok") != std::string::npos) break;
    }
  }
  printer.finish();
  const double wall = since(start);
  const auto& record = printer.deposition();
  fmt::print("{}: {} commands in {:.3f} s wall ({:.0f}/s); sim clock {:.1f} s, motion {:.1f} s, "
             "file's estimate {:.1f} s; {} layers, {} extruding moves, filament {:.1f} mm "
             "(file {:.1f} mm); {} unknown commands\n",
             path, lines.size(), wall, static_cast<double>(lines.size()) / wall,
             printer.motion_end_time(), printer.motion_time(), header(gcode, "PRINT_TIME_S"),
             record.layer_z.size(), record.moves.size(), record.filament_used(),
             header(gcode, "FILAMENT_MM"), printer.counters().unknown_commands);
  auto t = Clock::now();
  sim::write_record_json(printer, "/tmp/bench_sim_record.json");
  fmt::print("record: {:.2f} s, {:.1f} MB\n", since(t),
             static_cast<double>(std::filesystem::file_size("/tmp/bench_sim_record.json")) / 1e6);
  t = Clock::now();
  const geometry::Mesh part = sim::printed_part(record, printer.config().filament_diameter);
  const double mesh_time = since(t);
  sim::write_printed_stl(printer, "/tmp/bench_sim_part.stl");
  fmt::print("printed part: {} triangles, {:.1f} mm^3, built in {:.2f} s, STL {:.1f} MB\n",
             part.faces.size(), geometry::signed_volume(part), mesh_time,
             static_cast<double>(std::filesystem::file_size("/tmp/bench_sim_part.stl")) / 1e6);
}

}  // namespace

static int run_bench(int argc, char** argv) {
  std::size_t count = 500000;
  bool pty = true;
  std::string gcode, profile;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--no-pty") == 0) {
      pty = false;
    } else if (std::strcmp(argv[i], "--gcode") == 0 && i + 1 < argc) {
      gcode = argv[++i];
    } else if (std::strcmp(argv[i], "--printer") == 0 && i + 1 < argc) {
      profile = argv[++i];
    } else {
      count = std::stoul(argv[i]);
    }
  }
  if (!gcode.empty()) {
    bench_gcode(gcode, profile);
    return 0;
  }
  bench_in_process(count);
  if (pty) bench_pty(115200);
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
