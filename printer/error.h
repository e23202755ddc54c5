// Errors printer/ throws. Each message is one line naming the file, key or port and saying
// what to do; host/ prints it and exits with the code DESIGN.md §5 gives for its kind.
#pragma once

#include <stdexcept>
#include <string>

namespace printer {

// A profile, G-code file or option value that cannot be used (exit code 2).
struct ConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The link to the printer failed: port missing, busy, vanished, or silent (exit code 3).
struct LinkError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The firmware stopped the job: halted, thermal runaway, kill() (exit code 3).
struct PrinterError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The firmware refused a command the print cannot go without (heating, waiting, homing): the
// message says what it refused, where the print stopped when that is known, and what to set
// in the printer profile (exit code 3).
struct CommandRefused : PrinterError {
  // `refusal`: "PORT: the printer refused CMD (\"REPLY\")"; `where`: "before anything was
  // extruded", "at layer 12/40 ...", or "" when the caller does not know; `advice`: what to do.
  CommandRefused(const std::string& refusal, const std::string& where, const std::string& advice)
      : PrinterError(refusal + ", so the print stopped" + (where.empty() ? "" : " " + where) + ": " + advice),
        refusal(refusal),
        advice(advice) {}
  std::string refusal, advice;
};

// The firmware stopped itself: kill() (a halt, thermal runaway, M112) or a reset. It turned its
// heaters off and reads nothing more until it is reset (exit code 3).
struct FirmwareStopped : PrinterError {
  using PrinterError::PrinterError;
};

}  // namespace printer
