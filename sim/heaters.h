// The simulated printer's two heaters as the firmware drives them (sim/printer.h): targets
// clamped to the maximum temperatures, M109/M190's wait for the target and its residency,
// the temperature report, and Marlin's thermal protection stopping a failed heater.
//
// Input: target changes and waits at sim times (s). Output: the report text Marlin prints
// (" T:200.00 /200.00 B:60.00 /60.00 @:0 B@:0"), when a wait ends, when thermal runaway
// fires. Each heater follows sim/heater.h's closed form, so any time step is exact.
#pragma once

#include <limits>
#include <string>

#include "sim/config.h"
#include "sim/heater.h"

namespace sim {

class Heaters {
 public:
  enum class Which { hotend, bed };

  Heaters(const Config& config, double now);

  void advance_to(double t);
  void set_hotend(double target, double now);  // clamped to max_hotend_temp
  void set_bed(double target);                 // clamped to max_bed_temp
  void all_off();                              // kill(): targets 0, no runaway to come
  // runaway-at-line: the hotend heater fails from `now` on.
  void fail_hotend(double now);

  // M109 / M190 once the target is set: reports at once and every second until done;
  // returns when the wait ends (within the window for the residency time and at the
  // target). `wait_for_cooling` (R rather than S) also waits for a heater above its target.
  double start_wait(Which which, bool wait_for_cooling, double now);
  // The report a waiting M109/M190 prints each second: the states and "W:<s left>" ("W:?"
  // until within the window).
  std::string wait_report(Which which, double now) const;
  void end_wait() { residency_from_ = kNever; }

  // " T:<hotend> /<target> B:<bed> /<target> @:<power> B@:<power>", Marlin's M105 fields.
  std::string states() const;

  // When the heater will have stood within `band` °C of its target for `residency` seconds
  // counted from its last target change (Teacup's temp_achieved, temp.c: a target change resets
  // the residency); -infinity for a heater without a target.
  double settled_at(Which which, double band, double residency) const;

  // When thermal protection stops the printer; +infinity when it will not.
  double runaway_at() const { return runaway_at_; }

  const Heater& hotend() const { return hotend_; }
  const Heater& bed() const { return bed_; }

 private:
  static constexpr double kNever = std::numeric_limits<double>::infinity();
  const HeaterConstants& constants(Which which) const {
    return which == Which::hotend ? config_->hotend : config_->bed;
  }
  Heater& heater(Which which) { return which == Which::hotend ? hotend_ : bed_; }
  void update_runaway(double now);

  const Config* config_;
  Heater hotend_, bed_;
  Heater hotend_at_change_, bed_at_change_;  // as each was when its target last changed
  double residency_from_ = kNever;  // when the waited-for heater got within its window
  double runaway_at_ = kNever;
};

}  // namespace sim
