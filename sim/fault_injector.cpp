#include "sim/fault_injector.h"

#include <limits>

#include "sim/serial_line.h"

namespace sim {

FaultInjector::FaultInjector(const FaultSpec& spec)
    : spec_(spec),
      rng_corrupt_(spec.seed * 4 + 0),
      rng_drop_(spec.seed * 4 + 1),
      rng_dup_(spec.seed * 4 + 2),
      rng_resend_(spec.seed * 4 + 3) {
  power_on();
}

void FaultInjector::power_on() { armed_ = !spec_.from_line; }

void FaultInjector::line_accepted(long number) {
  if (spec_.from_line && number >= *spec_.from_line) armed_ = true;
}

double FaultInjector::chance(std::mt19937_64& rng) {
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng);
}

// A digit becomes another digit (a number on the line changes and the line still reads as
// G-code); any other byte gets one bit flipped that the checksum is sure to catch
// (sim/faults.h), or stays c.
char FaultInjector::flipped(char c) {
  if (c >= '0' && c <= '9') {
    std::uniform_int_distribution<int> other(1, 9);
    return static_cast<char>('0' + (c - '0' + other(rng_corrupt_)) % 10);
  }
  std::uniform_int_distribution<int> bit(0, 7);
  for (int attempt = 0; attempt < 16; ++attempt) {
    const char f = static_cast<char>(c ^ (1 << bit(rng_corrupt_)));
    if (is_line_end(f) || f == ';' || f == '*' || f == '\b' || f == '\0' || f == '\\' ||
        f == 'N' || f == 'n') {
      continue;
    }
    return f;
  }
  return c;
}

int FaultInjector::corrupt(std::string& bytes) {
  int flips = 0;
  for (char& c : bytes) {
    const bool eol = is_line_end(c);
    const bool protected_byte = eol || c == ';' || c == '*' || c == '\b' || c == '\0' ||
                                c == '\\' || (wire_line_start_ && (c == 'N' || c == 'n'));
    if (armed_ && spec_.corrupt > 0 && !line_corrupted_ && !protected_byte &&
        chance(rng_corrupt_) < spec_.corrupt) {
      const char f = flipped(c);
      if (f != c) {
        c = f;
        line_corrupted_ = true;
        ++flips;
      }
    }
    if (eol) {
      line_corrupted_ = false;
      wire_line_start_ = true;
    } else if (c != ' ') {
      wire_line_start_ = false;
    }
  }
  return flips;
}

bool FaultInjector::drop_ok() {
  return armed_ && spec_.drop_ok > 0 && chance(rng_drop_) < spec_.drop_ok;
}

bool FaultInjector::drop_blocking_ok() {
  if (blocking_oks_dropped_ >= spec_.drop_blocking_ok) return false;
  ++blocking_oks_dropped_;
  return true;
}

bool FaultInjector::duplicate_ok() {
  return armed_ && spec_.dup_ok > 0 && chance(rng_dup_) < spec_.dup_ok;
}

bool FaultInjector::spurious_resend() {
  return armed_ && spec_.resend > 0 && chance(rng_resend_) < spec_.resend;
}

bool FaultInjector::disconnect_time_due(double now) {
  if (!spec_.disconnect_at_time || disconnect_time_done_ || now < *spec_.disconnect_at_time) {
    return false;
  }
  disconnect_time_done_ = true;
  return true;
}

double FaultInjector::next_disconnect_time() const {
  if (!spec_.disconnect_at_time || disconnect_time_done_) {
    return std::numeric_limits<double>::infinity();
  }
  return *spec_.disconnect_at_time;
}

}  // namespace sim
