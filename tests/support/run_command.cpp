#include "support/run_command.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

extern char** environ;

namespace test_support {

int spawn_tied(const std::vector<char*>& argv, const std::vector<char*>& envp, int stdout_fd,
               const std::string& stderr_path) {
  const pid_t parent = getpid();
  // The child reports why it could not start (an errno) on this pipe; execve closes it, so the
  // parent reads nothing when the program started.
  int report[2];
  if (pipe2(report, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
  // Everything the child does before execve is async-signal-safe (the test process has threads).
  const pid_t pid = fork();
  if (pid < 0) {
    close(report[0]);
    close(report[1]);
    throw std::runtime_error("fork failed");
  }
  if (pid == 0) {
    close(report[0]);
    const auto fail = [&](int error) {
      [[maybe_unused]] const ssize_t n = write(report[1], &error, sizeof error);
      _exit(127);
    };
    if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) fail(errno);
    if (getppid() != parent) fail(ESRCH);
    const int in = open("/dev/null", O_RDONLY | O_CLOEXEC);
    const int err = open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0600);
    if (in < 0 || err < 0 || dup2(in, 0) < 0 || dup2(stdout_fd, 1) < 0 || dup2(err, 2) < 0) {
      fail(errno);
    }
    execve(argv[0], argv.data(), envp.data());
    fail(errno);
  }
  close(report[1]);
  int error = 0;
  ssize_t n;
  do n = read(report[0], &error, sizeof error);
  while (n < 0 && errno == EINTR);
  close(report[0]);
  if (n > 0) {
    waitpid(pid, nullptr, 0);
    throw std::runtime_error(fmt::format("cannot start {}: {}", argv[0], std::strerror(error)));
  }
  return pid;
}

CommandResult run_command(const std::vector<std::string>& argv, const std::string& input,
                          std::chrono::seconds timeout) {
  int in_pipe[2], out_pipe[2], err_pipe[2];
  if (pipe2(in_pipe, O_CLOEXEC) || pipe2(out_pipe, O_CLOEXEC) || pipe2(err_pipe, O_CLOEXEC)) {
    throw std::runtime_error("pipe failed");
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in_pipe[0], 0);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], 2);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(in_pipe[0]);
  close(out_pipe[1]);
  close(err_pipe[1]);
  if (spawned != 0) {
    close(in_pipe[1]);
    close(out_pipe[0]);
    close(err_pipe[0]);
    throw std::runtime_error("cannot run " + argv.at(0));
  }

  CommandResult result;
  std::size_t written = 0;
  if (input.empty()) close(in_pipe[1]);
  fcntl(in_pipe[1], F_SETFL, O_NONBLOCK);
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  bool out_open = true, err_open = true, in_open = !input.empty();
  char buffer[65536];
  while (out_open || err_open) {
    pollfd fds[3];
    int n = 0;
    if (out_open) fds[n++] = {out_pipe[0], POLLIN, 0};
    if (err_open) fds[n++] = {err_pipe[0], POLLIN, 0};
    if (in_open) fds[n++] = {in_pipe[1], POLLOUT, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      kill(pid, SIGKILL);
      result.timed_out = true;
      break;
    }
    if (poll(fds, n, static_cast<int>(left.count())) < 0 && errno != EINTR) break;
    for (int i = 0; i < n; ++i) {
      if (!fds[i].revents) continue;
      if (fds[i].fd == in_pipe[1]) {
        const ssize_t w = write(in_pipe[1], input.data() + written, input.size() - written);
        if (w > 0) written += static_cast<std::size_t>(w);
        if (w < 0 || written == input.size()) {
          close(in_pipe[1]);
          in_open = false;
        }
        continue;
      }
      const ssize_t r = read(fds[i].fd, buffer, sizeof buffer);
      std::string& sink = fds[i].fd == out_pipe[0] ? result.out : result.err;
      if (r > 0) {
        sink.append(buffer, static_cast<std::size_t>(r));
      } else {
        (fds[i].fd == out_pipe[0] ? out_open : err_open) = false;
      }
    }
  }
  if (in_open) close(in_pipe[1]);
  close(out_pipe[0]);
  close(err_pipe[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

CommandResult run_mahost(const std::vector<std::string>& args, const std::string& input,
                         std::chrono::seconds timeout) {
  std::vector<std::string> argv{MAHOST_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command(argv, input, timeout);
}

namespace {

namespace fs = std::filesystem;

// The folder of this checkout's test processes: one a process, named by its id.
fs::path scratch_base() {
  // One folder per checkout (a short hash of its path) and per test process, so two checkouts'
  // test runs at once (a clean-clone check beside the working tree), or two copies of one test
  // binary, never clear each other's files; short, so that the sockets made inside stay within
  // the 108 bytes a socket path may have.
  const std::size_t checkout = std::hash<std::string_view>{}(MAHOST_SOURCE_DIR) % 0xfffff;
  return fs::temp_directory_path() / fmt::format("mahost-test-{}-{:05x}", getuid(), checkout);
}

// A failed test's folder and a dead process's are kept for a day under these names.
constexpr std::string_view kFailedPrefix = "failed-";
constexpr std::string_view kDiedPrefix = "died-";
constexpr auto kKeptFor = std::chrono::hours(24);
// In a process's folder once its main has returned: it did not die.
constexpr std::string_view kEndedMark = ".ended";

bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

// This process's folder, made once. The folders of processes gone are cleared first: one
// whose main returned is removed; one without that mark died (a signal, an abort, a hang
// killed by ctest's timeout) and is kept for a day as died-PID, evidence the process could
// not report itself; failed-PID folders are kept for a day too.
const fs::path& process_scratch() {
  static const fs::path mine = [] {
    const fs::path base = scratch_base();
    std::error_code ignored;
    for (const auto& entry : fs::directory_iterator(base, ignored)) {
      const std::string name = entry.path().filename().string();
      if (starts_with(name, kFailedPrefix) || starts_with(name, kDiedPrefix)) {
        const auto written = fs::last_write_time(entry.path(), ignored);
        if (!ignored && fs::file_time_type::clock::now() - written < kKeptFor) continue;
        fs::remove_all(entry.path(), ignored);
        continue;
      }
      pid_t pid = 0;
      const auto [end, error] = std::from_chars(name.data(), name.data() + name.size(), pid);
      const bool a_process_folder = error == std::errc{} && end == name.data() + name.size();
      if (a_process_folder && !(kill(pid, 0) != 0 && errno == ESRCH)) continue;  // alive
      if (a_process_folder && !fs::exists(entry.path() / kEndedMark, ignored)) {
        std::error_code moved;
        fs::rename(entry.path(), base / fmt::format("{}{}", kDiedPrefix, name), moved);
        if (!moved) continue;
      }
      // Anything else here is no live process's folder and goes too.
      fs::remove_all(entry.path(), ignored);
    }
    return base / std::to_string(getpid());
  }();
  return mine;
}

bool made_scratch = false;
// What a dying process says on stderr, made before it may be needed: a signal handler may
// only write() it.
char died_notice[512] = "";

// The last `lines` lines of a text file.
std::string tail_of(const fs::path& path, std::size_t lines) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::string> last;
  for (std::string line; std::getline(in, line);) {
    last.push_back(std::move(line));
    if (last.size() > lines) last.erase(last.begin());
  }
  std::string out;
  for (const std::string& line : last) out += line + "\n";
  return out;
}

}  // namespace

std::string scratch_dir(const std::string& test_name) {
  const fs::path dir = process_scratch() / test_name;
  if (!made_scratch) {
    made_scratch = true;
    const fs::path died = process_scratch().parent_path() / fmt::format("{}{}", kDiedPrefix, getpid());
    // Said at once, for a process that dies without a word (ctest's timeout kills it): its
    // output up to then is all there is.
    std::fputs(fmt::format("mahost tests: this process's files are in {} (kept as {} if it dies)\n",
                           process_scratch().string(), died.string())
                   .c_str(),
               stderr);
    fmt::format_to_n(died_notice, sizeof died_notice - 1,
                     "mahost tests: the test process died; its files are kept for a day in {}\n", died.string());
  }
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

void mark_scratch_ended() {
  if (!made_scratch) return;
  std::ofstream(process_scratch() / kEndedMark).put('\n');
}

void say_scratch_kept_after_death() {
  if (died_notice[0] == '\0') return;
  const ssize_t ignored = ::write(2, died_notice, std::strlen(died_notice));
  (void)ignored;
}

std::string keep_scratch_after_failure() {
  if (!made_scratch) return {};
  std::error_code error;
  const fs::path& mine = process_scratch();
  std::string said;
  for (const auto& entry : fs::recursive_directory_iterator(mine, error)) {
    if (entry.is_regular_file(error) && entry.path().extension() == ".log") {
      said += fmt::format("---- the end of {} ----\n{}", entry.path().string(), tail_of(entry.path(), 80));
    }
  }
  const fs::path kept = mine.parent_path() / fmt::format("{}{}", kFailedPrefix, mine.filename().string());
  fs::rename(mine, kept, error);
  said += error ? fmt::format("the test's files: {} (removed by the next run)\n", mine.string())
                : fmt::format("the test's files are kept for a day in {}\n", kept.string());
  return said;
}

}  // namespace test_support
