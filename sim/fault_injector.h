// Where the simulated printer applies its faults (sim/faults.h): one object that owns the
// random streams and decides, at each point the firmware asks, whether a fault fires.
//
// One random stream per fault, seeded from the spec's seed, so enabling one fault does not
// move another's pattern. Faults given as a probability or a delay wait for from-line
// (armed()); the faults at a line or a time fire when the firmware reaches it.
#pragma once

#include <cstdint>
#include <random>
#include <string>

#include "sim/faults.h"

namespace sim {

class FaultInjector {
 public:
  explicit FaultInjector(const FaultSpec& spec);

  // The firmware restarted: from-line faults wait for their line again.
  void power_on();
  // The firmware accepted numbered line `number` (the host's numbering).
  void line_accepted(long number);
  bool armed() const { return armed_; }

  // corrupt=p: flips at most one bit per line of the host's bytes as they go onto the wire,
  // never in a byte Marlin's checksum cannot catch a change of; returns the flips made.
  int corrupt(std::string& bytes);
  // drop-ok=p: whether this ok is lost. dup-ok=p: whether it is sent twice.
  bool drop_ok();
  // drop-blocking-ok=N: whether the ok of this command, one that blocked, is lost.
  bool drop_blocking_ok();
  bool duplicate_ok();
  // resend=p: whether an intact numbered line is answered as a checksum error.
  bool spurious_resend();
  // delay=T: how much later every reply leaves.
  double reply_delay() const { return armed_ ? spec_.delay : 0.0; }

  // The faults at an accepted line (counted from 1 since power-on) or a time.
  bool ok_late_at(std::uint64_t line) const {
    return spec_.late_ok_at_line && line == *spec_.late_ok_at_line;
  }
  bool halts_at(std::uint64_t line) const { return spec_.halt_at_line && line == *spec_.halt_at_line; }
  bool fails_heater_at(std::uint64_t line) const {
    return spec_.runaway_at_line && line == *spec_.runaway_at_line;
  }
  bool freezes_at_line(std::uint64_t line) const {
    return spec_.freeze_at_line && line == *spec_.freeze_at_line;
  }
  bool disconnects_at_line(std::uint64_t line) const {
    return spec_.disconnect_at_line && line == *spec_.disconnect_at_line;
  }
  // disconnect-at-time=T, once: true the first time it is asked at or after T.
  bool disconnect_time_due(double now);
  // When disconnect-at-time fires, +infinity when it has or there is none.
  double next_disconnect_time() const;

  const FaultSpec& spec() const { return spec_; }

 private:
  double chance(std::mt19937_64& rng);
  char flipped(char c);

  FaultSpec spec_;
  std::mt19937_64 rng_corrupt_, rng_drop_, rng_dup_, rng_resend_;
  bool armed_ = true;
  bool line_corrupted_ = false;  // this line (as it crosses the wire) already has its flip
  bool wire_line_start_ = true;  // the next non-blank byte on the wire starts a line
  bool disconnect_time_done_ = false;
  std::uint64_t blocking_oks_dropped_ = 0;
};

}  // namespace sim
