#include "printer/print_time.h"

#include <cmath>

namespace printer {

namespace {

constexpr double kDefaultFeedrate = 25.0;  // mm/s before any F: Marlin's 1500 mm/min

}  // namespace

PrintClock::PrintClock(MotionLimits limits, std::size_t lookahead) : model_(limits, lookahead) {}

void PrintClock::line(std::string_view text) {
  // Most lines of a program are moves or comments: skip comments without parsing.
  std::size_t start = 0;
  while (start < text.size() && (text[start] == ' ' || text[start] == '\t')) ++start;
  if (start == text.size() || text[start] == ';') return;
  command(parse_gcode_line(text));
}

void PrintClock::drain() { model_.flush(); }

// The model's position is always where the interpreter has the machine (every move starts
// where the last ended, G28 and G92 set it), so its blocks are the moves that take time.
void PrintClock::push(const Motion& move) {
  model_.push(move.to, move.feedrate != 0 ? move.feedrate : kDefaultFeedrate);
}

void PrintClock::run(const GcodeStep& step) {
  if (step.homed) drain();
  for (const Motion& move : step.moves()) push(move);
  if (step.position_set) model_.set_position(machine_position(state_));
}

void PrintClock::linear_move(const MoveWords& words) { push(move_motion(state_, words)); }

void PrintClock::command(const GcodeCommand& c) {
  run(interpret(state_, c));
  if (const auto dwell = dwell_seconds(c)) {
    drain();
    dwell_ += *dwell;
    return;
  }
  if (c.letter != 'M') return;
  if (c.code == 109 || c.code == 190 || c.code == 400) return drain();
  if (const auto limits = motion_limits_after(model_.limits(), c)) model_.set_limits(*limits);
}

double PrintClock::elapsed() const { return model_.total_time() + dwell_; }

double PrintClock::modeled() const { return elapsed() + model_.pending_time(); }

std::size_t PrintClock::moves_final() const { return model_.blocks() - model_.pending(); }

double PrintClock::finish() {
  drain();
  return elapsed();
}

double estimate_print_time(std::string_view program, const MotionLimits& limits) {
  PrintClock clock(limits);
  while (!program.empty()) {
    const std::size_t end = program.find('\n');
    clock.line(program.substr(0, end));
    if (end == std::string_view::npos) break;
    program.remove_prefix(end + 1);
  }
  return clock.finish();
}

}  // namespace printer
