#include "printer/print_eta.h"

#include <algorithm>

#include "printer/print_time.h"

namespace printer {

PrintEta::PrintEta(const GcodeFile& file, const MotionLimits& limits) {
  PrintClock clock(limits);
  times_.reserve(file.size() + 1);
  times_.push_back(0.0f);
  for (std::size_t i = 0; i < file.size(); ++i) {
    clock.line(file.command(i));
    times_.push_back(static_cast<float>(clock.elapsed()));
  }
  times_.back() = static_cast<float>(clock.finish());
}

double PrintEta::at(std::size_t commands) const {
  if (times_.empty()) return 0.0;
  return times_[std::min(commands, times_.size() - 1)];
}

void PrintEta::arm_pace(std::size_t commands) {
  if (!armed_at_) armed_at_ = commands;
}

void PrintEta::command_done(std::size_t commands, double printing_seconds) {
  if (pace_start_ || !armed_at_ || !(at(commands) > at(*armed_at_))) return;
  pace_start_ = PaceStart{at(commands), printing_seconds};
}

std::optional<double> PrintEta::pace(std::size_t commands, double printing_seconds) const {
  if (!pace_start_) return std::nullopt;
  const double modelled = at(commands) - pace_start_->model;
  const double measured = printing_seconds - pace_start_->printing;
  if (modelled < min_sample || !(measured > 0)) return std::nullopt;
  return measured / modelled;
}

double PrintEta::remaining(std::size_t commands, double done_at, double now) const {
  const double pace_now = pace(commands, done_at).value_or(1.0);
  const double left = std::max(0.0, total() - at(commands)) * pace_now;
  const double next_move = (at(commands + 1) - at(commands)) * pace_now;
  return std::max(0.0, left - std::clamp(now - done_at, 0.0, next_move));
}

double PrintEta::fraction(std::size_t commands) const {
  const double whole = total();
  if (whole > 0) return std::clamp(at(commands) / whole, 0.0, 1.0);
  // Nothing that takes time (heating, settings): the share of the commands.
  const std::size_t all = times_.size() - 1;
  return all > 0 ? static_cast<double>(std::min(commands, all)) / static_cast<double>(all) : 1.0;
}

}  // namespace printer
