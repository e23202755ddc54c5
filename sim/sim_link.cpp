#include "sim/sim_link.h"

#include <cmath>
#include <thread>

#include <fmt/core.h>

#include "printer/error.h"

namespace sim {

SimLink::SimLink(Config config) : printer_(std::move(config)) {}

void SimLink::throw_if_gone() const {
  if (printer_.state() == PrinterState::disconnected) {
    throw printer::LinkError(fmt::format("{}: the link is gone: {}; reconnect the printer",
                                         name(), printer_.stop_reason()));
  }
}

void SimLink::write(std::string_view bytes) {
  throw_if_gone();
  printer_.receive(bytes);
}

std::string SimLink::read(std::chrono::milliseconds timeout) {
  throw_if_gone();
  const double start = printer_.now();
  const double deadline = start + std::max<double>(static_cast<double>(timeout.count()), 0.0) / 1e3;
  printer_.run_until_output(deadline);
  const double scale = printer_.config().time_scale;
  if (scale > 0) {
    const double wall = (printer_.now() - start) / scale;
    std::this_thread::sleep_for(std::chrono::duration<double>(wall));
  }
  std::string bytes = printer_.take_output();
  // A disconnect while waiting: what arrived before it is lost with the link.
  throw_if_gone();
  return bytes;
}

std::chrono::nanoseconds SimLink::now() const {
  return std::chrono::nanoseconds(std::llround(printer_.now() * 1e9));
}

std::string SimLink::name() const { return "simulated printer"; }

void SimLink::reconnect() { printer_.reconnect(); }

}  // namespace sim
