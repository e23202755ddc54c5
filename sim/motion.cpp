#include "sim/motion.h"

#include <algorithm>
#include <array>
#include <optional>

namespace sim {

Motion::Motion(const Config& config, DepositionRecord& record, double now)
    : config_(&config),
      record_(&record),
      planner_(config.motion, static_cast<std::size_t>(std::max(config.planner_depth, 1))),
      stepper_free_(now) {
  state_.rules = gcode_rules(config.dialect);
  state_.feedrate = 1500;  // mm/min: Marlin's feedrate_mm_s at boot (module/motion.cpp)
}

int Motion::planner_free() const {
  return std::max(0, config_->planner_depth - static_cast<int>(planner_.pending()));
}

// Queues a move in the planner; returns when it could enter (a slot was free).
double Motion::plan_move(printer::AxisPosition target, double speed, double now) {
  const printer::AxisPosition from = planner_.position();
  const bool moves = target.x != from.x || target.y != from.y || target.z != from.z ||
                     target.e != from.e;
  const std::size_t before = planner_.pending();
  const double seconds = planner_.push(target, speed);
  const std::size_t opened = before + (moves ? 1 : 0);
  const std::size_t finalized = opened > planner_.pending() ? opened - planner_.pending() : 0;
  if (moves) open_moves_.push_back(now);
  if (finalized == 0) return now;
  if (!drained_ && open_moves_.front() > stepper_free_) starved_ += open_moves_.front() - stepper_free_;
  drained_ = false;
  const double start = std::max(stepper_free_, open_moves_.front());
  for (std::size_t i = 0; i < finalized && !open_moves_.empty(); ++i) open_moves_.pop_front();
  stepper_free_ = start + seconds;
  return std::max(now, stepper_free_);
}

double Motion::finish(double now) {
  drained_ = true;
  const double seconds = planner_.flush();
  if (!open_moves_.empty()) {
    const double start = std::max(stepper_free_, open_moves_.front());
    stepper_free_ = std::max(start + seconds, open_moves_.back());
    open_moves_.clear();
  }
  return std::max(now, stepper_free_);
}

void Motion::quickstop(double now) {
  drained_ = true;
  planner_.flush();
  open_moves_.clear();
  stepper_free_ = std::min(stepper_free_, now);
  planner_.set_position(planner_target());
}

// Where the planner has the head: the interpreter's (with any firmware retraction) and the
// filament actually fed.
printer::AxisPosition Motion::planner_target() const {
  printer::AxisPosition at = printer::machine_position(state_);
  at.e = fed_;
  return at;
}

// One straight move: recorded if it extrudes, queued in the planner. Returns when it
// entered the planner.
double Motion::line(const printer::Motion& move, double now) {
  const double speed = move.feedrate * feed_percent_ / 100.0;
  const double fed = (move.to.e - move.from.e) * state_.flow / 100.0;
  fed_ += fed;
  const geometry::Vec2 start{move.from.x, move.from.y}, end{move.to.x, move.to.y};
  if (fed > 0 && !(start == end)) record_->add(move.to.z, start, end, fed, speed);
  return plan_move({move.to.x, move.to.y, move.to.z, fed_}, speed, now);
}

Motion::Queued Motion::move(const printer::GcodeCommand& c, double now) {
  const printer::GcodeStep step = printer::interpret(state_, c);
  Queued queued{now, step.bad_arc};
  for (const printer::Motion& m : step.moves()) queued.entered = std::max(queued.entered, line(m, now));
  return queued;
}

double Motion::home(const printer::GcodeCommand& c, double now) {
  finish(now);
  // G28's axes, or those Teacup's G161/G162 name (gcode_process.c).
  const std::array<bool, 3> axes =
      c.is('G', 28) ? printer::homed_axes(c) : std::array<bool, 3>{c.has('X'), c.has('Y'), c.has('Z')};
  printer::AxisPosition at = planner_target();
  planner_.set_position(at);
  double seconds = 0;
  printer::GcodeCommand homed = printer::parse_gcode_line("G28");
  for (int axis = 0; axis < 3; ++axis) {
    const char name = "XYZ"[axis];
    if (!axes[axis]) continue;
    homed.words.push_back({name, std::nullopt});
    double* coordinate = axis == 0 ? &at.x : axis == 1 ? &at.y : &at.z;
    const double speed = config_->homing_feedrate[axis];
    const double bump = config_->homing_bump[axis];
    *coordinate = 0;  // to the endstop at 0
    seconds += planner_.push(at, speed);
    *coordinate = bump;  // back off
    seconds += planner_.push(at, speed);
    *coordinate = 0;  // and touch again, slower
    seconds += planner_.push(at, speed / (axis == 2 ? 4 : 2));
    seconds += planner_.flush();
  }
  if (!homed.words.empty()) printer::interpret(state_, homed);  // the homed axes at 0
  stepper_free_ = std::max(stepper_free_, now) + seconds;
  return stepper_free_;
}

void Motion::set_position(const printer::GcodeCommand& c) {
  printer::interpret(state_, c);
  planner_.set_position(planner_target());
}

void Motion::set_limits(const printer::GcodeCommand& c) {
  if (const auto limits = printer::motion_limits_after(planner_.limits(), c)) planner_.set_limits(*limits);
}

}  // namespace sim
