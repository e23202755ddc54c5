// The errors out of the application layer that are the user's to fix, by the names a front end
// catches them by: host/ turns each into one line and an exit code without including a stage.
// printer::ConfigError (profiles, options, files that cannot be written) comes from
// printer/error.h, which host/ includes for the printer link anyway.
#pragma once

#include "geometry/core/error.h"

namespace app {

// A model file or a value the user gave that cannot be used (geometry/core/error.h).
using InputError = geometry::InputError;

}  // namespace app
