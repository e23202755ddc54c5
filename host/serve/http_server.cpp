#include "host/serve/http_server.h"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <deque>
#include <optional>
#include <thread>
#include <vector>
#include <cstdio>
#include <cstring>

#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include "host/local_time.h"

namespace host::serve {

namespace {

using Clock = std::chrono::steady_clock;

// What a connection's thread knows of its connection, for the static queries the handlers make.
struct ClientConnection {
  const HttpServer* server = nullptr;
  std::string address;
  bool beyond_share = false;
  bool close = false;           // close after the answer being written
  bool head_timed_out = false;
  bool in_body = false;         // the request's head is read: what follows is its body
  std::uint64_t consumed = 0;   // bytes httplib took from the connection
  std::uint64_t head_end = 0;   // `consumed` where the request's head ended
  std::optional<std::uint64_t> body_length;  // Content-Length, when given and a number
  bool body_announced = false;  // a Content-Length or Transfer-Encoding was given
  std::uint64_t written = 0;    // bytes of the answer sent
};

thread_local ClientConnection* current = nullptr;

// Waits until `fd` is ready for `events`, or the deadline, or the server stops (looked at
// four times a second, so a stop ends every wait soon).
bool wait_ready(int fd, short events, Clock::time_point deadline, const std::function<bool()>& running) {
  while (running()) {
    const auto left = deadline - Clock::now();
    if (left <= Clock::duration::zero()) return false;
    // Rounded up: a wait that ends early by a fraction of a millisecond is not a timeout.
    const long long ms = std::chrono::ceil<std::chrono::milliseconds>(left).count();
    pollfd p{fd, events, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(std::min<long long>(ms, 250)));
    if (ready > 0) return true;  // readable, writable, or closed: the read or send says which
    if (ready < 0 && errno != EINTR) return false;
  }
  return false;
}

std::string numeric_host(const sockaddr_storage& address, socklen_t length, int* port) {
  char host[NI_MAXHOST] = "", service[NI_MAXSERV] = "";
  if (::getnameinfo(reinterpret_cast<const sockaddr*>(&address), length, host, sizeof host, service,
                    sizeof service, NI_NUMERICHOST | NI_NUMERICSERV) != 0) {
    return "-";
  }
  if (port != nullptr) *port = std::atoi(service);
  return host;
}

std::string peer_address(int sock, int* port = nullptr) {
  sockaddr_storage address{};
  socklen_t length = sizeof address;
  if (::getpeername(sock, reinterpret_cast<sockaddr*>(&address), &length) != 0) return "-";
  return numeric_host(address, length, port);
}

// A connection as httplib reads and writes it: reads buffered per connection (so a client
// that sends its next request at once loses nothing), each read bounded by the request's head
// deadline or, in a body, by the longest stall allowed.
class ConnectionStream final : public httplib::Stream {
 public:
  ConnectionStream(int sock, ClientConnection& connection, const ConnectionLimits& limits,
                   std::function<bool()> running)
      : sock_(sock), connection_(connection), limits_(limits), running_(std::move(running)) {}

  bool has_buffered() const { return start_ < end_; }
  // A request begins: its head is due within the head time.
  void start_request() { head_deadline_ = Clock::now() + limits_.head_time; }

  bool is_readable() const override { return has_buffered() || wait_ready(sock_, POLLIN, read_deadline(), running_); }
  bool is_writable() const override {
    if (!wait_ready(sock_, POLLOUT, Clock::now() + limits_.write_stall, running_)) return false;
    // Still open: a peek sees bytes, or nothing yet (not the end of the stream).
    char byte;
    const ssize_t n = ::recv(sock_, &byte, 1, MSG_PEEK | MSG_DONTWAIT);
    return n > 0 || (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK));
  }

  ssize_t read(char* ptr, size_t size) override {
    if (!has_buffered()) {
      if (!wait_ready(sock_, POLLIN, read_deadline(), running_)) {
        if (!connection_.in_body && Clock::now() >= head_deadline_) connection_.head_timed_out = true;
        return -1;
      }
      const ssize_t n = ::recv(sock_, buffer_, sizeof buffer_, 0);
      if (n <= 0) return n;
      start_ = 0;
      end_ = static_cast<std::size_t>(n);
    }
    const std::size_t taken = std::min(size, end_ - start_);
    std::memcpy(ptr, buffer_ + start_, taken);
    start_ += taken;
    connection_.consumed += taken;
    return static_cast<ssize_t>(taken);
  }

  ssize_t write(const char* ptr, size_t size) override {
    if (!wait_ready(sock_, POLLOUT, Clock::now() + limits_.write_stall, running_)) return -1;
    const ssize_t n = ::send(sock_, ptr, size, MSG_NOSIGNAL);
    if (n > 0) connection_.written += static_cast<std::uint64_t>(n);
    return n;
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override { ip = peer_address(sock_, &port); }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    sockaddr_storage address{};
    socklen_t length = sizeof address;
    if (::getsockname(sock_, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
      ip = numeric_host(address, length, &port);
    }
  }
  socket_t socket() const override { return sock_; }

 private:
  Clock::time_point read_deadline() const {
    return connection_.in_body ? Clock::now() + limits_.body_stall : head_deadline_;
  }

  int sock_;
  ClientConnection& connection_;
  const ConnectionLimits& limits_;
  std::function<bool()> running_;
  Clock::time_point head_deadline_{};
  char buffer_[16384];
  std::size_t start_ = 0, end_ = 0;
};

// An answer written without httplib (no request was read to hang it on), then logged as the
// answers httplib writes are.
void answer_raw(int sock, const std::string& address, int status, const char* reason, const std::string& message) {
  const std::string body = nlohmann::json{{"error", message}}.dump();
  const std::string response = fmt::format(
      "HTTP/1.1 {} {}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{}",
      status, reason, body.size(), body);
  // A short write is as good as none: the client that stopped reading loses only this answer.
  [[maybe_unused]] const ssize_t sent = ::send(sock, response.data(), response.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  std::fprintf(stderr, "%s %s (no request) -> %d: %s\n", local_time().c_str(), address.c_str(), status,
               message.c_str());
  std::fflush(stderr);
}

// Closes after an answer the client may not have read yet while it still sends: the bytes
// that follow are read and dropped for a while, so the client's kernel keeps the answer rather
// than meeting a reset (what closing with unread bytes sends).
void close_lingering(int sock, const ConnectionLimits& limits, const std::function<bool()>& running) {
  ::shutdown(sock, SHUT_WR);
  const auto deadline = Clock::now() + limits.linger;
  std::uint64_t dropped = 0;
  char sink[16384];
  while (dropped < limits.linger_bytes && wait_ready(sock, POLLIN, deadline, running)) {
    const ssize_t n = ::recv(sock, sink, sizeof sink, 0);
    if (n <= 0) break;
    dropped += static_cast<std::uint64_t>(n);
  }
  ::close(sock);
}

// httplib's task queue as a thread for each connection: a thread is made when every thread is
// busy, up to `most`; threads stay for the next connections once made.
class ConnectionThreads final : public httplib::TaskQueue {
 public:
  explicit ConnectionThreads(std::size_t most) : most_(most) {}

  void enqueue(std::function<void()> task) override {
    std::lock_guard lock(mutex_);
    tasks_.push_back(std::move(task));
    if (tasks_.size() > idle_ && threads_.size() < most_) {
      threads_.emplace_back([this] { work(); });
    } else {
      ready_.notify_one();
    }
  }

  void shutdown() override {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    ready_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

 private:
  void work() {
    std::unique_lock lock(mutex_);
    while (true) {
      ++idle_;
      ready_.wait(lock, [&] { return stopping_ || !tasks_.empty(); });
      --idle_;
      if (tasks_.empty()) return;  // stopping, nothing left
      std::function<void()> task = std::move(tasks_.front());
      tasks_.pop_front();
      lock.unlock();
      task();
      lock.lock();
    }
  }

  const std::size_t most_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<std::function<void()>> tasks_;
  std::vector<std::thread> threads_;
  std::size_t idle_ = 0;
  bool stopping_ = false;
};

std::optional<std::uint64_t> digits_value(const std::string& text) {
  if (text.empty() || text.size() > 19 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return std::nullopt;
  }
  return std::stoull(text);
}

}  // namespace

HttpServer::HttpServer(ConnectionLimits limits) : limits_(limits) {
  // A thread for each connection, made as connections come (the most ever: `total` and a few
  // for those refused at once), so a request never waits for another connection to end.
  const int most = limits_.total + 16;
  new_task_queue = [most] { return new ConnectionThreads(static_cast<std::size_t>(most)); };
}

bool HttpServer::admit(const std::string& address, bool& beyond_share) {
  std::lock_guard lock(mutex_);
  if (open_ >= limits_.total) return false;
  ++open_;
  beyond_share = ++addresses_[address].open > limits_.per_address;
  return true;
}

void HttpServer::leave(const std::string& address) {
  std::lock_guard lock(mutex_);
  --open_;
  if (--addresses_[address].open <= 0) addresses_.erase(address);
}

bool HttpServer::process_and_close_socket(socket_t sock) {
  const std::function<bool()> running = [this] { return svr_sock_ != INVALID_SOCKET; };
  const std::string address = peer_address(sock);
  bool beyond_share = false;
  if (!admit(address, beyond_share)) {
    answer_raw(sock, address, 503, "Service Unavailable",
               fmt::format("{} connections are open, this server's most: try again shortly", limits_.total));
    close_lingering(sock, limits_, running);
    return false;
  }
  ClientConnection connection;
  connection.server = this;
  connection.address = address;
  connection.beyond_share = beyond_share;
  current = &connection;
  ConnectionStream stream(sock, connection, limits_, running);
  bool linger = false;
  const auto accepted = Clock::now();
  for (std::size_t count = keep_alive_max_count_; count > 0 && running(); --count) {
    // The first request's first byte is due within the head time, the next ones' within the
    // idle time; a client that sent nothing is closed on without an answer.
    const bool first = count == keep_alive_max_count_;
    if (!stream.has_buffered() &&
        !wait_ready(sock, POLLIN, first ? accepted + limits_.head_time : Clock::now() + limits_.idle, running)) {
      break;
    }
    stream.start_request();
    connection.close = connection.head_timed_out = connection.in_body = false;
    connection.written = 0;
    bool closed_by_client = false;
    const bool ok = process_request(stream, count == 1, closed_by_client, [&](httplib::Request& req) {
      connection.in_body = true;
      connection.head_end = connection.consumed;
      connection.body_announced = req.has_header("Content-Length") || req.has_header("Transfer-Encoding");
      connection.body_length = digits_value(req.get_header_value("Content-Length"));
    });
    if (connection.head_timed_out && connection.written == 0) {
      answer_raw(sock, address, 408, "Request Timeout", head_timeout_message());
      linger = true;
      break;
    }
    if (connection.close) {
      linger = true;
      break;
    }
    if (!ok || closed_by_client) break;
  }
  current = nullptr;
  if (linger) {
    close_lingering(sock, limits_, running);
  } else {
    ::shutdown(sock, SHUT_RDWR);
    ::close(sock);
  }
  leave(address);
  return true;
}

std::string HttpServer::beyond_share_refusal(const httplib::Request& req) {
  ClientConnection* c = current;
  if (c == nullptr || !c->beyond_share) return {};
  if (c->server->always_served && c->server->always_served(req)) return {};
  c->close = true;
  return fmt::format("{} has {} connections open to this server already, its most: close some "
                     "(pause, resume, cancel and emergency stop are served all the same)",
                     c->address, c->server->limits().per_address);
}

bool HttpServer::head_timed_out() { return current != nullptr && current->head_timed_out; }

std::string HttpServer::head_timeout_message() {
  const std::chrono::milliseconds head_time = current != nullptr ? current->server->limits().head_time
                                                                 : ConnectionLimits{}.head_time;
  return fmt::format("the request's line and headers did not arrive within {} s",
                     std::chrono::duration<double>(head_time).count());
}

void HttpServer::close_if_unread(const httplib::Request&, httplib::Response& res) {
  ClientConnection* c = current;
  if (c == nullptr) return;
  if (!c->close) {
    if (!c->in_body) {
      c->close = true;  // the head could not be read: where the next request starts is unknown
    } else if (c->body_announced) {
      // A body of unknown length (chunked, or a length that is no number) is not known to be
      // read: only an answer that took it (2xx) keeps the connection.
      c->close = c->body_length ? c->consumed - c->head_end < *c->body_length : res.status >= 300;
    }
  }
  if (c->close) {
    res.set_header("Connection", "close");
    res.headers.erase("Keep-Alive");
  }
}

}  // namespace host::serve
