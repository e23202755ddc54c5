// Controlling a running print from another terminal or a script: a Unix socket next to the
// job's journal (mode 0600: only the user who started the job), one request line per
// connection (pause, resume, cancel, stop, status) and one reply line.
//
// The print serves it from its job loop without blocking (ControlSocket::serve);
// `mahost ctl` is the client (send_control). Jobs live in printer::job_directory().
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "printer/job.h"

namespace host {

class ControlSocket {
 public:
  // Binds and listens at `path` with mode 0600. Throws printer::ConfigError naming the path.
  explicit ControlSocket(std::string path);
  ~ControlSocket();
  ControlSocket(const ControlSocket&) = delete;
  ControlSocket& operator=(const ControlSocket&) = delete;

  // Answers every client waiting now; returns at once when there is none.
  void serve(printer::Job& job);
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
};

// The reply to one request line, applied to the job: what serve() sends back.
std::string answer_request(printer::Job& job, const std::string& request);

// Sends one request to the job at `socket_path` and returns its reply line. Throws
// printer::LinkError naming the socket when no job answers there.
std::string send_control(const std::string& socket_path, const std::string& request,
                         std::chrono::milliseconds timeout = std::chrono::milliseconds(5000));

// The control sockets in the job directory whose job answers, oldest first.
std::vector<std::string> running_jobs();

}  // namespace host
