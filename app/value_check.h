// Checks of a value a user typed, said as a user reads them: what the command line and the
// HTTP API both say of a number or a name out of place.
#pragma once

#include <string>
#include <vector>

namespace app {

// "" for a finite number within [lo, hi] (above lo where `lo_excluded`; a whole one where
// `whole`), else "needs a number from 0 to 50, not '-3'", "needs a whole number from 1 to 32,
// not '0'", "needs a number greater than 0, not 'inf'".
std::string number_problem(const std::string& text, double lo, double hi, bool lo_excluded,
                           bool whole);

// "" for one of `choices`, else "'cm' is not a unit; use one of m|mm|in" (`noun`: "a unit").
std::string choice_problem(const std::string& text, const std::vector<std::string>& choices,
                           const std::string& noun);

}  // namespace app
