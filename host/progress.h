// A one-line progress display on stderr for long work (slicing, analysis, printing).
//
// On a terminal it redraws one line in place at most 10 times a second; when stderr is not a
// terminal it prints nothing until finish(), so logs and tests stay clean.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace host {

class Progress {
 public:
  Progress(std::string label, std::size_t total);
  ~Progress();

  // Sets the count of finished units and an optional short status ("layer 12/334", "212 C").
  // Safe to call from several threads.
  void update(std::size_t done, const std::string& status = {});
  // Clears the line (on a terminal).
  void finish();

 private:
  std::string label_;
  std::size_t total_;
  bool terminal_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_{};
  std::size_t last_done_ = 0;
};

}  // namespace host
