#include "host/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <mutex>

#include <fmt/core.h>

namespace host {

namespace {
std::mutex draw_mutex;
}

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      terminal_(isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()) {}

Progress::~Progress() { finish(); }

void Progress::update(std::size_t done, const std::string& status) {
  if (!terminal_ || finished_) return;
  std::lock_guard lock(draw_mutex);
  const auto now = std::chrono::steady_clock::now();
  if (done < total_ && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  last_done_ = std::max(last_done_, done);
  const double fraction = total_ ? static_cast<double>(last_done_) / total_ : 1.0;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(filled, '#');
  bar.resize(kWidth, '.');
  std::string eta;
  if (fraction > 0.02 && fraction < 1.0) {
    eta = fmt::format(" ETA {:.0f}s", elapsed * (1.0 - fraction) / fraction);
  }
  fmt::print(stderr, "\r\033[K{} [{}] {:3.0f}% {}{}", label_, bar, 100.0 * fraction, status, eta);
  std::fflush(stderr);
}

void Progress::finish() {
  if (!terminal_ || finished_) return;
  finished_ = true;
  std::lock_guard lock(draw_mutex);
  fmt::print(stderr, "\r\033[K");
  std::fflush(stderr);
}

}  // namespace host
