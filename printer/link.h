// printer::Link: a byte stream to a printer's firmware, with timeouts (DESIGN.md §4).
//
// Implementations: SerialLink (libserialport: USB serial ports and pseudo-terminals) and
// SimLink (the in-process simulated printer, sim/sim_link.h). The host reads time only
// through now(), so against SimLink every timeout runs on the simulator's clock and tests are
// deterministic however fast the machine is.
#pragma once

#include <chrono>
#include <string>
#include <string_view>

namespace printer {

class Link {
 public:
  virtual ~Link() = default;

  // Sends all bytes. Throws LinkError when the link is gone.
  virtual void write(std::string_view bytes) = 0;

  // Returns the bytes that arrived, waiting at most `timeout` (on this link's clock) for the
  // first one; an empty string means nothing came. Throws LinkError when the link is gone.
  virtual std::string read(std::chrono::milliseconds timeout) = 0;

  // This link's clock: wall time for a serial port, simulated time for SimLink.
  virtual std::chrono::nanoseconds now() const = 0;

  // What to call this link in messages: "/dev/ttyUSB0", "simulated printer".
  virtual std::string name() const = 0;
};

}  // namespace printer
