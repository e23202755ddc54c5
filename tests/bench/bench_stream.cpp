// Streaming throughput of the host against `mahost sim --pty --baud B`: lines per second as a
// share of what the link can carry, ping-pong (one line in flight, plain ok) and with a window
// (ADVANCED_OK), and the host's CPU use while streaming. The sim runs as a separate process on
// a pseudo-terminal, pacing bytes like a UART (10 bits a byte), its clock as fast as possible,
// so the link is the only limit. Prints one row per run.
//
//   build-*/bench_stream [lines=3000] [baud window]   (no baud: 115200 and 250000, windows 1 and 4)
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/core.h>

#include "printer/line_protocol.h"
#include "printer/serial_link.h"
#include "bench/bench_main.h"

extern char** environ;

namespace {

struct Sim {
  pid_t pid = -1;
  std::string pty;
};

Sim start_sim(int baud, bool advanced_ok) {
  int out[2];
  if (pipe(out) != 0) std::exit(1);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  std::vector<std::string> argv{MAHOST_BINARY, "sim", "--pty", "--time-scale", "max", "--baud",
                                std::to_string(baud)};
  if (advanced_ok) argv.push_back("--advanced-ok");
  std::vector<char*> raw;
  for (std::string& a : argv) raw.push_back(a.data());
  raw.push_back(nullptr);
  Sim sim;
  if (posix_spawn(&sim.pid, MAHOST_BINARY, &actions, nullptr, raw.data(), environ) != 0) std::exit(1);
  close(out[1]);
  char c;
  while (read(out[0], &c, 1) == 1 && c != '\n') sim.pty += c;
  close(out[0]);
  return sim;
}

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
}

void run(int baud, std::size_t window, int lines) {
  const bool advanced = window > 1;
  const Sim sim = start_sim(baud, advanced);
  {
    printer::SerialLink link(sim.pty, baud);
    printer::ProtocolOptions options;
    options.window = window;
    printer::LineProtocol protocol(link, options);
    protocol.connect();
    const auto bytes_before = protocol.stats().bytes_written;
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = cpu_seconds();
    for (int i = 0; i < lines; ++i) {
      protocol.send(fmt::format("G1 X{:.3f} Y{:.3f} E{:.5f}", 100 + (i % 400) * 0.125,
                                100 + (i % 397) * 0.25, 0.0331 * i));
    }
    protocol.wait_acknowledged();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = cpu_seconds() - cpu0;
    const double bytes_per_line =
        static_cast<double>(protocol.stats().bytes_written - bytes_before) / lines;
    const double limit = baud / 10.0 / bytes_per_line;
    const double rate = lines / wall;
    fmt::print("{:>7} baud  {:<26} {:>6.0f} lines/s of {:>4.0f} the link carries ({:.1f} B/line): "
               "{:5.1f}%   host CPU {:4.1f}% of one core   resends {}\n",
               baud, advanced ? fmt::format("window {} (ADVANCED_OK)", window) : "ping-pong (plain ok)",
               rate, limit, bytes_per_line, 100 * rate / limit, 100 * cpu / wall,
               protocol.stats().resend_requests);
  }
  kill(sim.pid, SIGINT);
  waitpid(sim.pid, nullptr, 0);
}

}  // namespace

static int run_bench(int argc, char** argv) {
  const int lines = argc > 1 ? std::atoi(argv[1]) : 3000;
  fmt::print("streaming {} lines to mahost sim --pty (time scale max, bytes paced at the baud rate)\n", lines);
  if (argc > 3) {
    run(std::atoi(argv[2]), static_cast<std::size_t>(std::atoi(argv[3])), lines);
    return 0;
  }
  for (const int baud : {115200, 250000}) {
    run(baud, 1, lines);
    run(baud, 4, lines);
  }
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
