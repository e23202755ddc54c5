#include "printer/print_time.h"

#include <cmath>

namespace printer {

PrintClock::PrintClock(MotionLimits limits, std::size_t lookahead) : model_(limits, lookahead) {}

void PrintClock::line(std::string_view text) {
  // Most lines of a program are moves or comments: skip comments without parsing.
  std::size_t start = 0;
  while (start < text.size() && (text[start] == ' ' || text[start] == '\t')) ++start;
  if (start == text.size() || text[start] == ';') return;
  command(parse_gcode_line(text));
}

void PrintClock::drain() { model_.flush(); }

void PrintClock::linear_move(const MoveWords& words) {
  auto axis = [&](const std::optional<double>& word, double current, bool relative) {
    if (!word) return current;
    return relative ? current + *word : *word;
  };
  AxisPosition target;
  target.x = axis(words.x, position_.x, relative_xyz_);
  target.y = axis(words.y, position_.y, relative_xyz_);
  target.z = axis(words.z, position_.z, relative_xyz_);
  target.e = axis(words.e, position_.e, relative_e_);
  if (words.f && *words.f > 0) feedrate_ = *words.f / 60.0;
  // The same test the motion model makes for a move that takes time.
  const double dx = target.x - position_.x, dy = target.y - position_.y, dz = target.z - position_.z;
  const double xyz = std::sqrt(dx * dx + dy * dy + dz * dz);
  const double length = xyz > 0 ? xyz : std::abs(target.e - position_.e);
  if (length > 0 && std::isfinite(length)) ++moves_;
  model_.push(target, feedrate_);
  position_ = target;
}

void PrintClock::command(const GcodeCommand& c) {
  if (c.letter == 'G') {
    switch (c.code) {
      case 0: case 1: case 2: case 3:
        linear_move({c.get('X'), c.get('Y'), c.get('Z'), c.get('E'), c.get('F')});
        return;
      case 4:
        drain();
        if (auto p = c.get('P')) dwell_ += *p / 1000.0;
        if (auto s = c.get('S')) dwell_ += *s;
        return;
      case 28: {
        drain();
        const bool all = !c.has('X') && !c.has('Y') && !c.has('Z');
        if (all || c.has('X')) position_.x = 0;
        if (all || c.has('Y')) position_.y = 0;
        if (all || c.has('Z')) position_.z = 0;
        model_.set_position(position_);
        return;
      }
      case 90: relative_xyz_ = false; relative_e_ = false; return;
      case 91: relative_xyz_ = true; relative_e_ = true; return;
      case 92:
        if (auto v = c.get('X')) position_.x = *v;
        if (auto v = c.get('Y')) position_.y = *v;
        if (auto v = c.get('Z')) position_.z = *v;
        if (auto v = c.get('E')) position_.e = *v;
        model_.set_position(position_);
        return;
      default: return;
    }
  }
  if (c.letter != 'M') return;
  MotionLimits limits = model_.limits();
  static constexpr char kAxes[4] = {'X', 'Y', 'Z', 'E'};
  switch (c.code) {
    case 82: relative_e_ = false; return;
    case 83: relative_e_ = true; return;
    case 109: case 190: case 400: drain(); return;
    case 201:
      for (int i = 0; i < 4; ++i) {
        if (auto v = c.get(kAxes[i]); v && *v > 0) limits.max_acceleration[i] = *v;
      }
      break;
    case 203:
      for (int i = 0; i < 4; ++i) {
        if (auto v = c.get(kAxes[i]); v && *v > 0) limits.max_speed[i] = *v;
      }
      break;
    case 204:
      if (auto v = c.get('S'); v && *v > 0) limits.print_acceleration = limits.travel_acceleration = *v;
      if (auto v = c.get('P'); v && *v > 0) limits.print_acceleration = *v;
      if (auto v = c.get('R'); v && *v > 0) limits.retract_acceleration = *v;
      if (auto v = c.get('T'); v && *v > 0) limits.travel_acceleration = *v;
      break;
    case 205:
      if (auto v = c.get('J'); v && *v > 0) limits.junction_deviation = *v;
      break;
    default: return;
  }
  model_.set_limits(limits);
}

double PrintClock::elapsed() const { return model_.total_time() + dwell_; }

double PrintClock::modeled() const { return elapsed() + model_.pending_time(); }

std::size_t PrintClock::moves_final() const { return moves_ - model_.pending(); }

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
