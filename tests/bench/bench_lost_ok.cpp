// What a lost ok costs, at 115 200 baud.
//
// 1. mahost against the in-process simulated printer, on the sim's clock, in each dialect: a
//    print with 1% of the oks lost (drop-ok=0.01, three seeds) and the same print clean. Per
//    lost ok: how long the firmware then sat idle until the host's next byte (the sim's
//    lost_ok_waits: median, 90th percentile, worst), and the print time lost, (faulty - clean)
//    / lost oks (less than the idle time where the planner's queued moves ran on meanwhile).
// 2. The same kind of print against `mahost sim --pty --baud 115200 --time-scale max` (a
//    separate process, a real serial link, the wall clock while the firmware waits), by
//    `mahost print --port` and by Printrun's printcore, clean and with 1% of the oks lost:
//    completed or not within the time limit, the commands the firmware executed, the idle
//    wait per lost ok (wall seconds, from the sim's record) and the wall time lost per lost
//    ok. printcore waits for an ok without a timeout, so its first lost ok ends its print.
//
// 3. A small part at the simulator's real time (`mahost sim --pty --baud 115200 --time-scale 1`,
//    Marlin) by `mahost print --port`: the bunny 8 mm tall at 0.3 mm (sliced here; its heat-up
//    waits left out, they would only add the same minutes to both), clean and with 2% of the
//    oks lost, alternated, `rounds` of each: the print's wall time (medians, and faulty over
//    clean) and the seconds the planner ran empty in each (the sim's planner_starved: the head
//    stood still mid-print for want of the next move).
//
//   build/tests/bench/bench_lost_ok [layers=60] [limit_s=240] [rounds=3]
// The G-code of 1 and 2 is the ring test program (tests/printer/test_program.h), 120 moves a
// layer.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/core.h>

#include "printer/gcode_file.h"
#include "printer/gcode_line.h"
#include "printer/job.h"
#include "printer/line_protocol.h"
#include "printer/test_program.h"
#include "sim/sim_link.h"
#include "bench/bench_main.h"

extern char** environ;

namespace {

std::string program_for(const std::string& dialect, int layers) {
  std::string g = test_support::ring_program(layers, 120);
  if (dialect == "teacup") g.replace(g.find("M190 S60\nM109 S210\n"), 19, "M116\n");
  return g;
}

struct Run {
  double sim_time = 0;
  std::vector<double> waits;
  long probes = 0;
};

Run print_in_process(const std::string& dialect, const printer::GcodeFile& file, const std::string& faults) {
  sim::Config config;
  config.dialect = *sim::parse_dialect(dialect);
  config.baud = 115200;
  config.faults = sim::parse_fault_spec(faults);
  sim::SimLink link(config);
  printer::LineProtocol protocol(link);
  protocol.connect();
  printer::Job job(protocol, file, {});
  if (job.run().state != printer::JobState::completed) std::exit(1);
  link.printer().run_until(link.printer().now() + 600);  // what a queue still holds runs out
  link.printer().finish();
  Run run;
  run.sim_time = std::max(link.printer().now(), link.printer().motion_end_time());
  run.waits = link.printer().lost_ok_waits();
  run.probes = protocol.stats().probes;
  return run;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

// A process with stdout to a pipe (the sim prints its port first) or to /dev/null.
struct Process {
  pid_t pid = -1;
  int out = -1;
};

Process spawn(std::vector<std::string> argv, bool read_stdout) {
  int fds[2] = {-1, -1};
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (read_stdout) {
    if (pipe(fds) != 0) std::exit(1);
    posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  } else {
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  }
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  std::vector<char*> raw;
  for (std::string& a : argv) raw.push_back(a.data());
  raw.push_back(nullptr);
  Process p;
  if (posix_spawnp(&p.pid, argv[0].c_str(), &actions, nullptr, raw.data(), environ) != 0) return p;
  posix_spawn_file_actions_destroy(&actions);
  if (read_stdout) {
    close(fds[1]);
    p.out = fds[0];
  }
  return p;
}

// Waits up to `limit` for the process; kills it after. Returns its exit code, -1 if killed.
int wait_for(const Process& p, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (waitpid(p.pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(p.pid, SIGKILL);
      waitpid(p.pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The record's text (sim/record.h).
std::string read_record(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// The commands the sim's record says it executed.
long executed_in_record(const std::string& text) {
  const auto counters = text.find("\"counters\":");
  if (counters == std::string::npos) return -1;
  const auto at = text.find("\"commands\":", counters);
  if (at == std::string::npos) return -1;
  return std::atol(text.c_str() + at + 11);
}

// The record's "lost_ok_waits": per lost ok the idle wait that followed, s. Over a pty at
// --time-scale max the sim's clock follows the wall clock while it waits, so these are wall
// seconds. A wait the host never ended (a stall) is not in the list.
std::vector<double> waits_in_record(const std::string& text) {
  std::vector<double> waits;
  const auto at = text.find("\"lost_ok_waits\":[");
  if (at == std::string::npos) return waits;
  const char* p = text.c_str() + at + 17;
  while (*p != ']' && *p != '\0') {
    char* end = nullptr;
    waits.push_back(std::strtod(p, &end));
    if (end == p) break;
    p = end;
    if (*p == ',') ++p;
  }
  return waits;
}

// A number the record gives as "key":value, or -1.
double number_in_record(const std::string& text, const std::string& key) {
  const auto at = text.find("\"" + key + "\":");
  return at == std::string::npos ? -1 : std::strtod(text.c_str() + at + key.size() + 3, nullptr);
}

struct PtyRun {
  int code = -1;
  double wall = 0;
  long executed = 0;
  std::vector<double> waits;
  double starved = 0;  // s the planner ran empty (sim clock)
};

PtyRun over_a_pty(const std::string& host, const std::string& gcode_path, const std::string& faults,
                  std::chrono::seconds limit, const std::string& time_scale = "max") {
  const std::string record = "/tmp/bench_lost_ok_" + host + ".json";
  std::vector<std::string> sim_argv = {MAHOST_BINARY, "sim", "--pty", "--baud", "115200", "--time-scale",
                                       time_scale, "--record", record};
  if (!faults.empty()) {
    sim_argv.push_back("--faults");
    sim_argv.push_back(faults);
  }
  Process sim = spawn(sim_argv, true);
  std::string pty;
  char c;
  while (read(sim.out, &c, 1) == 1 && c != '\n') pty += c;
  const auto start = std::chrono::steady_clock::now();
  Process client = host == "mahost"
                       ? spawn({MAHOST_BINARY, "print", gcode_path, "--port", pty, "--baud", "115200"}, false)
                       : spawn({"printcore", pty, gcode_path}, false);
  PtyRun run;
  if (client.pid < 0) {
    fmt::print("  {:<10} could not be started (is printrun installed? scripts/setup)\n", host);
  } else {
    run.code = wait_for(client, limit);
    run.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  kill(sim.pid, SIGINT);
  waitpid(sim.pid, nullptr, 0);
  const std::string text = read_record(record);
  run.executed = executed_in_record(text);
  run.waits = waits_in_record(text);
  run.starved = number_in_record(text, "planner_starved");
  return run;
}

void report_pty(const std::string& host, const PtyRun& clean, const PtyRun& faulty, std::size_t commands) {
  const auto outcome = [](const PtyRun& r) {
    return r.code == 0 ? std::string("completed") : r.code == -1 ? std::string("STALLED (killed at the limit)")
                                                                 : fmt::format("failed (exit {})", r.code);
  };
  fmt::print("  {:<10} clean: {} in {:.1f} s wall, {} commands executed; 1% oks lost: {} in {:.1f} s wall, "
             "{} commands executed (the file has {}; the host's own come on top)\n",
             host, outcome(clean), clean.wall, clean.executed, outcome(faulty), faulty.wall, faulty.executed,
             commands);
  if (faulty.waits.empty()) {
    fmt::print("  {:<10} no lost ok was ever answered by the host\n", host);
    return;
  }
  fmt::print("  {:<10} {} lost oks recovered: firmware idle per lost ok median {:.2f} s, worst {:.2f} s (wall)",
             host, faulty.waits.size(), quantile(faulty.waits, 0.5),
             *std::max_element(faulty.waits.begin(), faulty.waits.end()));
  if (faulty.code == 0 && clean.code == 0) {
    fmt::print("; wall time lost per lost ok {:.2f} s", (faulty.wall - clean.wall) / static_cast<double>(faulty.waits.size()));
  }
  fmt::print("\n");
}

}  // namespace

static int run_bench(int argc, char** argv) {
  const int layers = argc > 1 ? std::atoi(argv[1]) : 60;
  const auto limit = std::chrono::seconds(argc > 2 ? std::atoi(argv[2]) : 240);
  fmt::print("1. mahost, in-process simulated printer at 115200 baud, sim clock; ring program of "
             "{} layers, 1% of the oks lost (3 seeds)\n", layers);
  for (const std::string dialect : {"marlin", "teacup", "repetier"}) {
    const printer::GcodeFile file = printer::parse_gcode(program_for(dialect, layers), "ring.gcode");
    const Run clean = print_in_process(dialect, file, "");
    std::vector<double> waits;
    double lost_time = 0;
    long probes = 0;
    for (const int seed : {1, 2, 3}) {
      const Run faulty = print_in_process(dialect, file, fmt::format("drop-ok=0.01,seed={}", seed));
      waits.insert(waits.end(), faulty.waits.begin(), faulty.waits.end());
      lost_time += faulty.sim_time - clean.sim_time;
      probes += faulty.probes;
    }
    fmt::print("  {:<9} {} commands: {} oks lost, {} probes; firmware idle per lost ok: median "
               "{:.2f} s, p90 {:.2f} s, worst {:.2f} s; print time lost per lost ok {:.2f} s\n",
               dialect, file.size(), waits.size(), probes, quantile(waits, 0.5), quantile(waits, 0.9),
               waits.empty() ? 0.0 : *std::max_element(waits.begin(), waits.end()),
               waits.empty() ? 0.0 : lost_time / static_cast<double>(waits.size()));
  }

  const std::string gcode_path = "/tmp/bench_lost_ok.gcode";
  std::ofstream(gcode_path) << program_for("marlin", std::max(layers / 3, 5));
  const printer::GcodeFile file = printer::read_gcode_file(gcode_path);
  const std::string faults = "drop-ok=0.01,from-line=5,seed=7";
  fmt::print("2. mahost sim --pty --baud 115200 --time-scale max (wall clock), Marlin, {} commands, clean and "
             "with --faults {}; limit {} s a run\n",
             file.size(), faults, limit.count());
  for (const std::string host : {"mahost", "printcore"}) {
    const PtyRun clean = over_a_pty(host, gcode_path, "", limit);
    const PtyRun faulty = over_a_pty(host, gcode_path, faults, limit);
    report_pty(host, clean, faulty, file.size());
  }

  const int rounds = argc > 3 ? std::atoi(argv[3]) : 3;
  const std::string part = "/tmp/bench_lost_ok_part.gcode";
  const Process slice = spawn({MAHOST_BINARY, "slice", MAHOST_DATA_DIR "/bunny.stl", "--up", "y", "--units", "m",
                               "--height", "8", "--layer", "0.3", "-o", part},
                              false);
  if (wait_for(slice, std::chrono::seconds(300)) != 0) return 1;
  std::string text = read_record(part);
  for (const std::string wait : {"M190 ", "M109 "}) {
    for (auto at = text.find("\n" + wait); at != std::string::npos; at = text.find("\n" + wait, at)) {
      text.erase(at + 1, text.find('\n', at + 1) - at);
    }
  }
  std::ofstream(part) << text;
  const printer::GcodeFile small = printer::read_gcode_file(part);
  const std::string lossy = "drop-ok=0.02,from-line=5";
  fmt::print("3. mahost sim --pty --baud 115200 --time-scale 1 (real time), Marlin: the bunny 8 mm tall at 0.3 mm, "
             "{} commands, {} layers, no heat-up waits; clean and --faults {},seed=<round>, alternated, {} rounds\n",
             small.size(), small.layers.size(), lossy, rounds);
  std::vector<double> clean_wall, lossy_wall, clean_starved, lossy_starved;
  std::size_t lost = 0;
  for (int round = 1; round <= rounds; ++round) {
    const PtyRun clean = over_a_pty("mahost", part, "", limit, "1");
    const PtyRun faulty = over_a_pty("mahost", part, fmt::format("{},seed={}", lossy, round), limit, "1");
    if (clean.code != 0 || faulty.code != 0) {
      fmt::print("  round {}: a print did not complete (exit {} clean, {} with lost oks)\n", round, clean.code,
                 faulty.code);
      return 1;
    }
    fmt::print("  round {}: clean {:.2f} s, planner empty {:.3f} s; 2% lost: {:.2f} s ({} oks lost), planner "
               "empty {:.3f} s; {:.4f}x\n",
               round, clean.wall, clean.starved, faulty.wall, faulty.waits.size(), faulty.starved,
               faulty.wall / clean.wall);
    clean_wall.push_back(clean.wall);
    lossy_wall.push_back(faulty.wall);
    clean_starved.push_back(clean.starved);
    lossy_starved.push_back(faulty.starved);
    lost += faulty.waits.size();
  }
  fmt::print("  medians: clean {:.2f} s (planner empty {:.3f} s), 2% of oks lost {:.2f} s (planner empty {:.3f} s, "
             "{:.1f} oks lost a print): {:.4f}x the clean run's time\n",
             quantile(clean_wall, 0.5), quantile(clean_starved, 0.5), quantile(lossy_wall, 0.5),
             quantile(lossy_starved, 0.5), static_cast<double>(lost) / rounds,
             quantile(lossy_wall, 0.5) / quantile(clean_wall, 0.5));
  return 0;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
