#include "host/control_socket.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fmt/core.h>

#include "base/text.h"
#include "host/print_ui.h"
#include "printer/error.h"
#include "printer/journal.h"

namespace host {

namespace {

using base::trim;

sockaddr_un address_of(const std::string& path) {
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (path.size() >= sizeof address.sun_path) {
    throw printer::ConfigError(fmt::format(
        "{}: the path is too long for a control socket ({} characters at most); use a shorter "
        "--journal path",
        path, sizeof address.sun_path - 1));
  }
  std::memcpy(address.sun_path, path.c_str(), path.size() + 1);
  return address;
}

}  // namespace

std::string answer_request(printer::Job& job, const std::string& raw) {
  const std::string request(trim(raw));
  const printer::JobProgress before = job.progress();
  if (request == "status") return "ok " + progress_text(before);
  if (request == "pause") {
    if (before.state != printer::JobState::printing) {
      return fmt::format("error: the job is {}, not printing", printer::to_string(before.state));
    }
    job.request(printer::JobRequest::pause);
    return fmt::format("ok pausing before layer {}", before.layer + 1);
  }
  if (request == "resume") {
    if (before.state == printer::JobState::printing && before.pause_before_layer > 0) {
      job.request(printer::JobRequest::resume);
      return "ok pause called off";
    }
    if (before.state != printer::JobState::paused && before.state != printer::JobState::pausing) {
      return fmt::format("error: the job is {}, not paused", printer::to_string(before.state));
    }
    job.request(printer::JobRequest::resume);
    return "ok resuming";
  }
  if (request == "cancel") {
    job.request(printer::JobRequest::cancel);
    return "ok cancelling";
  }
  if (request == "stop") {
    job.request(printer::JobRequest::stop);
    return "ok emergency stop";
  }
  return fmt::format("error: unknown request '{}': use pause, resume, cancel, stop or status", request);
}

ControlSocket::ControlSocket(std::string path) : path_(std::move(path)) {
  const sockaddr_un address = address_of(path_);
  fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd_ < 0) {
    throw printer::ConfigError(fmt::format("{}: cannot create the control socket: {}", path_,
                                           std::strerror(errno)));
  }
  ::unlink(path_.c_str());  // a socket left by a job that died
  // The socket must never exist with a looser mode, not even between bind and chmod.
  const mode_t old_mask = ::umask(0177);
  const int bound = ::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address);
  const int bind_errno = errno;
  ::umask(old_mask);
  if (bound != 0 || ::listen(fd_, 8) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw printer::ConfigError(fmt::format("{}: cannot listen for mahost ctl: {}", path_,
                                           std::strerror(bound != 0 ? bind_errno : errno)));
  }
  ::chmod(path_.c_str(), 0600);
}

ControlSocket::~ControlSocket() {
  if (fd_ >= 0) {
    ::close(fd_);
    ::unlink(path_.c_str());
  }
}

void ControlSocket::serve(printer::Job& job) {
  while (true) {
    const int client = ::accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (client < 0) return;  // EAGAIN: nobody waiting
    // Only the user who started the job may steer it (the mode already says so; a socket
    // created by root in a shared /tmp would not).
    ucred peer{};
    socklen_t size = sizeof peer;
    if (::getsockopt(client, SOL_SOCKET, SO_PEERCRED, &peer, &size) == 0 && peer.uid != ::getuid()) {
      ::close(client);
      continue;
    }
    std::string request;
    char buffer[256];
    pollfd p{client, POLLIN, 0};
    while (request.find('\n') == std::string::npos && request.size() < 256 &&
           ::poll(&p, 1, 200) > 0) {
      const ssize_t n = ::read(client, buffer, sizeof buffer);
      if (n <= 0) break;
      request.append(buffer, static_cast<std::size_t>(n));
    }
    const std::string reply = answer_request(job, request.substr(0, request.find('\n'))) + "\n";
    [[maybe_unused]] const ssize_t written = ::send(client, reply.data(), reply.size(), MSG_NOSIGNAL);
    ::close(client);
  }
}

std::string send_control(const std::string& socket_path, const std::string& request,
                         std::chrono::milliseconds timeout) {
  const sockaddr_un address = address_of(socket_path);
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) throw printer::LinkError(fmt::format("{}: cannot create a socket", socket_path));
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
    const int error = errno;
    ::close(fd);
    throw printer::LinkError(fmt::format("{}: no job answers there ({}); is the print still running?",
                                         socket_path, std::strerror(error)));
  }
  const std::string line = request + "\n";
  [[maybe_unused]] const ssize_t sent = ::send(fd, line.data(), line.size(), MSG_NOSIGNAL);
  std::string reply;
  char buffer[512];
  pollfd p{fd, POLLIN, 0};
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (reply.find('\n') == std::string::npos) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0 || ::poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n <= 0) break;
    reply.append(buffer, static_cast<std::size_t>(n));
  }
  ::close(fd);
  if (reply.find('\n') == std::string::npos) {
    throw printer::LinkError(fmt::format("{}: the job did not answer within {} s", socket_path,
                                         timeout.count() / 1000.0));
  }
  return std::string(trim(reply.substr(0, reply.find('\n'))));
}

std::vector<std::string> running_jobs() {
  namespace fs = std::filesystem;
  std::vector<std::pair<fs::file_time_type, std::string>> found;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(printer::job_directory(), error)) {
    if (entry.path().extension() != ".sock" || !entry.is_socket(error)) continue;
    try {
      send_control(entry.path().string(), "status", std::chrono::milliseconds(1000));
      found.emplace_back(entry.last_write_time(error), entry.path().string());
    } catch (const printer::LinkError&) {
      // a socket left by a job that died
    }
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> paths;
  for (auto& [time, path] : found) paths.push_back(path);
  return paths;
}

}  // namespace host
