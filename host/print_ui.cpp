#include "host/print_ui.h"

#include <poll.h>
#include <signal.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>

#include <fmt/core.h>

namespace host {

namespace {

std::atomic<int> interrupts{0};

extern "C" void on_interrupt(int) { interrupts.fetch_add(1); }

}  // namespace

void install_print_signals() {
  struct sigaction action{};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // A print outlives the terminal or ssh session that started it.
  signal(SIGHUP, SIG_IGN);
  signal(SIGPIPE, SIG_IGN);
}

int interrupt_count() { return interrupts.load(); }

std::string clock_text(std::chrono::nanoseconds duration) {
  const long long total = std::chrono::duration_cast<std::chrono::seconds>(duration).count();
  const long long s = total < 0 ? 0 : total;
  return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
}

std::string progress_text(const printer::JobProgress& p) {
  std::string text;
  if (p.state != printer::JobState::printing) text += fmt::format("{}  ", printer::to_string(p.state));
  if (p.layers > 0) {
    text += p.layer > 0 ? fmt::format("layer {}/{}", p.layer, p.layers)
                        : fmt::format("start of {} layers", p.layers);
  }
  text += fmt::format("  {:.1f}%  elapsed {}", 100.0 * p.fraction, clock_text(p.elapsed));
  if (p.remaining) {
    text += fmt::format("  ETA {}", clock_text(*p.remaining));
  } else if (p.estimating) {
    text += "  ETA estimating";
  }
  if (p.temperatures) {
    const auto& t = *p.temperatures;
    if (t.hotend) text += fmt::format("  hotend {:.1f}/{:.0f} °C", *t.hotend, t.hotend_target.value_or(0));
    if (t.bed) text += fmt::format("  bed {:.1f}/{:.0f} °C", *t.bed, t.bed_target.value_or(0));
  }
  if (p.pause_before_layer > 0) text += fmt::format("  (pausing before layer {})", p.pause_before_layer);
  return text;
}

PrintUi::PrintUi() {
  terminal_ = isatty(STDERR_FILENO) == 1;
  if (isatty(STDIN_FILENO) == 1) {
    auto* saved = new termios{};
    if (tcgetattr(STDIN_FILENO, saved) == 0) {
      termios raw = *saved;
      raw.c_lflag &= static_cast<tcflag_t>(~(ICANON | ECHO));
      raw.c_cc[VMIN] = 0;
      raw.c_cc[VTIME] = 0;
      if (tcsetattr(STDIN_FILENO, TCSANOW, &raw) == 0) {
        saved_termios_ = saved;
        keys_ = true;
      } else {
        delete saved;
      }
    } else {
      delete saved;
    }
  }
}

PrintUi::~PrintUi() {
  finish();
  if (saved_termios_ != nullptr) {
    auto* saved = static_cast<termios*>(saved_termios_);
    tcsetattr(STDIN_FILENO, TCSANOW, saved);
    delete saved;
  }
}

void PrintUi::tick(printer::Job& job) {
  const int now_interrupts = interrupt_count();
  if (now_interrupts > handled_interrupts_) {
    if (handled_interrupts_ == 0) {
      event("interrupted: cancelling the print (Ctrl-C again for an emergency stop)");
      job.request(printer::JobRequest::cancel);
    }
    if (now_interrupts >= 2) job.request(printer::JobRequest::stop);
    handled_interrupts_ = now_interrupts;
  }
  if (keys_) {
    pollfd in{STDIN_FILENO, POLLIN, 0};
    while (poll(&in, 1, 0) > 0 && (in.revents & POLLIN)) {
      char key = 0;
      if (read(STDIN_FILENO, &key, 1) != 1) break;
      switch (key) {
        case 'p': case 'P':
          event("pause requested: the print pauses at the next layer start (r calls it off)");
          job.request(printer::JobRequest::pause);
          break;
        case 'r': case 'R':
          job.request(printer::JobRequest::resume);
          break;
        case 'c': case 'C':
          event("cancel requested");
          job.request(printer::JobRequest::cancel);
          break;
        case '!':
          event("emergency stop requested");
          job.request(printer::JobRequest::stop);
          break;
        default:
          break;
      }
    }
  }
  if (!terminal_) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_draw_ < std::chrono::milliseconds(200)) return;
  last_draw_ = now;
  std::string line = progress_text(job.progress());
  if (keys_) line += "  [p r c !]";
  fmt::print(stderr, "\r\033[K{}", line);
  std::fflush(stderr);
  drawn_ = true;
}

void PrintUi::event(const std::string& line) {
  if (terminal_ && drawn_) fmt::print(stderr, "\r\033[K");
  fmt::print(stderr, "{}\n", line);
  std::fflush(stderr);
  drawn_ = false;
}

void PrintUi::finish() {
  if (terminal_ && drawn_) {
    fmt::print(stderr, "\r\033[K");
    std::fflush(stderr);
  }
  drawn_ = false;
}

}  // namespace host
