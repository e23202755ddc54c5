// One heater of the simulated printer (hotend or bed): the first-order model of
// sim/config.h (HeaterConstants), solved in closed form so any time step is exact.
//
// Input: constants, ambient temperature, target changes and failures at given sim times.
// Output: temperature (°C) and heater power (Marlin's 0..127 PWM) at any later time, and the
// time the temperature crosses a level. A failed heater no longer heats (its power stays 0).
#pragma once

#include "sim/config.h"

namespace sim {

class Heater {
 public:
  Heater(HeaterConstants constants, double ambient);

  // Moves the model to sim time t (no effect for t <= the current time).
  void advance_to(double t);
  void set_target(double target);  // at the current time
  void fail();

  double time() const { return time_; }
  double temperature() const { return temperature_; }
  double target() const { return target_; }
  bool failed() const { return failed_; }
  // 127 while heating, the holding power at the target, 0 when off or cooling.
  int power() const;

  // The first sim time >= time() at which the temperature reaches `level` on its present
  // course (rising toward or holding the target, or falling); +infinity if it never does.
  double time_reaching(double level) const;

  // Temperature at full power in the limit (ambient + heating_rate * time_constant).
  double ceiling() const;

 private:
  HeaterConstants constants_;
  double ambient_;
  double time_ = 0;
  double temperature_;
  double target_ = 0;
  bool failed_ = false;
};

}  // namespace sim
