#include "sim/motion.h"

#include <algorithm>
#include <cmath>
#include <numbers>


namespace sim {

Motion::Motion(const Config& config, DepositionRecord& record, double now)
    : config_(&config),
      record_(&record),
      planner_(config.motion, static_cast<std::size_t>(std::max(config.planner_depth, 1))),
      stepper_free_(now) {}

int Motion::planner_free() const {
  return std::max(0, config_->planner_depth - static_cast<int>(planner_.pending()));
}

void Motion::absolute_positioning(bool absolute) {
  relative_ = !absolute;
  e_mode_ = EMode::follow;
}

void Motion::absolute_extrusion(bool absolute) {
  e_mode_ = absolute ? EMode::absolute : EMode::relative;
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
  planner_.set_position({head_.x, head_.y, head_.z, fed_});
}

bool Motion::e_relative() const {
  if (e_mode_ == EMode::relative) return true;
  if (e_mode_ == EMode::absolute) return false;
  return relative_;
}

// Where a G0-G3 goes, in the current modes; F sets the feedrate.
Motion::Head Motion::destination(const printer::GcodeCommand& c) {
  Head target = head_;
  if (auto v = c.get('X')) target.x = relative_ ? head_.x + *v : *v;
  if (auto v = c.get('Y')) target.y = relative_ ? head_.y + *v : *v;
  if (auto v = c.get('Z')) target.z = relative_ ? head_.z + *v : *v;
  if (auto v = c.get('E')) target.e = e_relative() ? head_.e + *v : *v;
  if (auto f = c.get('F'); f && *f > 0) feedrate_ = *f / 60.0;
  return target;
}

// One straight move: recorded if it extrudes, queued in the planner. Returns when it
// entered the planner.
double Motion::line_to(const Head& target, double now) {
  const double speed = feedrate_ * feed_percent_ / 100.0;
  const double fed = (target.e - head_.e) * flow_percent_ / 100.0;
  const geometry::Vec2 start{head_.x, head_.y}, end{target.x, target.y};
  head_ = target;
  fed_ += fed;
  if (fed > 0 && !(start == end)) record_->add(target.z, start, end, fed, speed);
  return plan_move({head_.x, head_.y, head_.z, fed_}, speed, now);
}

double Motion::move(const printer::GcodeCommand& c, double now) { return line_to(destination(c), now); }

// G2/G3: an arc in XY about the centre at I, J from the start (or of radius R), Z and E
// spread along it, cut into 1 mm segments (Marlin's plan_arc with MM_PER_ARC_SEGMENT 1). A
// start equal to the end with I/J is a full circle.
double Motion::arc(const printer::GcodeCommand& c, bool clockwise, double now) {
  const Head start = head_;
  const Head target = destination(c);
  double i = c.get('I').value_or(0), j = c.get('J').value_or(0);
  if (auto r = c.get('R'); r && *r != 0 && (target.x != start.x || target.y != start.y)) {
    const double e = (clockwise != (*r < 0)) ? -1 : 1;
    const double dx = target.x - start.x, dy = target.y - start.y, d = std::hypot(dx, dy);
    const double h2 = (*r - 0.5 * d) * (*r + 0.5 * d), h = h2 >= 0 ? std::sqrt(h2) : 0.0;
    const double cx = (start.x + target.x) / 2 + e * h * -dy / d;
    const double cy = (start.y + target.y) / 2 + e * h * dx / d;
    i = cx - start.x;
    j = cy - start.y;
  }
  const double cx = start.x + i, cy = start.y + j;
  const double radius = std::hypot(i, j);
  const double ax = -i, ay = -j;  // centre to start
  const double bx = target.x - cx, by = target.y - cy;
  double angle = std::atan2(ax * by - ay * bx, ax * bx + ay * by);
  if (angle < 0) angle += 2 * std::numbers::pi;
  if (clockwise) angle -= 2 * std::numbers::pi;
  if (angle == 0 && start.x == target.x && start.y == target.y && radius > 0) {
    angle = clockwise ? -2 * std::numbers::pi : 2 * std::numbers::pi;
  }
  const double flat = radius * std::abs(angle), rise = target.z - start.z;
  const double travel = std::hypot(flat, rise);
  if (!(radius > 0) || travel < 0.001) return line_to(target, now);
  const int segments = std::max(1, static_cast<int>(std::floor(travel / 1.0)));
  double entered = now;
  for (int k = 1; k <= segments; ++k) {
    Head p = target;
    if (k < segments) {
      const double share = static_cast<double>(k) / segments, turn = angle * share;
      p.x = cx + ax * std::cos(turn) - ay * std::sin(turn);
      p.y = cy + ax * std::sin(turn) + ay * std::cos(turn);
      p.z = start.z + rise * share;
      p.e = start.e + (target.e - start.e) * share;
    }
    entered = std::max(entered, line_to(p, now));
  }
  return entered;
}

double Motion::home(const printer::GcodeCommand& c, double now) {
  finish(now);
  const bool all = !c.has('X') && !c.has('Y') && !c.has('Z');
  printer::AxisPosition at{head_.x, head_.y, head_.z, fed_};
  planner_.set_position(at);
  double seconds = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (!all && !c.has("XYZ"[axis])) continue;
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
    (axis == 0 ? head_.x : axis == 1 ? head_.y : head_.z) = 0;
  }
  stepper_free_ = std::max(stepper_free_, now) + seconds;
  return stepper_free_;
}

void Motion::set_position(const printer::GcodeCommand& c) {
  if (auto v = c.get('X')) head_.x = *v;
  if (auto v = c.get('Y')) head_.y = *v;
  if (auto v = c.get('Z')) head_.z = *v;
  if (auto v = c.get('E')) head_.e = *v;
  planner_.set_position({head_.x, head_.y, head_.z, fed_});
}

void Motion::set_limits(const printer::GcodeCommand& c) {
  printer::MotionLimits limits = planner_.limits();
  constexpr std::string_view axes = "XYZE";
  for (int axis = 0; axis < 4; ++axis) {
    const auto v = c.get(axes[axis]);
    if (!v || *v <= 0) continue;
    if (c.code == 201) limits.max_acceleration[axis] = *v;
    if (c.code == 203) limits.max_speed[axis] = *v;
  }
  if (c.code == 204) {
    if (auto s = c.get('S'); s && *s > 0) limits.print_acceleration = limits.travel_acceleration = *s;
    if (auto p = c.get('P'); p && *p > 0) limits.print_acceleration = *p;
    if (auto r = c.get('R'); r && *r > 0) limits.retract_acceleration = *r;
    if (auto t = c.get('T'); t && *t > 0) limits.travel_acceleration = *t;
  }
  if (c.code == 205) {
    if (auto j = c.get('J'); j && *j > 0) limits.junction_deviation = *j;
    if (auto s = c.get('S'); s && *s >= 0) limits.min_feedrate = *s;
  }
  planner_.set_limits(limits);
}

}  // namespace sim
