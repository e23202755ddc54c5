// The terminal side of a print job: a progress line (layer n/N counted from 1, percent of the
// estimated print time, elapsed, ETA, temperatures) redrawn in place on stderr, single keys on stdin (p pause, r resume,
// c cancel, ! emergency stop), and the job's events as lines.
//
// Keys are read only when stdin is a terminal (it is put in non-canonical mode and restored
// on exit); otherwise `mahost ctl` drives the job through the control socket. Ctrl-C asks
// for a cancel, a second Ctrl-C for an emergency stop; a closed terminal (SIGHUP) does not
// end the print. Without a terminal on stderr there is no progress line, only events.
#pragma once

#include <chrono>
#include <string>

#include "printer/job.h"

namespace host {

class PrintUi {
 public:
  PrintUi();
  ~PrintUi();
  PrintUi(const PrintUi&) = delete;
  PrintUi& operator=(const PrintUi&) = delete;

  // Reads keys and signals into requests, redraws the progress line (at most 5 times a second
  // of wall time).
  void tick(printer::Job& job);
  // Prints one line above the progress line.
  void event(const std::string& line);
  // Clears the progress line.
  void finish();

  bool keys() const { return keys_; }

 private:
  bool keys_ = false;      // stdin is a terminal in non-canonical mode
  bool terminal_ = false;  // stderr is a terminal
  bool drawn_ = false;
  int handled_interrupts_ = 0;
  std::chrono::steady_clock::time_point last_draw_{};
  void* saved_termios_ = nullptr;
};

// "layer 12/334  35.2%  elapsed 0:12:33  ETA 0:23:10  hotend 210.1/210 °C  bed 60.0/60 °C"
std::string progress_text(const printer::JobProgress& progress);
// "0:12:33", "12:03:07".
std::string clock_text(std::chrono::nanoseconds duration);

// Signals: the count of SIGINT/SIGTERM received since install_print_signals().
void install_print_signals();
int interrupt_count();

}  // namespace host
