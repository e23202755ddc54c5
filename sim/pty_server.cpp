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

// No pacing of its own for the firmware: on the pty the wall clock paces the bytes.
Config for_pty(Config config) {
  config.baud = 0;
  config.time_scale = 0;
  return config;
}

}  // namespace

PtyServer::PtyServer(Config config, PtyOptions options)
    : printer_(for_pty(std::move(config))), options_(options) {
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

void PtyServer::serve(const std::atomic<bool>& stop) {
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  const bool max_speed = options_.time_scale <= 0;
  const double byte_rate = options_.baud > 0 ? options_.baud / 10 : 0;  // bytes/s

  bool open = false;  // a host has the port open
  // Sim clock = sim_base + (wall - wall_base) * scale while following the wall clock.
  Clock::time_point wall_base = Clock::now();
  double sim_base = printer_.now();
  // Byte pacing: a budget that grows at byte_rate from when a host opened the port.
  Clock::time_point pace_base = wall_base;
  std::uint64_t bytes_in = 0, bytes_out = 0;
  std::string pending_out;
  char buffer[4096];

  while (!stop.load() && master_ >= 0) {
    // 1. Is a host there? The master hangs up while no one has the slave open.
    pollfd probe{master_, POLLIN, 0};
    poll(&probe, 1, 0);
    const bool hung_up = (probe.revents & POLLHUP) != 0;
    if (hung_up && open) {
      open = false;
      pending_out.clear();
    } else if (!hung_up && !open) {
      open = true;
      ++opens_;
      // Align the clocks, then reset as a board does when DTR goes up.
      sim_base = printer_.now();
      wall_base = pace_base = Clock::now();
      bytes_in = bytes_out = 0;
      if (options_.reset_on_open) printer_.reset();
    }

    // 2. The sim clock catches up with the wall clock (or runs ahead at full speed).
    const double wall = seconds_since(wall_base);
    if (max_speed) {
      printer_.run_until(std::max(printer_.now(), sim_base + wall));
      sim_base = printer_.now() - wall;
    } else {
      printer_.run_until(sim_base + wall * options_.time_scale);
    }

    // 3. Bytes from the host, no faster than the UART would bring them.
    if (open) {
      std::size_t allowed = sizeof buffer;
      if (byte_rate > 0) {
        const double budget = seconds_since(pace_base) * byte_rate - static_cast<double>(bytes_in);
        allowed = budget < 1 ? 0 : std::min(sizeof buffer, static_cast<std::size_t>(budget));
      }
      if (allowed > 0) {
        const ssize_t n = read(master_, buffer, allowed);
        if (n > 0) {
          bytes_in += static_cast<std::uint64_t>(n);
          printer_.receive(std::string_view(buffer, static_cast<std::size_t>(n)));
          printer_.run_until(printer_.now());
        }
      }
    }

    // 4. Full speed: run through everything the firmware can do without the host.
    if (max_speed) {
      const Clock::time_point burst = Clock::now();
      while (!printer_.idle() && seconds_since(burst) < 0.05) {
        const double next = printer_.next_event_time();
        if (next == kInfinity) break;
        printer_.run_until(next);
        if (pending_out.size() > 65536) break;  // let the host read first
      }
      sim_base = printer_.now() - seconds_since(wall_base);
    }
    if (printer_.state() == PrinterState::disconnected) {
      close_master();  // the port vanishes, as a USB printer unplugged
      break;
    }

    // 5. Replies to the host, paced likewise; lost while no host has the port open.
    std::string said = printer_.take_output();
    if (open) pending_out += said;
    if (open && !pending_out.empty()) {
      std::size_t allowed = pending_out.size();
      if (byte_rate > 0) {
        const double budget = seconds_since(pace_base) * byte_rate - static_cast<double>(bytes_out);
        allowed = budget < 1 ? 0 : std::min(allowed, static_cast<std::size_t>(budget));
      }
      if (allowed > 0) {
        const ssize_t n = write(master_, pending_out.data(), allowed);
        if (n > 0) {
          bytes_out += static_cast<std::uint64_t>(n);
          pending_out.erase(0, static_cast<std::size_t>(n));
        }
      }
    }

    // 6. Sleep until input, the next firmware event, the next byte slot, or 50 ms.
    double wait = 0.05;
    if (!open) wait = 0.01;  // a hung-up master polls ready at once: look again soon
    const double next = printer_.next_event_time();
    if (next < kInfinity) {
      const double sim_wait = next - printer_.now();
      wait = std::min(wait, max_speed ? (printer_.idle() ? sim_wait : 0.0)
                                      : sim_wait / options_.time_scale);
    }
    if (byte_rate > 0 && (!pending_out.empty())) wait = std::min(wait, 1 / byte_rate);
    wait = std::max(wait, 0.0);
    if (!open) {
      usleep(static_cast<useconds_t>(wait * 1e6));
      continue;
    }
    pollfd fds{master_, static_cast<short>(POLLIN | (pending_out.empty() ? 0 : POLLOUT)), 0};
    if (byte_rate > 0) {
      // Input that the budget does not allow yet must not wake us at once.
      const double budget = seconds_since(pace_base) * byte_rate - static_cast<double>(bytes_in);
      if (budget < 1) {
        fds.events &= static_cast<short>(~POLLIN);
        wait = std::min(wait, (1 - budget) / byte_rate);
      }
    }
    if (wait > 0) poll(&fds, 1, static_cast<int>(std::ceil(wait * 1000)));
  }
  printer_.finish();
}

}  // namespace sim
