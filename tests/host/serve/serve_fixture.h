// `mahost serve --dry-run` (or on a --port) as the tests run it: a process on a free loopback port with its own
// runtime, config and files folders and a known API key, an HTTP client for it, raw sockets for
// requests no well-behaved client sends, and the simulated printer's record once it stops.
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <doctest/doctest.h>
#include <httplib.h>
#include <zlib.h>
#include <nlohmann/json.hpp>

#include "printer/gcode_file.h"
#include "support/run_command.h"

extern char** environ;

namespace serve_test {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using nlohmann::json;

inline constexpr const char* kKey = "serve-test-key-0123456789abcdef";

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline bool wait_for(const std::function<bool()>& condition, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!condition()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

// The folders of one test: scratch/{run,config,files}; the environment the server gets.
struct ServeDirs {
  std::string root, runtime, files, record;
  explicit ServeDirs(const std::string& name) {
    root = test_support::scratch_dir(name);
    runtime = root + "/run";
    files = root + "/files";
    record = root + "/record.json";
    fs::create_directories(runtime);
    fs::permissions(runtime, fs::perms::owner_all);
  }
};

class Serve {
 public:
  // Starts `mahost serve --dry-run --listen 127.0.0.1:0` plus `args`, and waits for its URL.
  Serve(const ServeDirs& dirs, std::vector<std::string> args, bool with_key = true) : dirs_(dirs) {
    int out[2];
    REQUIRE(pipe2(out, O_CLOEXEC) == 0);
    log_ = dirs.root + "/serve.log";
    // A port given (a simulated printer on a pseudo-terminal): that printer, not the dry run's.
    std::vector<std::string> argv{MAHOST_BINARY, "serve", "--files", dirs.files};
    if (std::find(args.begin(), args.end(), "--port") == args.end()) {
      argv.insert(argv.end(), {"--dry-run", "--record", dirs.record});
    }
    if (std::find(args.begin(), args.end(), "--listen") == args.end()) {
      argv.insert(argv.end(), {"--listen", "127.0.0.1:0"});
    }
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<std::string> env{"XDG_RUNTIME_DIR=" + dirs.runtime, "HOME=" + dirs.root,
                                 "XDG_CONFIG_HOME=" + dirs.root + "/config",
                                 "PATH=" + std::string(getenv("PATH") ? getenv("PATH") : "/usr/bin:/bin")};
    if (with_key) env.push_back(std::string("MAHOST_API_KEY=") + kKey);
    if (const char* asan = getenv("ASAN_OPTIONS")) env.push_back(std::string("ASAN_OPTIONS=") + asan);
    std::vector<char*> raw_argv, raw_env;
    for (std::string& a : argv) raw_argv.push_back(a.data());
    raw_argv.push_back(nullptr);
    for (std::string& e : env) raw_env.push_back(e.data());
    raw_env.push_back(nullptr);
    pid_ = test_support::spawn_tied(raw_argv, raw_env, out[1], log_);
    close(out[1]);
    out_ = out[0];
    const std::string line = first_line(60s);
    INFO("serve log: " << read_text(log_));
    REQUIRE(line.rfind("mahost serve: http://", 0) == 0);
    const std::string url = line.substr(0, line.find("/ "));
    port = std::stoi(url.substr(url.rfind(':') + 1));
  }
  ~Serve() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (out_ >= 0) close(out_);
  }
  Serve(const Serve&) = delete;
  Serve& operator=(const Serve&) = delete;

  httplib::Client client(bool key = true) const {
    httplib::Client c("127.0.0.1", port);
    c.set_read_timeout(30, 0);
    c.set_connection_timeout(10, 0);
    if (key) c.set_default_headers({{"X-Api-Key", kKey}});
    return c;
  }
  json get_json(const std::string& path) const {
    auto c = client();
    auto r = c.Get(path);
    REQUIRE(r);
    INFO(path << " -> " << r->status << " " << r->body);
    REQUIRE(r->status == 200);
    return json::parse(r->body);
  }
  int post_json(const std::string& path, const json& body) const {
    auto c = client();
    auto r = c.Post(path, body.dump(), "application/json");
    REQUIRE(r);
    return r->status;
  }
  // Uploads `text` as `name` (multipart, as PrusaSlicer does) with the extra form fields.
  httplib::Result upload(const std::string& name, const std::string& text,
                         const std::vector<std::pair<std::string, std::string>>& fields = {}) const {
    auto c = client();
    httplib::MultipartFormDataItems items{{"file", text, name, "application/octet-stream"}};
    for (const auto& [k, v] : fields) items.push_back({k, v, "", ""});
    return c.Post("/api/files/local", items);
  }
  std::string state() const { return get_json("/api/job")["state"]; }
  bool wait_state(const std::string& wanted, std::chrono::seconds timeout) const {
    return wait_for([&] { return state() == wanted; }, timeout);
  }
  // SIGTERM, then the exit code (128 + signal when killed).
  int stop(std::chrono::seconds timeout = 60s) {
    kill(pid_, SIGTERM);
    return wait(timeout);
  }
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
  void kill_now() {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  std::string log() const { return read_text(log_); }
  bool alive() const { return pid_ > 0 && ::kill(pid_, 0) == 0; }

  int port = 0;

 private:
  std::string first_line(std::chrono::seconds timeout) {
    std::string buffer;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (buffer.find('\n') == std::string::npos && std::chrono::steady_clock::now() < deadline) {
      pollfd p{out_, POLLIN, 0};
      if (poll(&p, 1, 100) > 0) {
        char chunk[256];
        const ssize_t n = read(out_, chunk, sizeof chunk);
        if (n <= 0) break;
        buffer.append(chunk, static_cast<std::size_t>(n));
      }
    }
    return buffer.substr(0, buffer.find('\n'));
  }

  const ServeDirs& dirs_;
  pid_t pid_ = -1;
  int out_ = -1;
  std::string log_;
};

// `mahost sim` on a pseudo-terminal: a printer serve reaches by a port, which a test can
// unplug (kill) and plug back (start again, on a new terminal). What it says on stderr goes to
// `log` (appended: a printer plugged back writes on), read when a test fails.
class SimPrinter {
 public:
  SimPrinter(std::vector<std::string> args, const std::string& log) {
    int out[2];
    REQUIRE(pipe2(out, O_CLOEXEC) == 0);
    args.insert(args.begin(), {MAHOST_BINARY, "sim"});
    std::vector<char*> argv, env;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    for (char** e = environ; *e; ++e) env.push_back(*e);
    env.push_back(nullptr);
    pid_ = test_support::spawn_tied(argv, env, out[1], log);
    close(out[1]);
    out_ = out[0];
    // The first line is the port; what follows (a line per host opening it) is read and dropped.
    std::string line;
    char c;
    while (read(out_, &c, 1) == 1 && c != '\n') line += c;
    port = line;
    drain_ = std::thread([fd = out_] {
      char buffer[256];
      while (read(fd, buffer, sizeof buffer) > 0) {
      }
    });
  }
  ~SimPrinter() { unplug(); }
  SimPrinter(const SimPrinter&) = delete;
  SimPrinter& operator=(const SimPrinter&) = delete;
  // The printer vanishes at once, as a USB cable pulled: its terminal closes under the host.
  void unplug() {
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
      pid_ = -1;
    }
    if (drain_.joinable()) drain_.join();
    if (out_ >= 0) close(out_);
    out_ = -1;
  }

  std::string port;

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::thread drain_;
};

// A raw TCP connection, for requests no library would send.
class RawConnection {
 public:
  // From `from`, a loopback address of this machine (127.0.0.2 ...: Linux answers the whole
  // 127/8), so one test can be many client addresses.
  explicit RawConnection(int port, const std::string& from = "") {
    fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    REQUIRE(fd_ >= 0);
    if (!from.empty()) {
      sockaddr_in source{};
      source.sin_family = AF_INET;
      REQUIRE(inet_pton(AF_INET, from.c_str(), &source.sin_addr) == 1);
      REQUIRE(bind(fd_, reinterpret_cast<sockaddr*>(&source), sizeof source) == 0);
    }
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
  }
  ~RawConnection() {
    if (fd_ >= 0) close(fd_);
  }
  bool send(const std::string& bytes) {
    std::size_t sent = 0;
    while (sent < bytes.size()) {
      const ssize_t n = ::send(fd_, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
      if (n <= 0) return false;
      sent += static_cast<std::size_t>(n);
    }
    return true;
  }
  void finish_sending() { shutdown(fd_, SHUT_WR); }
  // Closes at once, unread bytes and all (the kernel answers with a reset).
  void drop() {
    linger l{1, 0};
    setsockopt(fd_, SOL_SOCKET, SO_LINGER, &l, sizeof l);
    close(fd_);
    fd_ = -1;
  }
  // The bytes that arrive next, "" once the server closed or `deadline` passed.
  std::string receive_some(std::chrono::steady_clock::time_point deadline) {
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 100) <= 0) continue;
      char chunk[16384];
      const ssize_t n = read(fd_, chunk, sizeof chunk);
      if (n <= 0) return {};
      return std::string(chunk, static_cast<std::size_t>(n));
    }
    return {};
  }
  // Whether the server closed its side: the end of the stream comes before `timeout`.
  bool closed_by_server(std::chrono::seconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 100) <= 0) continue;
      char chunk[4096];
      const ssize_t n = read(fd_, chunk, sizeof chunk);
      if (n <= 0) return true;
    }
    return false;
  }
  // What arrives until the server closes or `timeout` passes.
  std::string receive(std::chrono::seconds timeout, std::size_t enough = SIZE_MAX) {
    std::string got;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (got.size() < enough && std::chrono::steady_clock::now() < deadline) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 100) <= 0) continue;
      char chunk[4096];
      const ssize_t n = read(fd_, chunk, sizeof chunk);
      if (n <= 0) break;
      got.append(chunk, static_cast<std::size_t>(n));
      if (got.find("\r\n\r\n") != std::string::npos && enough == SIZE_MAX) {
        // a whole response: its body is short JSON; keep reading briefly for it
        const auto header_end = got.find("\r\n\r\n");
        const auto length_at = got.find("Content-Length: ");
        if (length_at != std::string::npos && length_at < header_end) {
          const std::size_t length = std::stoul(got.substr(length_at + 16));
          if (got.size() >= header_end + 4 + length) break;
        }
      }
    }
    return got;
  }

 private:
  int fd_ = -1;
};

// A gzip stream's bytes unpacked ("" when they are not gzip).
inline std::string gunzip(const std::string& packed) {
  z_stream z{};
  if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) return {};
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(packed.data()));
  z.avail_in = static_cast<uInt>(packed.size());
  std::string out;
  char chunk[16384];
  int status = Z_OK;
  while (status == Z_OK) {
    z.next_out = reinterpret_cast<Bytef*>(chunk);
    z.avail_out = sizeof chunk;
    status = inflate(&z, Z_NO_FLUSH);
    out.append(chunk, sizeof chunk - z.avail_out);
  }
  inflateEnd(&z);
  return status == Z_STREAM_END ? out : std::string();
}

// One HTTP response read off a connection: the status, the head and the body (by its
// Content-Length), or status -1 when the connection ended or `timeout` passed first.
struct RawResponse {
  int status = -1;
  std::string head, body;
  bool closes() const { return head.find("\r\nConnection: close\r\n") != std::string::npos; }
};

inline RawResponse read_response(RawConnection& raw, std::string& pending, std::chrono::seconds timeout) {
  RawResponse r;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  auto more = [&] {
    const std::string got = raw.receive_some(deadline);
    pending += got;
    return !got.empty();
  };
  std::size_t end;
  while ((end = pending.find("\r\n\r\n")) == std::string::npos) {
    if (!more()) return r;
  }
  r.head = pending.substr(0, end + 4);
  std::size_t length = 0;
  const auto at = r.head.find("Content-Length: ");
  if (at != std::string::npos) length = std::stoul(r.head.substr(at + 16));
  while (pending.size() < end + 4 + length) {
    if (!more()) return r;
  }
  r.body = pending.substr(end + 4, length);
  pending.erase(0, end + 4 + length);
  if (r.head.find("\r\nContent-Encoding: gzip\r\n") != std::string::npos) r.body = gunzip(r.body);
  r.status = std::stoi(r.head.substr(9, 3));
  return r;
}

inline int status_of(const std::string& response) {
  if (response.rfind("HTTP/1.1 ", 0) != 0 || response.size() < 12) return -1;
  return std::stoi(response.substr(9, 3));
}

// PrusaSlicer's "Upload and Print" as it sends it (src/slic3r/Utils/OctoPrint.cpp,
// upload_inner_with_host: form_add "print", form_add "path", form_add_file "file"), in
// libcurl's form encoding: fields without a Content-Type, the file as application/octet-stream.
inline std::string prusaslicer_upload(const std::string& name, const std::string& text, bool print) {
  const std::string b = "------------------------9b6a6c3c0e7a40d2";
  const std::string body = "--" + b + "\r\nContent-Disposition: form-data; name=\"print\"\r\n\r\n" +
                           (print ? "true" : "false") + "\r\n--" + b +
                           "\r\nContent-Disposition: form-data; name=\"path\"\r\n\r\n\r\n--" + b +
                           "\r\nContent-Disposition: form-data; name=\"file\"; filename=\"" + name +
                           "\"\r\nContent-Type: application/octet-stream\r\n\r\n" + text + "\r\n--" + b + "--\r\n";
  return "POST /api/files/local HTTP/1.1\r\nHost: 127.0.0.1\r\nUser-Agent: PrusaSlicer/2.7.1\r\n"
         "Accept: */*\r\nX-Api-Key: " + std::string(kKey) + "\r\nContent-Length: " + std::to_string(body.size()) +
         "\r\nContent-Type: multipart/form-data; boundary=" + b + "\r\n\r\n" + body;
}

// Cura's OctoPrint plugin's upload with "Automatically start print job" (fieldOfView's
// Cura-OctoPrintPlugin, OctoPrintOutputDevice.py, _sendPrintJob: parts path, file, select,
// print), as Qt's QHttpMultiPart writes it: the boundary quoted, each part's Content-Disposition
// then its Content-Type.
inline std::string cura_upload(const std::string& name, const std::string& text, bool print) {
  const std::string b = "boundary_.oOo._MTU4NzQ2MzE5NDYwNTQ4MjQ0NDc2NTk4";
  const auto part = [&](const std::string& disposition, const std::string& type, const std::string& value) {
    return "--" + b + "\r\nContent-Disposition: form-data; " + disposition + "\r\nContent-Type: " + type +
           "\r\n\r\n" + value + "\r\n";
  };
  std::string body = part("name=\"path\"", "text/plain", "") +
                     part("name=\"file\"; filename=\"" + name + "\"", "application/octet-stream", text);
  if (print) body += part("name=\"select\"", "text/plain", "true") + part("name=\"print\"", "text/plain", "true");
  body += "--" + b + "--\r\n";
  return "POST /api/files/local HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Api-Key: " + std::string(kKey) +
         "\r\nUser-Agent: Cura-OctoPrintPlugin/3.7.3\r\nContent-Type: multipart/form-data; boundary=\"" + b +
         "\"\r\nMIME-Version: 1.0\r\nContent-Length: " + std::to_string(body.size()) +
         "\r\nConnection: Keep-Alive\r\nAccept-Encoding: gzip, deflate\r\n\r\n" + body;
}

// Sends a whole request on a connection of its own and reads its answer.
inline RawResponse send_raw(int port, const std::string& request, std::chrono::seconds timeout = 60s) {
  RawConnection raw(port);
  REQUIRE(raw.send(request));
  std::string pending;
  return read_response(raw, pending, timeout);
}

// The commands a simulated print executed, less the host's own: M105 (temperatures), M110 and
// M115 (connecting), M155 (auto-report), M113 (the busy keepalive a job asks Marlin for).
inline std::vector<std::string> printed_commands(const json& record) {
  std::vector<std::string> out;
  for (const json& c : record["commands"]) {
    const std::string s = c;
    if (s.rfind("M105", 0) == 0 || s.rfind("M110", 0) == 0 || s.rfind("M115", 0) == 0 || s.rfind("M155", 0) == 0 ||
        s.rfind("M113", 0) == 0) continue;
    out.push_back(s);
  }
  return out;
}

inline std::vector<std::string> file_commands(const std::string& text) {
  const printer::GcodeFile file = printer::parse_gcode(text, "test");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < file.size(); ++i) out.emplace_back(file.command(i));
  return out;
}

// A ring wall without heating, so a print of it takes seconds at --time-scale 20-50 (each
// layer about 4 s of simulated time).
inline std::string ring_gcode(int layers, int segments = 60) {
  std::string g = "; generated by the mahost serve tests\nG28\nG90\nM82\nG92 E0\n";
  const double pi = std::acos(-1.0);
  for (int layer = 0; layer < layers; ++layer) {
    const double z = 0.2 * (layer + 1);
    char line[160];
    std::snprintf(line, sizeof line, ";LAYER:%d\n;Z:%.3f\nG92 E0\nG1 Z%.3f F600\n", layer, z, z);
    g += line;
    const double r = 20 + 5 * std::sin(layer * 0.1);
    std::snprintf(line, sizeof line, "G0 X%.3f Y100.000 F6000\nG1 E1.00000 F1800\n", 100 + r);
    g += line;
    double e = 1.0;
    for (int i = 1; i <= segments; ++i) {
      const double a = 2 * pi * i / segments;
      e += 2 * pi * r / segments * 0.0333;
      std::snprintf(line, sizeof line, "G1 X%.3f Y%.3f E%.5f F1800\n", 100 + r * std::cos(a),
                    100 + r * std::sin(a), e);
      g += line;
    }
    std::snprintf(line, sizeof line, "G1 E%.5f F1800\n", e - 1.0);
    g += line;
  }
  g += "M104 S0\nM140 S0\nG91\nG1 Z10 F600\nG90\nM84\n";
  return g;
}

}  // namespace serve_test
