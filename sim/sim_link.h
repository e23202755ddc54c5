// sim::SimLink: printer::Link to an in-process simulated printer (DESIGN.md §1, §4).
//
// read(timeout) does not wait: it runs the simulator forward until a reply arrives or
// `timeout` has passed on the simulator's clock, so every host timeout is deterministic and a
// print of hours runs in seconds. With Config::time_scale > 0 it also sleeps the matching
// wall-clock time (1 = real time). On construction the board powers on and says `start`.
#pragma once

#include <chrono>
#include <string>
#include <string_view>

#include "printer/link.h"
#include "sim/printer.h"

namespace sim {

class SimLink : public printer::Link {
 public:
  explicit SimLink(Config config = {});

  // Throws printer::LinkError once a disconnect fault has fired (until reconnect()).
  void write(std::string_view bytes) override;
  std::string read(std::chrono::milliseconds timeout) override;
  std::chrono::nanoseconds now() const override;
  std::string name() const override;  // "simulated printer"

  // Plugs the printer back in after a disconnect (the board resets, says `start`).
  void reconnect();

  sim::Printer& printer() { return printer_; }
  const sim::Printer& printer() const { return printer_; }

 private:
  void throw_if_gone() const;
  sim::Printer printer_;
};

}  // namespace sim
