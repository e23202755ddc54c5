// The one error geometry/ throws: a file or value the user gave that cannot be used.
//
// Geometry functions themselves are total (empty and degenerate input give defined output);
// InputError is for I/O and user input only. The message is one line that names the file or
// option and says what to do; host/ turns it into that line on stderr and exit code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace geometry {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace geometry
