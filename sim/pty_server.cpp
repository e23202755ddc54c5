#include "sim/pty_server.h"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>

#include <fmt/core.h>

#include "printer/error.h"

namespace sim {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The firmware spaces bytes at the baud rate on its own clock (so a burst read from the
// kernel arrives byte by byte, as over a UART); the server paces them on the wall clock.
Config for_pty(Config config, const PtyOptions& options) {
  config.baud = options.baud;
  config.time_scale = 0;  // SimLink's pacing; the server follows the wall clock itself
  return config;
}

// What a UART at `rate` bytes/s can have moved: time for bytes starts when there is something
// to move (an idle line saves nothing up), so over any stretch no more than rate x its length
// goes through; `burst` bounds how far a late wake-up may catch up.
class ByteBudget {
 public:
  using Time = std::chrono::steady_clock::time_point;
  ByteBudget(double rate, double burst) : rate_(rate), burst_(burst) {}
  bool limited() const { return rate_ > 0; }
  bool idle() const { return idle_; }
  // There are bytes to move from `now` on.
  void demand(Time now) {
    if (!idle_) return;
    idle_ = false;
    last_ = now;
    tokens_ = 0;
  }
  void go_idle() { idle_ = true; }
  void refill(Time now) {
    if (idle_) return;
    const double dt = std::chrono::duration<double>(now - last_).count();
    tokens_ = std::min(burst_, tokens_ + std::max(dt, 0.0) * rate_);
    last_ = now;
  }
  std::size_t allowed(std::size_t wanted) const {
    if (!limited()) return wanted;
    return idle_ || tokens_ < 1 ? 0 : std::min(wanted, static_cast<std::size_t>(tokens_));
  }
  void spend(std::size_t bytes) {
    if (limited()) tokens_ -= static_cast<double>(bytes);
  }
  // Seconds until one byte may move (0 when unlimited or idle).
  double wait() const { return !limited() || idle_ || tokens_ >= 1 ? 0.0 : (1 - tokens_) / rate_; }

 private:
  double rate_, burst_;
  double tokens_ = 0;
  bool idle_ = true;
  Time last_{};
};

}  // namespace

PtyServer::PtyServer(Config config, PtyOptions options)
    : printer_(for_pty(std::move(config), options)), options_(options) {
  int slave = -1;
  char name[256] = {};
  if (openpty(&master_, &slave, name, nullptr, nullptr) != 0) {
    throw printer::LinkError(fmt::format(
        "cannot open a pseudo-terminal for the simulated printer: {} (is /dev/pts mounted?)",
        std::strerror(errno)));
  }
  termios raw{};
  if (tcgetattr(slave, &raw) == 0) {
    cfmakeraw(&raw);
    cfsetispeed(&raw, B115200);
    cfsetospeed(&raw, B115200);
    tcsetattr(slave, TCSANOW, &raw);
  }
  // Only the master stays open here, so a host closing the port hangs the master up.
  close(slave);
  fcntl(master_, F_SETFL, fcntl(master_, F_GETFL) | O_NONBLOCK);
  fcntl(master_, F_SETFD, FD_CLOEXEC);
  path_ = name;
}

PtyServer::~PtyServer() { close_master(); }

void PtyServer::close_master() {
  if (master_ >= 0) close(master_);
  master_ = -1;
}

struct PtyServer::Session {
  Session(const PtyOptions& options, double sim_now)
      : max_speed(options.time_scale <= 0),
        byte_rate(options.baud > 0 ? options.baud / 10 : 0),
        in(byte_rate, burst()),
        out(byte_rate, burst()),
        sim_base(sim_now) {}
  // A late wake-up catches up at most 10 ms of bytes.
  double burst() const { return std::max(1.0, byte_rate * 0.01); }

  bool max_speed;
  double byte_rate;  // bytes/s; 0: unpaced
  ByteBudget in, out;
  bool open = false;  // a host has the port open
  // Sim clock = sim_base + (wall - wall_base) * scale while following the wall clock.
  Clock::time_point wall_base = Clock::now();
  double sim_base;
  std::string pending_out;
  char buffer[4096];
};

void PtyServer::serve(const std::atomic<bool>& stop) {
  Session s(options_, printer_.now());
  while (!stop.load() && master_ >= 0) {
    follow_host(s);
    catch_up(s);
    if (s.open) read_host(s);
    if (s.max_speed) run_ahead(s);
    if (printer_.state() == PrinterState::disconnected) {
      close_master();  // the port vanishes, as a USB printer unplugged
      break;
    }
    write_host(s);
    sleep_until_due(s);
  }
  printer_.finish();
}

// The master hangs up while no one has the slave open.
void PtyServer::follow_host(Session& s) {
  pollfd probe{master_, POLLIN, 0};
  poll(&probe, 1, 0);
  const bool hung_up = (probe.revents & POLLHUP) != 0;
  if (hung_up && s.open) {
    s.open = false;
    s.pending_out.clear();
    if (options_.on_session) options_.on_session(false);
  } else if (!hung_up && !s.open) {
    s.open = true;
    ++opens_;
    // Align the clocks, then reset as a board does when DTR goes up.
    s.sim_base = printer_.now();
    s.wall_base = Clock::now();
    s.in.go_idle();
    s.out.go_idle();
    if (options_.reset_on_open) {
      // Bytes left from the last session, or sent while the board resets, are lost.
      while (read(master_, s.buffer, sizeof s.buffer) > 0) {
      }
      printer_.reset();
    }
    if (options_.on_session) options_.on_session(true);
  }
}

void PtyServer::catch_up(Session& s) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const double wall = seconds_since(s.wall_base);
  if (!s.max_speed) {
    printer_.run_until(s.sim_base + wall * options_.time_scale);
    return;
  }
  printer_.run_until(std::max(printer_.now(), s.sim_base + wall));
  // Booting is the firmware's own wait: done at once, before any byte is read.
  while (printer_.state() == PrinterState::booting && printer_.next_event_time() < kInfinity) {
    printer_.run_until(printer_.next_event_time());
  }
  s.sim_base = printer_.now() - wall;
}

void PtyServer::read_host(Session& s) {
  if (s.in.limited() && s.in.idle()) {
    pollfd ready{master_, POLLIN, 0};
    if (poll(&ready, 1, 0) > 0 && (ready.revents & POLLIN)) s.in.demand(Clock::now());
  }
  s.in.refill(Clock::now());
  const std::size_t allowed = s.in.allowed(sizeof s.buffer);
  if (allowed == 0) return;
  const ssize_t n = read(master_, s.buffer, allowed);
  if (n < static_cast<ssize_t>(allowed) && s.in.limited()) s.in.go_idle();
  if (n > 0) {
    s.in.spend(static_cast<std::size_t>(n));
    printer_.receive(std::string_view(s.buffer, static_cast<std::size_t>(n)));
    printer_.run_until(printer_.now());
  }
}

void PtyServer::run_ahead(Session& s) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const Clock::time_point burst = Clock::now();
  while (!printer_.idle() && seconds_since(burst) < 0.05) {
    const double next = printer_.next_event_time();
    if (next == kInfinity) break;
    printer_.run_until(next);
    if (s.pending_out.size() > 65536) break;  // let the host read first
  }
  s.sim_base = printer_.now() - seconds_since(s.wall_base);
}

// Replies are lost while no host has the port open.
void PtyServer::write_host(Session& s) {
  std::string said = printer_.take_output();
  if (!s.open) return;
  s.pending_out += said;
  if (s.pending_out.empty()) return;
  s.out.demand(Clock::now());
  s.out.refill(Clock::now());
  const std::size_t allowed = s.out.allowed(s.pending_out.size());
  if (allowed == 0) return;
  const ssize_t n = write(master_, s.pending_out.data(), allowed);
  if (n > 0) {
    s.out.spend(static_cast<std::size_t>(n));
    s.pending_out.erase(0, static_cast<std::size_t>(n));
    if (s.pending_out.empty()) s.out.go_idle();
  }
}

void PtyServer::sleep_until_due(Session& s) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  double wait = 0.05;
  if (!s.open) wait = 0.01;  // a hung-up master polls ready at once: look again soon
  const double next = printer_.next_event_time();
  if (next < kInfinity) {
    const double sim_wait = next - printer_.now();
    wait = std::min(wait, s.max_speed ? (printer_.idle() ? sim_wait : 0.0)
                                      : sim_wait / options_.time_scale);
  }
  if (!s.pending_out.empty()) wait = std::min(wait, s.out.wait());
  wait = std::max(wait, 0.0);
  if (!s.open) {
    usleep(static_cast<useconds_t>(wait * 1e6));
    return;
  }
  // Wake for input or room to write only when the budgets allow moving a byte; otherwise
  // sleep until they do.
  s.in.refill(Clock::now());
  s.out.refill(Clock::now());
  short events = 0;
  if (s.in.wait() > 0) {
    wait = std::min(wait, s.in.wait());
  } else {
    events |= POLLIN;
  }
  if (!s.pending_out.empty() && s.out.wait() == 0) events |= POLLOUT;
  pollfd fds{master_, events, 0};
  if (wait > 0) poll(&fds, 1, static_cast<int>(std::ceil(wait * 1000)));
}

}  // namespace sim
