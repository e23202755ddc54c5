#include "sim/heaters.h"

#include <algorithm>
#include <cmath>

#include <fmt/core.h>

namespace sim {

Heaters::Heaters(const Config& config, double now)
    : config_(&config),
      hotend_(config.hotend, config.ambient),
      bed_(config.bed, config.ambient),
      hotend_at_change_(hotend_),
      bed_at_change_(bed_) {
  hotend_.advance_to(now);
  bed_.advance_to(now);
}

void Heaters::advance_to(double t) {
  hotend_.advance_to(t);
  bed_.advance_to(t);
}

void Heaters::set_hotend(double target, double now) {
  hotend_.set_target(std::clamp(target, 0.0, config_->max_hotend_temp));
  hotend_at_change_ = hotend_;
  update_runaway(now);
}

void Heaters::set_bed(double target) {
  bed_.set_target(std::clamp(target, 0.0, config_->max_bed_temp));
  bed_at_change_ = bed_;
}

void Heaters::all_off() {
  hotend_.set_target(0);
  bed_.set_target(0);
  hotend_at_change_ = hotend_;
  bed_at_change_ = bed_;
  runaway_at_ = kNever;
}

void Heaters::fail_hotend(double now) {
  hotend_.fail();
  update_runaway(now);
}

void Heaters::update_runaway(double now) {
  // Thermal protection: a failed heater that stays `hysteresis` below its target for
  // `period` seconds stops the printer.
  runaway_at_ = kNever;
  if (!hotend_.failed() || hotend_.target() <= config_->ambient) return;
  const double below = hotend_.target() - config_->runaway_hysteresis;
  const double from = hotend_.temperature() < below ? now : hotend_.time_reaching(below);
  runaway_at_ = from + config_->runaway_period;
}

double Heaters::start_wait(Which which, bool wait_for_cooling, double now) {
  const Heater& h = heater(which);
  const HeaterConstants& c = constants(which);
  const double target = h.target();
  const bool cooling = h.temperature() > target;
  if (cooling && !wait_for_cooling) return now;
  if (std::abs(h.temperature() - target) <= c.window) {
    residency_from_ = now;
  } else {
    residency_from_ = h.time_reaching(cooling ? target + c.window : target - c.window);
  }
  const double at_target = h.time_reaching(target);
  return std::max(at_target, residency_from_ + c.residency);
}

std::string Heaters::wait_report(Which which, double now) const {
  std::string w = "?";
  if (residency_from_ <= now) {
    const long left_ms = std::lround((constants(which).residency - (now - residency_from_)) * 1000);
    w = fmt::format("{}", left_ms / 1000);
  }
  return states() + " W:" + w;
}

double Heaters::settled_at(Which which, double band, double residency) const {
  const Heater& h = which == Which::hotend ? hotend_at_change_ : bed_at_change_;
  if (h.target() <= 0) return -kNever;
  const double off = h.temperature() - h.target();
  const double within = std::abs(off) < band ? h.time()
                        : off < 0            ? h.time_reaching(h.target() - band)
                                             : h.time_reaching(h.target() + band);
  return within + residency;
}

std::string Heaters::states() const {
  return fmt::format(" T:{:.2f} /{:.2f} B:{:.2f} /{:.2f} @:{} B@:{}", hotend_.temperature(),
                     hotend_.target(), bed_.temperature(), bed_.target(), hotend_.power(),
                     bed_.power());
}

}  // namespace sim
