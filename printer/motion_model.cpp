// The motion model (see motion_model.h): Marlin 2.x's planner, reduced to what decides time.
//
// Per move (a "block" in Marlin's words):
//   length      the XYZ distance; |E| for a move of the extruder alone
//   nominal     the feedrate (at least min_feedrate), scaled down so that no axis exceeds its
//               max_speed; a non-positive or non-finite feedrate means "as fast as the axes go"
//   accel       print_acceleration if it extrudes, travel_acceleration if it does not,
//               retract_acceleration for E alone; then scaled down so that no axis exceeds
//               its max_acceleration
//   max entry   the junction speed with the previous move (junction deviation, below), never
//               above either move's nominal speed; 0 for the first move after the buffer ran dry
// Junction deviation as Marlin computes it: with cos_theta = -(u_prev . u) over the XYZE unit
// directions, v^2 = a_j * junction_deviation * s / (1 - s), s = sqrt((1 - cos_theta) / 2),
// a_j the move's acceleration limited by the axis maxima along the junction vector u - u_prev.
// A full reversal (cos_theta > 0.999999) stops; a move shorter than 1 mm turning by less than
// 45 degrees is also held to the speed of the arc it approximates, v^2 = a_j * length / angle.
// Look-ahead: every push re-plans the open moves with the newest one ending at rest (reverse
// pass: each entry no faster than can still stop in time; forward pass: no faster than can be
// reached). The oldest open move's entry is fixed (it continues the move before it); it
// becomes final, with its exit speed as currently planned, when more than `lookahead` moves
// are open. Its time is the trapezoid (or triangle) from entry to exit through nominal.
// A move's reverse-pass entry depends only on the moves from it to the newest, so a push
// changes them from the newest back only until one comes out as it was (as Marlin's
// recalculate stops where a block's entry is already at its maximum), and the forward pass
// only from there on: the same numbers as re-planning every open move, in a few steps.
#include "printer/motion_model.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>
#include <limits>

namespace printer {

namespace {

struct Block {
  double length = 0;        // mm
  double acceleration = 0;  // mm/s^2
  double nominal_sqr = 0;   // (mm/s)^2
  double max_entry_sqr = 0;
  double reverse_sqr = 0;   // the entry the reverse pass allows (not for the oldest open block)
  double entry_sqr = 0;     // as planned; fixed for the oldest open block
};

// Seconds to cover `length` starting at sqrt(entry_sqr), ending at sqrt(exit_sqr), never faster
// than sqrt(nominal_sqr), accelerating and braking at `acceleration`.
double block_time(const Block& b, double exit_sqr) {
  const double a = b.acceleration, d = b.length;
  const double vn = std::sqrt(b.nominal_sqr);
  if (!(a > 0) || !std::isfinite(a)) return d / vn;
  const double v0 = std::sqrt(b.entry_sqr), v1 = std::sqrt(exit_sqr);
  const double accelerate = (b.nominal_sqr - b.entry_sqr) / (2 * a);
  const double brake = (b.nominal_sqr - exit_sqr) / (2 * a);
  if (accelerate + brake <= d) {  // trapezoid: reaches nominal speed and cruises
    return (vn - v0) / a + (vn - v1) / a + (d - accelerate - brake) / vn;
  }
  const double peak_sqr = 0.5 * (b.entry_sqr + exit_sqr) + a * d;  // triangle
  if (peak_sqr < std::max(b.entry_sqr, exit_sqr)) {
    // Entry and exit cannot both be met at this acceleration (limits changed between
    // moves): a single ramp between them.
    return 2 * d / (v0 + v1);
  }
  const double vp = std::sqrt(peak_sqr);
  return (vp - v0) / a + (vp - v1) / a;
}

// The nominal speed: the feedrate (at least min_feedrate), then every axis held to its own
// maximum; no feedrate is as fast as the axes go.
double nominal_speed(const MotionLimits& lim, const std::array<double, 4>& delta, double length,
                     double feedrate) {
  double speed = (feedrate > 0 && std::isfinite(feedrate))
                     ? feedrate
                     : std::numeric_limits<double>::infinity();
  speed = std::max(speed, lim.min_feedrate);
  for (int axis = 0; axis < 4; ++axis) {
    const double share = std::abs(delta[axis]) / length;  // axis speed per unit of nominal
    if (share > 0 && lim.max_speed[axis] > 0) speed = std::min(speed, lim.max_speed[axis] / share);
  }
  if (!std::isfinite(speed)) speed = lim.max_speed[0] > 0 ? lim.max_speed[0] : 1.0;
  return speed;
}

// The acceleration a move asks for: retracting (E alone), printing or travelling.
double move_acceleration(const MotionLimits& lim, bool extruder_only, bool extrudes) {
  return extruder_only ? lim.retract_acceleration
         : extrudes    ? lim.print_acceleration
                       : lim.travel_acceleration;
}

// `acceleration` along `direction` (of length `norm`), scaled down so that no axis exceeds
// its own maximum.
double held_to_axes(double acceleration, const std::array<double, 4>& direction, double norm,
                    const std::array<double, 4>& max_acceleration) {
  for (int axis = 0; axis < 4; ++axis) {
    const double share = std::abs(direction[axis]) / norm;
    if (share > 0 && max_acceleration[axis] > 0 && acceleration * share > max_acceleration[axis]) {
      acceleration = max_acceleration[axis] / share;
    }
  }
  return acceleration;
}

// Direction over all four axes (Marlin normalises XYZE when the move extrudes).
std::array<double, 4> unit_direction(const std::array<double, 4>& delta, double norm) {
  std::array<double, 4> unit{};
  for (int axis = 0; axis < 4; ++axis) unit[axis] = delta[axis] / norm;
  return unit;
}

// The square of the speed through the junction from a move along `previous` into one along
// `unit` of `length` mm asking for `acceleration`: junction deviation, and the arc a short
// segment approximates (see the top of this file); not yet held to the two moves' nominal speeds.
double junction_speed_sqr(const MotionLimits& lim, const std::array<double, 4>& previous,
                          const std::array<double, 4>& unit, double acceleration, double length) {
  double cos_theta = 0;
  for (int axis = 0; axis < 4; ++axis) cos_theta -= previous[axis] * unit[axis];
  if (cos_theta > 0.999999) return 0;  // full reversal
  cos_theta = std::max(cos_theta, -0.999999);
  // The acceleration available along the change of direction.
  std::array<double, 4> turn{};
  double turn_norm = 0;
  for (int axis = 0; axis < 4; ++axis) {
    turn[axis] = unit[axis] - previous[axis];
    turn_norm += turn[axis] * turn[axis];
  }
  turn_norm = std::sqrt(turn_norm);
  const double junction_acceleration =
      turn_norm > 0 ? held_to_axes(acceleration, turn, turn_norm, lim.max_acceleration) : acceleration;
  const double sin_half = std::sqrt(0.5 * (1.0 - cos_theta));
  double junction_sqr = junction_acceleration * lim.junction_deviation * sin_half / (1.0 - sin_half);
  if (length < 1.0 && cos_theta < -0.7071067812) {
    // A short segment of a curve: no faster than the arc it approximates allows. The turn
    // is at most pi/4 here, where angle <= 1.03 * sqrt(2 * (1 - cos angle)) (1 - cos x =
    // 2 sin^2(x/2), sin y >= 0.974 y for y <= pi/8): where the arc allows more than the
    // junction even at 1.05 times that bound, the acos is not needed (the same minimum).
    const double turn_bound = 1.05 * std::sqrt(2 * (1 + cos_theta));
    if (!(length * junction_acceleration >= turn_bound * junction_sqr)) {
      const double angle = std::acos(std::clamp(-cos_theta, -1.0, 1.0));
      if (angle > 0) junction_sqr = std::min(junction_sqr, length * junction_acceleration / angle);
    }
  }
  return junction_sqr;
}

}  // namespace

struct MotionModel::Planner {
  MotionLimits limits;
  std::size_t lookahead = 16;
  AxisPosition position;
  // The open blocks, oldest first: a ring of at least lookahead + 1 (a push adds one before
  // the oldest leaves), a power of two to wrap by a mask, `count` of them from `head`.
  std::vector<Block> ring;
  std::size_t mask = 0;
  std::size_t head = 0, count = 0;
  std::size_t blocks = 0;  // ever added
  double total = 0;

  // The last move that still shapes the next junction.
  bool has_previous = false;
  std::array<double, 4> previous_unit{};
  double previous_nominal_sqr = 0;

  Block& open(std::size_t i) { return ring[(head + i) & mask]; }
  const Block& open(std::size_t i) const { return const_cast<Planner*>(this)->open(i); }

  // Re-plans after `block` joins the open blocks as the newest, ending at rest.
  void add(const Block& block) {
    open(count++) = block;
    ++blocks;
    if (count < 2) return;
    const std::size_t last = count - 1;
    Block& newest = open(last);
    newest.reverse_sqr = std::min(newest.max_entry_sqr, 2 * newest.acceleration * newest.length);
    // Reverse pass, back to the first block it leaves as it was.
    std::size_t changed = last;
    for (std::size_t i = last - 1; i >= 1; --i) {
      Block& b = open(i);
      const double entry = std::min(b.max_entry_sqr, open(i + 1).reverse_sqr + 2 * b.acceleration * b.length);
      if (entry == b.reverse_sqr) break;
      b.reverse_sqr = entry;
      changed = i;
    }
    // Forward pass from there: before it, the entries follow from blocks as they were.
    for (std::size_t i = changed; i <= last; ++i) {
      const Block& b = open(i - 1);
      Block& next = open(i);
      next.entry_sqr = std::min(next.reverse_sqr, b.entry_sqr + 2 * b.acceleration * b.length);
    }
  }

  double finalize_oldest() {
    const double exit_sqr = count > 1 ? open(1).entry_sqr : 0.0;
    const double seconds = block_time(open(0), exit_sqr);
    head = (head + 1) & mask;
    --count;
    total += seconds;
    return seconds;
  }
};

MotionModel::MotionModel(MotionLimits limits, std::size_t lookahead)
    : planner_(std::make_unique<Planner>()) {
  planner_->limits = limits;
  planner_->lookahead = std::max<std::size_t>(lookahead, 1);
  planner_->ring.resize(std::bit_ceil(planner_->lookahead + 1));
  planner_->mask = planner_->ring.size() - 1;
}

MotionModel::~MotionModel() = default;
MotionModel::MotionModel(MotionModel&&) noexcept = default;
MotionModel& MotionModel::operator=(MotionModel&&) noexcept = default;

double MotionModel::push(AxisPosition target, double feedrate) {
  Planner& p = *planner_;
  const MotionLimits& lim = p.limits;
  const std::array<double, 4> delta{target.x - p.position.x, target.y - p.position.y,
                                    target.z - p.position.z, target.e - p.position.e};
  p.position = target;

  const double xyz = std::sqrt(delta[0] * delta[0] + delta[1] * delta[1] + delta[2] * delta[2]);
  const double e = std::abs(delta[3]);
  const bool extruder_only = !(xyz > 0);
  const double length = extruder_only ? e : xyz;
  if (!(length > 0) || !std::isfinite(length)) return 0;  // nothing moves: no block

  const double acceleration = held_to_axes(move_acceleration(lim, extruder_only, e > 0), delta, length,
                                           lim.max_acceleration);
  Block block;
  block.length = length;
  block.acceleration = acceleration;
  const double speed = nominal_speed(lim, delta, length, feedrate);
  block.nominal_sqr = speed * speed;

  const std::array<double, 4> unit = unit_direction(delta, std::sqrt(xyz * xyz + e * e));
  // After a dry buffer the move starts from rest.
  const double junction_sqr =
      p.has_previous ? std::min({junction_speed_sqr(lim, p.previous_unit, unit, acceleration, length),
                                 block.nominal_sqr, p.previous_nominal_sqr})
                     : 0.0;
  block.max_entry_sqr = junction_sqr;
  block.entry_sqr = 0.0;  // the first open block starts from rest; add() plans the others

  p.has_previous = true;
  p.previous_unit = unit;
  p.previous_nominal_sqr = block.nominal_sqr;

  p.add(block);
  double seconds = 0;
  while (p.count > p.lookahead) seconds += p.finalize_oldest();
  return seconds;
}

double MotionModel::flush() {
  Planner& p = *planner_;
  // Every push planned the open blocks already, and the oldest leaving changes none of them.
  double seconds = 0;
  while (p.count > 0) seconds += p.finalize_oldest();
  p.has_previous = false;  // the buffer ran dry: the next move starts from rest
  return seconds;
}

void MotionModel::set_position(AxisPosition position) { planner_->position = position; }
AxisPosition MotionModel::position() const { return planner_->position; }
double MotionModel::total_time() const { return planner_->total; }

double MotionModel::pending_time() const {
  const Planner& p = *planner_;
  double seconds = 0;
  for (std::size_t i = 0; i < p.count; ++i) {
    seconds += block_time(p.open(i), i + 1 < p.count ? p.open(i + 1).entry_sqr : 0.0);
  }
  return seconds;
}
std::size_t MotionModel::pending() const { return planner_->count; }
std::size_t MotionModel::blocks() const { return planner_->blocks; }
const MotionLimits& MotionModel::limits() const { return planner_->limits; }
void MotionModel::set_limits(const MotionLimits& limits) { planner_->limits = limits; }

}  // namespace printer
