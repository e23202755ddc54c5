// mahost serve under load: requests per second and latency of GET /api/job while a dry-run
// print runs, the server's memory and CPU, and what the load does to the print (its wall time
// at full simulated speed, and whether the printer got exactly the file's commands).
//
//   build/tests/bench/bench_serve [GCODE=/tmp/base/bunny_ma20.gcode] [clients=20] [time_scale=500]
//                                 [keep_alive=1]  (0: a new connection per request)
//
// Runs `mahost serve --dry-run` three times on a free loopback port with the file:
//   1. full speed (--time-scale max), no clients: the print's wall time alone;
//   2. full speed, `clients` clients at 10 Hz each (as the page and the slicers poll), then
//      asking back to back: the print's wall time under that load, the requests answered;
//   3. --time-scale `time_scale` (a print of seconds, the sim mostly sleeping as a printer's
//      host does), without clients and with them at 10 Hz: the latency they see and the CPU
//      the server spends on them.
// Each run's simulated printer record is compared with the file's commands (M105/M110/M113/
// M115/M155, the host's own, left out: M113 S1 asks Marlin for its busy keepalive). Memory: VmHWM (peak RSS) and VmRSS of the server at the end.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fmt/core.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "printer/gcode_file.h"
#include "bench/bench_main.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;
constexpr const char* kKey = "bench-serve-key-0123456789abcdef";
bool keep_alive = true;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Server {
  pid_t pid = -1;
  int port = 0;
  std::string dir, record;
};

Server start_server(const std::string& dir, const std::string& time_scale) {
  Server s;
  s.dir = dir;
  s.record = dir + "/record.json";
  fs::remove_all(dir);
  fs::create_directories(dir + "/run");
  fs::permissions(dir + "/run", fs::perms::owner_all);
  int out[2];
  if (pipe(out) != 0) std::exit(1);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  const std::string log = dir + "/serve.log";
  posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT, 0600);
  std::vector<std::string> argv{MAHOST_BINARY, "serve", "--dry-run", "--time-scale", time_scale, "--listen",
                                "127.0.0.1:0", "--files", dir + "/files", "--record", s.record};
  std::vector<std::string> env{"MAHOST_API_KEY=" + std::string(kKey), "XDG_RUNTIME_DIR=" + dir + "/run", "HOME=" + dir};
  std::vector<char*> a, e;
  for (auto& x : argv) a.push_back(x.data());
  a.push_back(nullptr);
  for (auto& x : env) e.push_back(x.data());
  e.push_back(nullptr);
  if (posix_spawn(&s.pid, MAHOST_BINARY, &actions, nullptr, a.data(), e.data()) != 0) std::exit(1);
  close(out[1]);
  std::string line;
  char c;
  while (read(out[0], &c, 1) == 1 && c != '\n') line += c;
  close(out[0]);
  const auto colon = line.find("127.0.0.1:");
  if (colon == std::string::npos) {
    fmt::print(stderr, "bench_serve: serve did not start: {}\n{}", line, read_text(log));
    std::exit(1);
  }
  s.port = std::stoi(line.substr(colon + 10));
  return s;
}

long proc_kib(pid_t pid, const std::string& key) {
  std::ifstream in(fmt::format("/proc/{}/status", pid));
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + ":", 0) == 0) return std::stol(line.substr(key.size() + 1));
  }
  return -1;
}

double proc_cpu_seconds(pid_t pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream fields(text.substr(text.rfind(')') + 2));
  std::string f;
  std::vector<std::string> v;
  while (fields >> f) v.push_back(f);
  return (std::stod(v[11]) + std::stod(v[12])) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

int stop_server(Server& s) {
  kill(s.pid, SIGTERM);
  int status = 0;
  waitpid(s.pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

httplib::Client client(int port) {
  httplib::Client c("127.0.0.1", port);
  c.set_default_headers({{"X-Api-Key", kKey}});
  c.set_read_timeout(30, 0);
  c.set_keep_alive(keep_alive);  // as browsers, Qt (Cura) and curl (PrusaSlicer) do
  return c;
}

std::string job_state(int port) {
  auto c = client(port);
  auto r = c.Get("/api/job");
  if (!r || r->status != 200) return "?";
  return json::parse(r->body)["mahost"]["jobState"];
}

// Uploads with print=true and returns the seconds the upload took.
double upload(int port, const std::string& gcode_text) {
  auto c = client(port);
  const auto start = Clock::now();
  auto r = c.Post("/api/files/local", httplib::MultipartFormDataItems{
                                          {"file", gcode_text, "part.gcode", "application/octet-stream"},
                                          {"print", "true", "", ""}});
  if (!r || r->status != 201) {
    fmt::print(stderr, "bench_serve: upload failed: {}\n", r ? r->body : "no answer");
    std::exit(1);
  }
  return std::chrono::duration<double>(Clock::now() - start).count();
}

struct Load {
  std::atomic<bool> stop{false};
  std::atomic<long> requests{0}, failures{0};
  std::vector<std::vector<double>> latencies;  // per client, ms
  std::vector<std::thread> threads;

  Load(int port, int clients, double hz) : latencies(static_cast<std::size_t>(clients)) {
    for (int i = 0; i < clients; ++i) {
      threads.emplace_back([this, port, hz, i] {
        auto c = client(port);
        auto next = Clock::now();
        while (!stop.load()) {
          const auto start = Clock::now();
          auto r = c.Get("/api/job");
          const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
          if (r && r->status == 200) {
            ++requests;
            latencies[static_cast<std::size_t>(i)].push_back(ms);
          } else {
            ++failures;
          }
          if (hz > 0) {
            next += std::chrono::microseconds(static_cast<long>(1e6 / hz));
            std::this_thread::sleep_until(next);
          }
        }
      });
    }
  }
  void finish() {
    stop.store(true);
    for (auto& t : threads) t.join();
  }
  std::vector<double> all() const {
    std::vector<double> v;
    for (const auto& l : latencies) v.insert(v.end(), l.begin(), l.end());
    std::sort(v.begin(), v.end());
    return v;
  }
};

double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0;
  return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(p * static_cast<double>(sorted.size())))];
}

std::vector<std::string> printed(const json& record) {
  std::vector<std::string> out;
  for (const json& c : record["commands"]) {
    const std::string s = c;
    if (s.rfind("M105", 0) == 0 || s.rfind("M110", 0) == 0 || s.rfind("M113", 0) == 0 || s.rfind("M115", 0) == 0 ||
        s.rfind("M155", 0) == 0) {
      continue;
    }
    out.push_back(s);
  }
  return out;
}

std::vector<std::string> commands_of(const std::string& text) {
  const printer::GcodeFile file = printer::parse_gcode(text, "bench");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < file.size(); ++i) out.emplace_back(file.command(i));
  return out;
}

struct RunResult {
  double print_wall = 0, upload = 0, cpu = 0;
  long rss_kib = 0, hwm_kib = 0;
  bool exact = false;
};

// One print of `text`, `clients` clients at `hz` (0: back to back) for its whole length.
RunResult run(const std::string& dir, const std::string& text, const std::string& time_scale, int clients, double hz,
              Load** load_out = nullptr) {
  Server s = start_server(dir, time_scale);
  RunResult r;
  const double cpu_before = proc_cpu_seconds(s.pid);
  r.upload = upload(s.port, text);
  const auto start = Clock::now();
  Load* load = clients > 0 ? new Load(s.port, clients, hz) : nullptr;
  while (job_state(s.port) != "completed") std::this_thread::sleep_for(std::chrono::milliseconds(20));
  r.print_wall = std::chrono::duration<double>(Clock::now() - start).count();
  if (load) load->finish();
  r.cpu = proc_cpu_seconds(s.pid) - cpu_before;
  r.rss_kib = proc_kib(s.pid, "VmRSS");
  r.hwm_kib = proc_kib(s.pid, "VmHWM");
  if (stop_server(s) != 0) fmt::print(stderr, "bench_serve: serve exited badly ({})\n", s.dir);
  r.exact = printed(json::parse(read_text(s.record))) == commands_of(text);
  if (load_out) *load_out = load; else delete load;
  return r;
}

}  // namespace

static int run_bench(int argc, char** argv) {
  const std::string gcode = argc > 1 ? argv[1] : "/tmp/base/bunny_ma20.gcode";
  const int clients = argc > 2 ? std::atoi(argv[2]) : 20;
  const std::string time_scale = argc > 3 ? argv[3] : "500";
  keep_alive = argc > 4 ? std::atoi(argv[4]) != 0 : true;
  const std::string text = read_text(gcode);
  if (text.empty()) {
    fmt::print(stderr, "bench_serve: cannot read {} (give a G-code file, e.g. one mahost slice wrote)\n", gcode);
    return 2;
  }
  const std::string dir = (fs::temp_directory_path() / fmt::format("mahost-bench-serve-{}", getuid())).string();
  fmt::print("file: {} ({:.1f} MiB, {} commands); {} clients{}; {} cores\n", gcode, text.size() / 1048576.0,
             commands_of(text).size(), clients, keep_alive ? "" : ", a connection per request",
             std::thread::hardware_concurrency());

  const RunResult alone = run(dir + "/alone", text, "max", 0, 0);
  fmt::print("full speed, no clients:      print {:6.2f} s wall, upload {:.3f} s ({:.0f} MiB/s), server CPU {:.2f} s, "
             "peak RSS {:.1f} MiB, commands exact: {}\n",
             alone.print_wall, alone.upload, text.size() / 1048576.0 / alone.upload, alone.cpu, alone.hwm_kib / 1024.0,
             alone.exact ? "yes" : "NO");

  Load* steady = nullptr;
  const RunResult polled_fast = run(dir + "/steady", text, "max", clients, 10, &steady);
  fmt::print("full speed, {} at 10 Hz:     print {:6.2f} s wall ({:.2f}x), {:.0f} req/s, {} failed, server CPU {:.2f} s, "
             "commands exact: {}\n",
             clients, polled_fast.print_wall, polled_fast.print_wall / alone.print_wall,
             static_cast<double>(steady->requests.load()) / polled_fast.print_wall, steady->failures.load(),
             polled_fast.cpu, polled_fast.exact ? "yes" : "NO");
  delete steady;

  Load* hammer = nullptr;
  const RunResult loaded = run(dir + "/loaded", text, "max", clients, 0, &hammer);
  const auto hammered = hammer->all();
  fmt::print("full speed, {} back to back: print {:6.2f} s wall ({:.2f}x), {:.0f} req/s, p50 {:.2f} ms, p99 {:.2f} ms, "
             "{} failed, server CPU {:.2f} s, peak RSS {:.1f} MiB, commands exact: {}\n",
             clients, loaded.print_wall, loaded.print_wall / alone.print_wall,
             static_cast<double>(hammer->requests.load()) / loaded.print_wall, percentile(hammered, 0.5),
             percentile(hammered, 0.99), hammer->failures.load(), loaded.cpu, loaded.hwm_kib / 1024.0,
             loaded.exact ? "yes" : "NO");
  delete hammer;

  const RunResult quiet = run(dir + "/quiet", text, time_scale, 0, 0);
  fmt::print("x{} clock, no clients:       print {:6.2f} s wall, server CPU {:.2f} s ({:.0f}% of a core), "
             "RSS {:.1f} MiB (peak {:.1f}), commands exact: {}\n",
             time_scale, quiet.print_wall, quiet.cpu, 100 * quiet.cpu / quiet.print_wall, quiet.rss_kib / 1024.0,
             quiet.hwm_kib / 1024.0, quiet.exact ? "yes" : "NO");
  Load* paced = nullptr;
  const RunResult polled = run(dir + "/paced", text, time_scale, clients, 10, &paced);
  const auto latencies = paced->all();
  fmt::print("x{} clock, {} at 10 Hz:       print {:6.2f} s wall, {:.0f} req/s, p50 {:.2f} ms, p95 {:.2f} ms, p99 {:.2f} ms, "
             "max {:.2f} ms, {} failed, server CPU {:.2f} s ({:.0f}% of a core), RSS {:.1f} MiB (peak {:.1f}), "
             "commands exact: {}\n",
             time_scale, clients, polled.print_wall, static_cast<double>(paced->requests.load()) / polled.print_wall,
             percentile(latencies, 0.5), percentile(latencies, 0.95), percentile(latencies, 0.99),
             latencies.empty() ? 0.0 : latencies.back(), paced->failures.load(), polled.cpu,
             100 * polled.cpu / polled.print_wall, polled.rss_kib / 1024.0, polled.hwm_kib / 1024.0,
             polled.exact ? "yes" : "NO");
  delete paced;
  fs::remove_all(dir);
  return alone.exact && polled_fast.exact && loaded.exact && quiet.exact && polled.exact ? 0 : 1;
}

int main(int argc, char** argv) { return bench::main(argc, argv, run_bench); }
