// `mahost print`, `resume`, `ctl`, `ports` as a user runs them: against the in-process
// simulated printer (--dry-run) and against `mahost sim --pty`, a separate process on a
// pseudo-terminal, including a host killed with SIGKILL mid-print.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <thread>

#include <doctest/doctest.h>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "geometry/mesh/stl_io.h"
#include "printer/gcode_file.h"
#include "printer/journal.h"
#include "printer/test_program.h"
#include "sim/sim_link.h"
#include "printer/line_protocol.h"
#include "printer/job.h"
#include "printer/gcode_line.h"
#include "support/build_kind.h"
#include "support/run_command.h"
#include "support/solids.h"

extern char** environ;

namespace print_cli_test {

using test_support::run_mahost;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

// A process running in the background, its stdout read line by line.
class Background {
 public:
  explicit Background(const std::vector<std::string>& args) {
    int out[2];
    REQUIRE(pipe2(out, O_CLOEXEC) == 0);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, out[1], 1);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
    std::vector<std::string> argv{MAHOST_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> raw;
    for (std::string& a : argv) raw.push_back(a.data());
    raw.push_back(nullptr);
    REQUIRE(posix_spawn(&pid_, MAHOST_BINARY, &actions, nullptr, raw.data(), environ) == 0);
    posix_spawn_file_actions_destroy(&actions);
    close(out[1]);
    out_ = out[0];
  }
  ~Background() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) close(out_);
  }
  // The first stdout line, waiting up to `timeout`.
  std::string first_line(std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (buffer_.find('\n') == std::string::npos && std::chrono::steady_clock::now() < deadline) {
      pollfd p{out_, POLLIN, 0};
      if (poll(&p, 1, 100) > 0) {
        char chunk[256];
        const ssize_t n = read(out_, chunk, sizeof chunk);
        if (n <= 0) break;
        buffer_.append(chunk, static_cast<std::size_t>(n));
      }
    }
    return buffer_.substr(0, buffer_.find('\n'));
  }
  // Waits up to `timeout` for a stdout line holding `text` after those already waited for;
  // whether one came.
  bool wait_for_line(const std::string& text, std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      const auto at = buffer_.find(text, seen_);
      if (at != std::string::npos) {
        seen_ = at + text.size();
        return true;
      }
      pollfd p{out_, POLLIN, 0};
      if (poll(&p, 1, 100) <= 0) continue;
      char chunk[256];
      const ssize_t n = read(out_, chunk, sizeof chunk);
      if (n <= 0) return false;
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
    return false;
  }
  // All of stdout once the process closes it, waiting up to `timeout`.
  std::string all_output(std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{out_, POLLIN, 0};
      if (poll(&p, 1, 100) <= 0) continue;
      char chunk[4096];
      const ssize_t n = read(out_, chunk, sizeof chunk);
      if (n <= 0) break;
      buffer_.append(chunk, static_cast<std::size_t>(n));
    }
    return buffer_;
  }
  void signal(int sig) { kill(pid_, sig); }
  // Exit code (128 + signal when killed); waits up to `timeout`, then kills.
  int wait(std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    int status = 0;
    while (waitpid(pid_, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > deadline) {
        kill(pid_, SIGKILL);
        waitpid(pid_, &status, 0);
        break;
      }
      std::this_thread::sleep_for(20ms);
    }
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::string buffer_;
  std::size_t seen_ = 0;  // of buffer_, what wait_for_line has passed
};

std::string write_file(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

bool wait_for(const std::function<bool()>& condition, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

std::optional<printer::JournalRecord> journal_of(const std::string& path) {
  try {
    return printer::read_journal(path);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

int count_lines(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

// Each test keeps its jobs in its own runtime directory, so `mahost ctl` finds only them.
std::string use_runtime_dir(const std::string& dir) {
  const std::string runtime = dir + "/run";
  fs::create_directories(runtime);
  fs::permissions(runtime, fs::perms::owner_all);
  setenv("XDG_RUNTIME_DIR", runtime.c_str(), 1);
  return runtime;
}

}  // namespace

TEST_CASE("dry_run_prints_a_gcode_file_and_says_what_the_print_would_do") {
  const std::string dir = test_support::scratch_dir("print_dry_run");
  const std::string runtime = use_runtime_dir(dir);
  const std::string gcode = write_file(dir, "ring.gcode", test_support::ring_program(20, 50));
  const auto r = run_mahost({"print", gcode, "--dry-run"});
  CHECK(r.exit_code == 0);
  // 9 start commands, per layer G92, Z, travel, prime, 50 moves, retract; 7 end commands.
  const int commands = 9 + 20 * (50 + 5) + 7;
  CHECK(r.out.starts_with(fmt::format(
      "completed: dry run on the simulated printer, {} of {} commands, 20 layers\nprint time ",
      commands, commands)));
  CHECK(r.out.find(" on the simulated printer's clock: ") != std::string::npos);
  CHECK(r.out.find(" (estimated ") != std::string::npos);
  CHECK(r.out.find("; filament ") != std::string::npos);
  // Every command once, the host's M115 query at connection, its M113 S1 asking for a busy
  // keepalive each second and its M155 S2 asking the firmware (which reports AUTOREPORT_TEMP)
  // for temperatures every 2 s.
  CHECK(r.out.find(fmt::format("\nlink: {} lines sent, 0 resent after 0 resend requests", commands + 3)) !=
        std::string::npos);
  CHECK(r.out.find("simulated faults") == std::string::npos);
  // A dry run leaves nothing behind: no journal, no socket.
  CHECK(fs::is_empty(runtime + "/mahost"));
  CHECK(r.err.find("(a dry run's: removed when it ends; --keep keeps it)") != std::string::npos);
}

TEST_CASE("dry_run_with_faults_still_completes") {
  const std::string dir = test_support::scratch_dir("print_dry_run_faults");
  use_runtime_dir(dir);
  const std::string gcode = write_file(dir, "ring.gcode", test_support::ring_program(20, 50));
  const auto r = run_mahost({"print", gcode, "--dry-run", "--faults",
                             "corrupt=0.01,drop-ok=0.01,resend=0.01,seed=3"});
  CHECK(r.exit_code == 0);
  CHECK(r.out.starts_with("completed:"));
  CHECK(r.out.find("0 resent after 0 resend") == std::string::npos);
}

TEST_CASE("a_bad_fault_spec_is_refused_before_the_model_is_sliced") {
  const std::string dir = test_support::scratch_dir("print_bad_faults");
  use_runtime_dir(dir);
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(8).mesh);
  for (const std::string spec : {"corrupt=2", "bogus=1", "corrupt"}) {
    CAPTURE(spec);
    const auto r = run_mahost({"print", stl, "--dry-run", "--faults", spec});
    CHECK(r.exit_code == 2);
    CHECK(r.out.find("sliced") == std::string::npos);  // nothing done before the refusal
    CHECK(r.err.starts_with("mahost: --faults: fault spec"));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
}

TEST_CASE("bad_print_invocations_give_one_line_and_a_code") {
  const std::string dir = test_support::scratch_dir("print_bad");
  use_runtime_dir(dir);
  const std::string gcode = write_file(dir, "ring.gcode", test_support::ring_program(3, 10));
  const std::string binary = write_file(dir, "noise.gcode", std::string("G1 X1\n\0\x01\x02", 9));

  auto r = run_mahost({"print", gcode});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "mahost: print: give either --port PORT or --dry-run\n");

  r = run_mahost({"print", gcode, "--port", "/dev/ttyUSB97"});
  CHECK(r.exit_code == 3);
  CHECK(r.err.starts_with("mahost: /dev/ttyUSB97: no such serial port"));
  CHECK(count_lines(r.err) == 1);

  r = run_mahost({"print", binary, "--dry-run"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("noise.gcode: line 2 contains NUL bytes") != std::string::npos);
  CHECK(count_lines(r.err) == 1);

  r = run_mahost({"print", gcode, "--dry-run", "--pause-at-layer", "9"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("--pause-at-layer 9: ") != std::string::npos);
  CHECK(r.err.find("has 3 layers") != std::string::npos);
  for (const std::string not_whole : {"2.5", "two"}) {
    r = run_mahost({"print", gcode, "--dry-run", "--pause-at-layer", not_whole});
    CHECK(r.exit_code == 2);
    const std::string kind = not_whole == "two" ? "a number" : "a whole number";
    CHECK(r.err == "mahost: --pause-at-layer: '" + not_whole + "' is not " + kind +
                       " (see mahost --help)\n");
  }

  r = run_mahost({"resume", dir + "/missing.journal", "--dry-run"});
  CHECK(r.exit_code == 2);
  CHECK(count_lines(r.err) == 1);

  r = run_mahost({"resume", gcode, "--dry-run"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.find("is not a mahost job journal") != std::string::npos);

  // No job to steer is a usage matter: exit 2 and what to do.
  r = run_mahost({"ctl", "pause"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.starts_with("mahost: no running mahost job in "));
  CHECK(r.err.find(": start one with mahost print, or give --job JOURNAL") != std::string::npos);
  CHECK(count_lines(r.err) == 1);
  r = run_mahost({"ctl", "status", "--job", dir + "/nothing.journal"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.starts_with("mahost: --job " + dir + "/nothing.journal: no such mahost job"));
  CHECK(count_lines(r.err) == 1);

  r = run_mahost({"ctl", "dance"});
  CHECK(r.exit_code == 2);
}

TEST_CASE("files_that_are_not_gcode_are_refused_before_anything_is_sent") {
  const std::string dir = test_support::scratch_dir("print_garbage");
  use_runtime_dir(dir);
  std::string high;
  for (int line = 0; line < 50; ++line) {
    for (int b = 0x80; b <= 0xff; ++b) high += static_cast<char>(b);
    high += '\n';
  }
  const std::string noise = write_file(dir, "high.gcode", high);
  const std::string hello = write_file(dir, "hello.gcode", "hello world\n");
  for (const std::string& file : {noise, hello}) {
    const auto r = run_mahost({"print", file, "--dry-run"});
    CHECK(r.exit_code == 2);
    CHECK(r.err.starts_with("mahost: " + file + ": line 1 is not G-code ("));
    CHECK(count_lines(r.err) == 1);
    CHECK(r.out.empty());  // refused before the job began
  }
  // A valid file with one bad line: refused by that line's number, or left out with --force.
  std::string program = test_support::ring_program(3, 10);
  const std::size_t at = program.find(";LAYER:1\n");
  const int bad_line = static_cast<int>(std::count(program.begin(), program.begin() + at, '\n')) + 1;
  program.insert(at, "G1 X10 Y=5\n");
  const std::string one_bad = write_file(dir, "one_bad.gcode", program);
  auto r = run_mahost({"print", one_bad, "--dry-run"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.starts_with(fmt::format("mahost: {}: line {} is not G-code (it has a parameter whose value "
                                      "is not a number: \"G1 X10 Y=5\")",
                                      one_bad, bad_line)));
  r = run_mahost({"print", one_bad, "--dry-run", "--force"});
  CHECK(r.exit_code == 0);
  CHECK(r.err.find(fmt::format("note: --force: left out 1 line that is not G-code (line {})", bad_line)) !=
        std::string::npos);
  CHECK(r.out.starts_with("completed: "));
}

TEST_CASE("baud_takes_the_standard_rates_and_says_which") {
  const std::string dir = test_support::scratch_dir("print_baud");
  const std::string gcode = write_file(dir, "ring.gcode", test_support::ring_program(3, 10));
  for (const char* rate : {"0", "-5", "12345", "fast"}) {
    CAPTURE(rate);
    const auto r = run_mahost({"print", gcode, "--port", "/dev/ttyUSB97", "--baud", rate});
    CHECK(r.exit_code == 2);
    CHECK(r.err.find(fmt::format("{} is not a serial speed; give one of 9600, 19200, 38400, 57600, "
                                 "115200, 230400, 250000, 460800, 500000, 921600, 1000000",
                                 rate)) != std::string::npos);
    CHECK(count_lines(r.err) == 1);
  }
}

TEST_CASE("dialect_is_for_a_dry_run_only") {
  const std::string dir = test_support::scratch_dir("print_dialect");
  const std::string gcode = write_file(dir, "ring.gcode", test_support::ring_program(3, 10));
  const auto r = run_mahost({"print", gcode, "--port", "/dev/null", "--dialect", "teacup"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.starts_with("mahost: --dialect: only a --dry-run printer"));
}

TEST_CASE("halt_fault_exits_3_with_the_reason_and_the_resume_command") {
  const std::string dir = test_support::scratch_dir("print_halt");
  use_runtime_dir(dir);
  const std::string gcode = write_file(dir, "ring.gcode", test_support::ring_program(20, 50));
  const std::string journal = dir + "/job.journal";
  const auto r = run_mahost({"print", gcode, "--dry-run", "--journal", journal, "--faults", "halt-at-line=700"});
  CHECK(r.exit_code == 3);
  CHECK(r.err.find("mahost: simulated printer: the printer stopped: Error:Printer halted. kill() called!") !=
        std::string::npos);
  CHECK(r.err.find("; to finish the part: mahost resume " + journal + " --dry-run\n") != std::string::npos);
  // A failed job still says what the link went through.
  CHECK(r.out.starts_with("failed: dry run on the simulated printer, "));
  CHECK(r.out.find("\nlink: ") != std::string::npos);
  CHECK(r.out.find("\nfirmware: Marlin ") != std::string::npos);
  const auto record = journal_of(journal);
  REQUIRE(record);
  CHECK(record->state == printer::JobState::failed);
  CHECK(fs::exists(dir + "/job.journal"));  // a journal the user named stays

  // Rehearsing the resume on the simulated printer finishes the part there and leaves the
  // journal as it was, for the real resume.
  std::ifstream before_in(journal);
  const std::string before((std::istreambuf_iterator<char>(before_in)), std::istreambuf_iterator<char>());
  const auto rehearsal = run_mahost({"resume", journal, "--dry-run"});
  CHECK(rehearsal.exit_code == 0);
  CHECK(rehearsal.out.starts_with("completed: dry run on the simulated printer, "));
  CHECK(rehearsal.err.find("is left as it was, for the real resume") != std::string::npos);
  std::ifstream after_in(journal);
  const std::string after((std::istreambuf_iterator<char>(after_in)), std::istreambuf_iterator<char>());
  CHECK(after == before);
}

TEST_CASE("ctl_pauses_and_resumes_a_print_without_a_terminal") {
  const std::string dir = test_support::scratch_dir("print_ctl");
  const std::string runtime = use_runtime_dir(dir);
  Background sim({"sim", "--pty", "--time-scale", "20"});
  const std::string pty = sim.first_line(10s);
  REQUIRE(pty.starts_with("/dev/pts/"));
  const std::string gcode = write_file(dir, "ring.gcode", test_support::ring_program(30, 60));
  fs::create_directories(runtime + "/mahost");
  const std::string journal = runtime + "/mahost/ring.journal";
  Background print({"print", gcode, "--port", pty, "--journal", journal});
  REQUIRE(wait_for([&] { return journal_of(journal) && journal_of(journal)->layer_index >= 3; }, 60s));

  struct stat info{};
  REQUIRE(stat((runtime + "/mahost/ring.sock").c_str(), &info) == 0);
  CHECK((info.st_mode & 0777) == 0600);

  auto r = run_mahost({"ctl", "pause"});  // found without --job: the one running job
  CHECK(r.exit_code == 0);
  CHECK(r.out.starts_with("pausing before layer "));
  REQUIRE(wait_for([&] { return journal_of(journal) && journal_of(journal)->state == printer::JobState::paused; }, 60s));
  r = run_mahost({"ctl", "status", "--job", journal});
  CHECK(r.exit_code == 0);
  CHECK(r.out.starts_with("paused  layer "));
  r = run_mahost({"ctl", "pause", "--job", "ring"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "mahost: ring: the job is paused, not printing\n");
  r = run_mahost({"ctl", "resume"});
  CHECK(r.exit_code == 0);
  CHECK(print.wait(120s) == 0);
  CHECK(journal_of(journal)->state == printer::JobState::completed);
  CHECK_FALSE(fs::exists(runtime + "/mahost/ring.sock"));

  // The job has ended: ctl says what its journal says; it is not "running".
  r = run_mahost({"ctl", "status", "--job", journal});
  CHECK(r.exit_code == 0);
  CHECK(r.out.starts_with("completed, 30 layers (journal updated "));
  r = run_mahost({"ctl", "pause", "--job", "ring"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.starts_with("mahost: ring: the job is not running: completed, 30 layers"));
  r = run_mahost({"ctl", "status"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.starts_with("mahost: no running mahost job in "));
}

TEST_CASE("a_completed_print_removes_its_own_journal") {
  const std::string dir = test_support::scratch_dir("print_completed_cleanup");
  const std::string runtime = use_runtime_dir(dir);
  Background sim({"sim", "--pty", "--time-scale", "200"});
  const std::string pty = sim.first_line(10s);
  REQUIRE(pty.starts_with("/dev/pts/"));
  const std::string gcode = write_file(dir, "ring.gcode", test_support::ring_program(4, 20));
  const auto r = run_mahost({"print", gcode, "--port", pty}, {}, 120s);
  CHECK(r.exit_code == 0);
  CHECK(r.out.starts_with("completed: on " + pty + ", "));
  CHECK(r.err.find("journal: " + runtime + "/mahost/ring-") != std::string::npos);
  CHECK(r.err.find("(if the print is interrupted: mahost resume ") != std::string::npos);
  CHECK(fs::is_empty(runtime + "/mahost"));  // journal and socket gone: nothing to resume
  CHECK(fs::exists(gcode));                  // the user's file stays
}

TEST_CASE("print_slices_an_stl_in_process_as_slice_does_and_a_dry_run_leaves_nothing") {
  const std::string dir = test_support::scratch_dir("print_stl");
  const std::string runtime = use_runtime_dir(dir);
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(8).mesh);
  const std::vector<std::string> options{"--contour", "mid", "--layer", "0.3", "--set",
                                         "print.skirt_loops=2", "--units", "mm"};
  std::vector<std::string> slice{"slice", stl, "-o", dir + "/sliced.gcode"};
  slice.insert(slice.end(), options.begin(), options.end());
  const auto sliced = run_mahost(slice);
  REQUIRE(sliced.exit_code == 0);
  const std::string summary = sliced.out.substr(sliced.out.find(": ") + 2);  // "27 layers, ..."

  std::vector<std::string> print{"print", stl, "--dry-run", "-o", dir + "/printed.gcode"};
  print.insert(print.end(), options.begin(), options.end());
  auto r = run_mahost(print);
  CHECK(r.exit_code == 0);
  CHECK(r.out.starts_with("sliced " + stl + " to " + dir + "/printed.gcode: " + summary));
  CHECK(r.out.find("\ncompleted: dry run on the simulated printer, ") != std::string::npos);
  CHECK(r.out.find(" g ABS)\n") != std::string::npos);  // the material's weight of what was fed
  const auto bytes = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  CHECK(bytes(dir + "/printed.gcode") == bytes(dir + "/sliced.gcode"));  // the same pipeline
  CHECK(fs::is_empty(runtime + "/mahost"));

  // Without -o the sliced G-code lives in the job directory and goes with the dry run.
  r = run_mahost({"print", stl, "--dry-run", "--contour", "mid"});
  CHECK(r.exit_code == 0);
  CHECK(r.out.starts_with("sliced " + stl + ": "));
  CHECK(fs::is_empty(runtime + "/mahost"));

  // --keep keeps the journal (completed) and the G-code it names.
  r = run_mahost({"print", stl, "--dry-run", "--contour", "mid", "--keep"});
  CHECK(r.exit_code == 0);
  std::vector<std::string> kept;
  for (const auto& entry : fs::directory_iterator(runtime + "/mahost")) kept.push_back(entry.path().string());
  std::sort(kept.begin(), kept.end());
  REQUIRE(kept.size() == 2);
  CHECK(kept[0].ends_with(".gcode"));
  CHECK(kept[1].ends_with(".journal"));
  const auto record = journal_of(kept[1]);
  REQUIRE(record);
  CHECK(record->state == printer::JobState::completed);
  CHECK(record->gcode_path == kept[0]);
  // The shipped profile, through the build tree's share/mahost.
  CHECK(std::filesystem::equivalent(record->printer, MAHOST_SOURCE_DIR "/configs/printers/up-plus-2.toml"));
}

TEST_CASE("slice_options_are_refused_for_a_gcode_file") {
  const std::string dir = test_support::scratch_dir("print_gcode_slice_options");
  use_runtime_dir(dir);
  const std::string gcode = write_file(dir, "ring.gcode", test_support::ring_program(3, 10));
  auto r = run_mahost({"print", gcode, "--dry-run", "--layer", "0.3"});
  CHECK(r.exit_code == 2);
  CHECK(r.err == "mahost: --layer: " + gcode + " is G-code, already sliced; slice options other "
                 "than --printer and --set apply to a model (STL, 3MF, OBJ)\n");
  r = run_mahost({"print", gcode, "--dry-run", "-o", dir + "/x.gcode"});
  CHECK(r.exit_code == 2);
  CHECK(count_lines(r.err) == 1);
  // --printer names the machine the file is timed for and the dry run simulates.
  r = run_mahost({"print", gcode, "--dry-run", "--printer", "generic-marlin"});
  CHECK(r.exit_code == 0);
}

TEST_CASE("a_gcode_file_prints_on_the_firmware_its_profile_is_set_to") {
  // A ring that waits for its heaters as Teacup does (M116), printed as a user who owns a
  // Teacup printer would: --set firmware=teacup. The dry run speaks Teacup, as the profile says.
  const std::string dir = test_support::scratch_dir("print_set_firmware");
  use_runtime_dir(dir);
  std::string program = test_support::ring_program(3, 10);
  program.replace(program.find("M190 S60\nM109 S210\n"), 19, "M116\n");
  program.replace(program.find("M107\n"), 5, "M106 S0\n");
  const std::string gcode = write_file(dir, "ring.gcode", program);
  auto r = run_mahost({"print", gcode, "--dry-run", "--set", "firmware=teacup"});
  CHECK(r.exit_code == 0);
  CHECK(r.out.starts_with("completed: dry run on the simulated printer, "));
  CHECK(r.out.find("\nfirmware: Teacup (teacup dialect)\n") != std::string::npos);
  // On a Marlin printer the same file is refused at its M116, with what to set.
  r = run_mahost({"print", gcode, "--dry-run"});
  CHECK(r.exit_code == 3);
  CHECK(r.err.find("the printer refused M116") != std::string::npos);
  CHECK(r.err.find("set firmware = \"marlin\"") != std::string::npos);
}

TEST_CASE("killed_host_resumes_and_reprints_only_the_interrupted_layer") {
  const std::string dir = test_support::scratch_dir("print_kill_resume");
  use_runtime_dir(dir);
  const std::string record_path = dir + "/record.json";
  const int layers = 40, segments = 100;
  const std::string program = test_support::ring_program(layers, segments);
  const std::string gcode = write_file(dir, "ring.gcode", program);
  const std::string journal = dir + "/ring.journal";

  Background sim({"sim", "--pty", "--time-scale", "40", "--record", record_path});
  const std::string pty = sim.first_line(10s);
  REQUIRE(pty.starts_with("/dev/pts/"));
  {
    Background print({"print", gcode, "--port", pty, "--journal", journal});
    REQUIRE(wait_for([&] { return journal_of(journal) && journal_of(journal)->layer_index >= 12; }, 120s));
    std::this_thread::sleep_for(100ms);  // into the layer (a layer takes about 7 s of sim time, 0.2 s here)
    print.signal(SIGKILL);
    CHECK(print.wait(10s) == 128 + SIGKILL);
  }
  // The sim has seen the host go (else a resume quick enough to open the port before it
  // looks would find the board not reset, as a board without DTR reset would be).
  REQUIRE(sim.wait_for_line("host opened the port: the board resets", 10s));
  REQUIRE(sim.wait_for_line("host closed the port", 10s));
  const auto interrupted = journal_of(journal);
  REQUIRE(interrupted);
  CHECK(interrupted->state == printer::JobState::printing);
  // The resuming host is held 300 ms between opening the port and emptying its input (a host
  // descheduled there): the board, reset by the open, says `start` within its boot time (1 s
  // on the sim clock, 25 ms at --time-scale 40), and the flush throws it away. Whether the
  // board reset is read from the printer's own M114, so the outcome does not depend on the race.
  setenv("MAHOST_DELAY_AFTER_OPEN_MS", "300", 1);
  const auto r = run_mahost({"resume", journal, "--port", pty}, {}, 300s);
  unsetenv("MAHOST_DELAY_AFTER_OPEN_MS");
  CHECK(r.exit_code == 0);
  CAPTURE(r.err);
  // The board reset on open and reports Z 0: Z comes from the journal.
  CHECK(r.err.find(fmt::format("setting Z from the journal (the printer reports Z 0.00, the journal {:.2f})",
                               interrupted->state_at_resume.z)) != std::string::npos);
  CHECK(journal_of(journal)->state == printer::JobState::completed);
  sim.signal(SIGINT);
  CHECK(sim.wait(30s) == 0);

  // The reference: the same file printed without interruption.
  const printer::GcodeFile file = printer::parse_gcode(program, "ring.gcode");
  sim::SimLink link{sim::Config{}};
  printer::LineProtocol protocol(link);
  protocol.connect();
  printer::Job job(protocol, file, {});
  REQUIRE(job.run().state == printer::JobState::completed);
  const auto& reference = link.printer().deposition().moves;

  std::ifstream in(record_path);
  const nlohmann::json record = nlohmann::json::parse(in);
  const auto& moves = record.at("moves");
  auto same = [&](std::size_t printed, std::size_t ref) {
    const auto& m = moves.at(printed);
    const auto& n = reference.at(ref);
    return m.at("z").get<double>() == n.z && m.at("x0").get<double>() == n.start.x &&
           m.at("y0").get<double>() == n.start.y && m.at("x1").get<double>() == n.end.x &&
           m.at("y1").get<double>() == n.end.y && std::abs(m.at("e").get<double>() - n.e) < 1e-9;
  };
  // Printed = reference[0, k) then reference[s, end): s the start of the interrupted layer,
  // s <= k <= s + one layer. So the part is complete, that layer's printed part came twice,
  // and nothing else. k reaches s + one layer where the kill fell after the layer's last move
  // and before the host journaled the next layer (it does so as it sends the next layer's
  // first command): the journal's layer is then wholly printed, and printed again.
  const std::size_t per_layer = segments;
  const std::size_t s = static_cast<std::size_t>(interrupted->layer_index) * per_layer;
  REQUIRE(moves.size() >= reference.size());
  const std::size_t k = moves.size() - (reference.size() - s);
  CHECK(k >= s);
  CHECK(k <= s + per_layer);
  bool all_same = true;
  for (std::size_t i = 0; i < k; ++i) all_same = all_same && same(i, i);
  for (std::size_t i = k; i < moves.size(); ++i) all_same = all_same && same(i, s + (i - k));
  CHECK(all_same);
  MESSAGE("interrupted at layer " << interrupted->layer_index + 1 << ", " << k - s
                                  << " moves of it printed twice");
}

TEST_CASE("a_missing_port_is_reported_before_slicing") {
  const std::string dir = test_support::scratch_dir("print_missing_port");
  const std::string runtime = use_runtime_dir(dir);
  const std::string stl = dir + "/cube.stl";
  geometry::write_stl_binary(stl, solids::cube(8).mesh);
  const auto r = run_mahost({"print", stl, "--units", "mm", "--port", "/dev/ttyUSB97", "-o",
                             dir + "/cube.gcode"});
  CHECK(r.exit_code == 3);
  CHECK(r.err == "mahost: /dev/ttyUSB97: no such serial port: is the printer plugged in? "
                 "`mahost ports` lists the ports found\n");
  // Nothing was sliced: no summary, no G-code, no job files.
  CHECK(r.out.find("sliced") == std::string::npos);
  CHECK_FALSE(fs::exists(dir + "/cube.gcode"));
  CHECK((!fs::exists(runtime + "/mahost") || fs::is_empty(runtime + "/mahost")));
  // A file that is not a device is refused the same way.
  const auto not_a_port = run_mahost({"print", stl, "--units", "mm", "--port", stl});
  CHECK(not_a_port.exit_code == 3);
  CHECK(not_a_port.err == "mahost: " + stl + ": is not a serial port or terminal: `mahost ports` "
                          "lists the ports found\n");
}

TEST_CASE("dry_runs_paused_show_targets_count_a_cancelled_pause_and_ctl_asks_which_job") {
  // Two dry runs of a ring printed at 250/105 °C on its first layer and 245/100 °C after,
  // both paused before layer 4, waiting (a dry run waits in real time while paused).
  const std::string dir = test_support::scratch_dir("print_dry_run_paused");
  const std::string runtime = use_runtime_dir(dir);
  std::string program = test_support::ring_program(8, 40);
  const std::string heat = "M140 S60\nM104 S210\nM190 S60\nM109 S210\n";
  program.replace(program.find(heat), heat.size(), "M140 S105\nM104 S250\nM190 S105\nM109 S250\n");
  program.replace(program.find(";LAYER:1\n"), 9, ";LAYER:1\nM104 S245\nM140 S100\n");
  const std::string gcode = write_file(dir, "ring.gcode", program);
  fs::create_directories(runtime + "/mahost");
  const std::string a = runtime + "/mahost/a.journal", b = runtime + "/mahost/b.journal";
  Background first({"print", gcode, "--dry-run", "--journal", a, "--pause-at-layer", "4"});
  Background second({"print", gcode, "--dry-run", "--journal", b, "--pause-at-layer", "4"});
  for (const std::string& journal : {a, b}) {
    REQUIRE(wait_for([&] { return journal_of(journal) && journal_of(journal)->state == printer::JobState::paused; }, 60s));
  }

  // Two jobs: ctl asks which, listing them.
  auto r = run_mahost({"ctl", "status"});
  CHECK(r.exit_code == 2);
  CHECK(r.err.starts_with("mahost: 2 jobs are running; choose one with --job PATH: "));
  CHECK(r.err.find(a) != std::string::npos);  // oldest first: the two started together
  CHECK(r.err.find(b) != std::string::npos);
  CHECK(count_lines(r.err) == 1);

  // The targets the file set last, not the first layer's; and the simulated clock has not
  // raced through the pause (at full speed it would make hours of each second).
  r = run_mahost({"ctl", "status", "--job", a});
  CHECK(r.exit_code == 0);
  CHECK(r.out.starts_with("paused  layer 4/8  "));
  CHECK(r.out.find("/245 °C  bed ") != std::string::npos);
  CHECK(r.out.find("/100 °C") != std::string::npos);
  CHECK(r.out.find("hotend 250.0/") == std::string::npos);  // a report made while paused
  CHECK(r.out.find("elapsed 0:0") != std::string::npos);  // under 10 minutes
  MESSAGE(r.out);

  // Cancelled while paused: the pause counts.
  r = run_mahost({"ctl", "cancel", "--job", a});
  CHECK(r.exit_code == 0);
  const std::string out = first.all_output(60s);
  CHECK(first.wait(60s) == 4);
  CHECK(out.starts_with("cancelled: dry run on the simulated printer, "));
  CHECK(out.find(" on the simulated printer's clock (") != std::string::npos);
  CHECK(out.find(" paused, not counted): ") != std::string::npos);
  CHECK(out.find("; 1 pause\n") != std::string::npos);
  MESSAGE(out);

  // Resumed: one pause, and the print time leaves it out.
  r = run_mahost({"ctl", "resume", "--job", b});
  CHECK(r.exit_code == 0);
  const std::string resumed = second.all_output(60s);
  CHECK(second.wait(60s) == 0);
  CHECK(resumed.starts_with("completed: dry run on the simulated printer, "));
  CHECK(resumed.find("; 1 pause\n") != std::string::npos);
}

TEST_CASE("ports_lists_or_says_none") {
  const auto r = run_mahost({"ports"});
  CHECK(r.exit_code == 0);
  CHECK(!r.out.empty());
}

namespace {

std::vector<std::string> job_part(const std::vector<std::string>& executed) {
  std::vector<std::string> out;
  for (const std::string& c : executed) {
    const printer::GcodeCommand parsed = printer::parse_gcode_line(c);
    if (parsed.is('M', 110) || parsed.is('M', 115) || parsed.is('M', 105) || parsed.is('M', 155) ||
        parsed.is('M', 113)) {
      continue;
    }
    out.push_back(c);
  }
  return out;
}

struct SimPrint {
  std::vector<std::string> executed;
  std::vector<sim::DepositedMove> moves;
  printer::ProtocolStats stats;
};

SimPrint print_on_sim(const printer::GcodeFile& file, const sim::Config& config, std::size_t window = 1) {
  sim::SimLink link(config);
  printer::ProtocolOptions options;
  options.window = window;
  printer::LineProtocol protocol(link, options);
  protocol.connect();
  printer::Job job(protocol, file, {});
  REQUIRE(job.run().state == printer::JobState::completed);
  return {link.printer().executed_commands(), link.printer().deposition().moves, protocol.stats()};
}

bool same_moves(const std::vector<sim::DepositedMove>& a, const std::vector<sim::DepositedMove>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].z != b[i].z || !(a[i].start == b[i].start) || !(a[i].end == b[i].end) ||
        a[i].e != b[i].e || a[i].feedrate != b[i].feedrate) {
      return false;
    }
  }
  return true;
}

}  // namespace

TEST_CASE("bunny_print_through_a_noisy_link_executes_the_gcode_exactly") {
  const std::string dir = test_support::scratch_dir("bunny_noisy");
  const std::string gcode = dir + "/bunny.gcode";
  const auto sliced = run_mahost({"slice", std::string(MAHOST_DATA_DIR) + "/bunny.stl", "--up", "y",
                                  "--units", "m", "--height", "50", "-o", gcode});
  REQUIRE(sliced.exit_code == 0);
  const printer::GcodeFile file = printer::read_gcode_file(gcode);
  REQUIRE(file.layers.size() > 200);
  std::vector<std::string> commands;
  printer::GcodeReader reader(file);
  for (std::size_t i = 0; i < file.size(); ++i) commands.emplace_back(reader.command(i));

  const SimPrint clean = print_on_sim(file, sim::Config{});
  CHECK(job_part(clean.executed) == commands);

  // 1% of the bytes corrupted, 1% of the oks lost, 1% of good lines answered with Resend;
  // with Marlin 1.1's ok after Resend and Marlin 2.0's without.
  for (const bool ok_after_resend : {true, false}) {
    CAPTURE(ok_after_resend);
    sim::Config noisy;
    noisy.ok_after_resend = ok_after_resend;
    noisy.faults = sim::parse_fault_spec("corrupt=0.01,drop-ok=0.01,resend=0.01,seed=2024");
    const SimPrint faulty = print_on_sim(file, noisy);
    CHECK(job_part(faulty.executed) == commands);  // no loss, no duplicate, same order
    CHECK(same_moves(faulty.moves, clean.moves));  // the same part
    CHECK(faulty.stats.resend_requests > 1000);
    CHECK(faulty.stats.probes > 500);
    MESSAGE("resend requests " << faulty.stats.resend_requests << ", lines resent "
                               << faulty.stats.lines_resent << ", M105 probes " << faulty.stats.probes);
  }
  // The same with a window of 4 lines on a firmware reporting ADVANCED_OK.
  sim::Config noisy;
  noisy.advanced_ok = true;
  noisy.faults = sim::parse_fault_spec("corrupt=0.01,drop-ok=0.01,resend=0.01,dup-ok=0.005,seed=99");
  const SimPrint windowed = print_on_sim(file, noisy, 4);
  CHECK(job_part(windowed.executed) == commands);
  CHECK(same_moves(windowed.moves, clean.moves));
}

TEST_CASE("bunny_prints_exactly_once_in_every_dialect_through_lost_oks_and_corrupted_lines" *
          test_support::release_build_only()) {
  // Each firmware as its source has it (printer/firmware_dialect.h), and the builds its source
  // offers that answer differently: Marlin 2.0.9 without the ok after a resend request, Teacup
  // with REQUIRE_LINENUMBER, Repetier without ACK_WITH_LINENUMBER.
  struct Build {
    std::string dialect, name;
    std::function<void(sim::Config&)> set;
  };
  const std::vector<Build> builds{
      {"marlin", "marlin", [](sim::Config&) {}},
      {"marlin", "marlin 2.0.9", [](sim::Config& c) { c.ok_after_resend = false; }},
      {"teacup", "teacup", [](sim::Config&) {}},
      {"teacup", "teacup REQUIRE_LINENUMBER", [](sim::Config& c) { c.teacup_require_linenumber = true; }},
      {"repetier", "repetier", [](sim::Config&) {}},
      {"repetier", "repetier, plain ok", [](sim::Config& c) { c.repetier_ack_with_linenumber = false; }},
  };
  const std::string dir = test_support::scratch_dir("bunny_dialects");
  std::map<std::string, printer::GcodeFile> sliced;
  std::uint64_t seed = 40;
  for (const Build& build : builds) {
    CAPTURE(build.name);
    if (!sliced.contains(build.dialect)) {
      // The bunny at 0.3 mm, sliced for this firmware (Teacup: M116, M106 S0).
      const std::string gcode = dir + "/bunny_" + build.dialect + ".gcode";
      const auto slice = run_mahost({"slice", std::string(MAHOST_DATA_DIR) + "/bunny.stl", "--up", "y",
                                     "--units", "m", "--height", "50", "--layer", "0.3", "--set",
                                     "firmware=" + build.dialect, "-o", gcode});
      REQUIRE(slice.exit_code == 0);
      sliced.emplace(build.dialect, printer::read_gcode_file(gcode));
    }
    const printer::GcodeFile& file = sliced.at(build.dialect);
    std::vector<std::string> commands;
    printer::GcodeReader reader(file);
    for (std::size_t i = 0; i < file.size(); ++i) commands.emplace_back(reader.command(i));

    // At 115 200 baud: about 1% of lines with a digit changed (one byte in 0.03% of the
    // bytes), 1% of the oks lost, and the oks of the first three commands that block.
    sim::Config config;
    config.dialect = *sim::parse_dialect(build.dialect);
    build.set(config);
    config.baud = 115200;
    config.faults = sim::parse_fault_spec(
        fmt::format("corrupt=0.0003,drop-ok=0.01,drop-blocking-ok=3,seed={}", seed++));
    sim::SimLink link(config);
    printer::ProtocolOptions options;
    options.baud = 115200;
    printer::LineProtocol protocol(link, options);
    protocol.connect();
    printer::Job job(protocol, file, {});
    REQUIRE(job.run().state == printer::JobState::completed);
    sim::Printer& sim = link.printer();
    // Repetier acknowledges a line when it queues it: the last few still run after the job
    // has handed everything over.
    sim.run_until(sim.now() + 600);
    CHECK(job_part(sim.executed_commands()) == commands);  // each exactly once, in order
    // Sliced for the firmware, nothing in it is refused.
    CHECK(protocol.refused().empty());

    const std::vector<double>& waits = sim.lost_ok_waits();
    const double lines = static_cast<double>(sim.counters().lines);
    const double corrupted = static_cast<double>(sim.counters().faults_injected - waits.size()) / lines;
    CHECK(corrupted > 0.005);
    CHECK(corrupted < 0.02);
    CHECK(waits.size() > static_cast<std::size_t>(0.005 * lines));
    // A lost ok is found before the printer runs out of moves: the head stood waiting for
    // the next move under 5 ms a lost ok (a probe after a fixed silence left it 1 s and more).
    CHECK(sim.planner_starved() < 0.005 * static_cast<double>(waits.size()));
    // One probe a lost ok, hardly more: the ok's time is known, not guessed.
    CHECK(protocol.stats().probes < 1.1 * static_cast<double>(waits.size()) + 10);
    MESSAGE(build.name << ": " << file.size() << " commands, " << 100 * corrupted << "% of lines corrupted, "
                       << waits.size() << " oks lost, " << protocol.stats().probes << " probes, "
                       << protocol.stats().resend_requests << " resend requests; the planner ran empty "
                       << sim.planner_starved() << " s in all");
  }
}

TEST_CASE("pause_at_layer_on_a_variable_stack_stops_at_that_layers_height") {
  // A 20 x 20 x 2 mm block on layers of 0.3, 0.15, 0.4, 0.25, 0.15, 0.4, 0.35 mm: paused
  // before layer 4 (;LAYER:3), the nozzle is at layer 3's top, 0.85 mm.
  const std::string dir = test_support::scratch_dir("print_variable_pause");
  const std::string runtime = use_runtime_dir(dir);
  const std::string stl = dir + "/block.stl";
  geometry::write_stl_binary(stl, solids::box({0, 0, 0}, {20, 20, 2}).mesh);
  fs::create_directories(runtime + "/mahost");
  const std::string journal = runtime + "/mahost/block.journal";
  Background job({"print", stl, "--dry-run", "--no-raft", "--journal", journal, "--boundaries",
                  "0.3,0.45,0.85,1.1,1.25,1.65,2", "--pause-at-layer", "4"});
  REQUIRE(wait_for([&] { return journal_of(journal) && journal_of(journal)->state == printer::JobState::paused; }, 60s));
  auto r = run_mahost({"ctl", "status", "--job", journal});
  CHECK(r.out.starts_with("paused  layer 4/7  "));
  // The journal holds where the print stands: layer index 3, the nozzle at layer 3's top.
  const auto record = journal_of(journal);
  REQUIRE(record);
  CHECK(record->layer_index == 3);
  CHECK(record->state_at_resume.z == doctest::Approx(0.85));
  r = run_mahost({"ctl", "resume", "--job", journal});
  CHECK(r.exit_code == 0);
  const std::string out = job.all_output(60s);
  CHECK(job.wait(60s) == 0);
  CAPTURE(out);
  CHECK(out.find("; 1 pause\n") != std::string::npos);
  CHECK(out.find("completed: dry run on the simulated printer, ") != std::string::npos);
  CHECK(out.find(", 7 layers\n") != std::string::npos);
}

}  // namespace print_cli_test
