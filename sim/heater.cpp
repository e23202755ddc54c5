#include "sim/heater.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace sim {

namespace {
constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kEpsilon = 1e-9;  // °C: "at the target"
}  // namespace

Heater::Heater(HeaterConstants constants, double ambient)
    : constants_(constants), ambient_(ambient), temperature_(ambient) {
  constants_.time_constant = std::max(constants_.time_constant, 1e-3);
  constants_.heating_rate = std::max(constants_.heating_rate, 0.0);
}

double Heater::ceiling() const {
  return ambient_ + constants_.heating_rate * constants_.time_constant;
}

void Heater::set_target(double target) { target_ = target; }

void Heater::fail() { failed_ = true; }

int Heater::power() const {
  if (failed_ || target_ <= ambient_) return 0;
  if (temperature_ < target_ - kEpsilon) return 127;
  if (temperature_ > target_ + kEpsilon) return 0;
  // Holding: the power that balances the losses at the target.
  const double share = (target_ - ambient_) / (constants_.heating_rate * constants_.time_constant);
  return static_cast<int>(std::lround(127 * std::clamp(share, 0.0, 1.0)));
}

void Heater::advance_to(double t) {
  const double tau = constants_.time_constant;
  while (t > time_) {
    const double dt = t - time_;
    const bool controlled = !failed_ && target_ > ambient_;
    if (controlled && std::abs(temperature_ - target_) <= kEpsilon) {
      temperature_ = target_;  // holding
      time_ = t;
    } else if (controlled && temperature_ < target_) {
      // Full power toward the ceiling until the target.
      const double c = ceiling();
      const double reach = target_ < c ? tau * std::log((c - temperature_) / (c - target_)) : kInfinity;
      if (reach <= dt) {
        temperature_ = target_;
        time_ += reach;
      } else {
        temperature_ = c + (temperature_ - c) * std::exp(-dt / tau);
        time_ = t;
      }
    } else {
      // Power off: falls toward ambient, or to the target and holds there.
      const double floor = controlled ? target_ : ambient_;
      const double reach = controlled && temperature_ > floor
                               ? tau * std::log((temperature_ - ambient_) / (floor - ambient_))
                               : kInfinity;
      if (reach <= dt) {
        temperature_ = target_;
        time_ += reach;
      } else {
        temperature_ = ambient_ + (temperature_ - ambient_) * std::exp(-dt / tau);
        time_ = t;
      }
    }
  }
}

double Heater::time_reaching(double level) const {
  const double tau = constants_.time_constant;
  if (std::abs(temperature_ - level) <= kEpsilon) return time_;
  const bool controlled = !failed_ && target_ > ambient_;
  if (controlled && temperature_ < target_ - kEpsilon) {
    // Rising to the target, then holding there.
    if (level < temperature_ || level > target_ + kEpsilon) return kInfinity;
    const double c = ceiling();
    if (level >= c) return kInfinity;
    return time_ + tau * std::log((c - temperature_) / (c - level));
  }
  if (controlled && std::abs(temperature_ - target_) <= kEpsilon) return kInfinity;
  // Falling toward ambient, or toward the target and holding there.
  const double floor = controlled ? target_ : ambient_;
  if (level > temperature_ || level < floor - kEpsilon || level <= ambient_) return kInfinity;
  return time_ + tau * std::log((temperature_ - ambient_) / (std::max(level, floor) - ambient_));
}

}  // namespace sim
