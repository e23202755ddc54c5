// Checks of a value a user typed; see value_check.h.
#include "app/value_check.h"

#include <charconv>
#include <cmath>

#include <fmt/core.h>

namespace app {

std::string number_problem(const std::string& text, double lo, double hi, bool lo_excluded,
                           bool whole) {
  double value = 0;
  long integer = 0;
  const char* first = text.data();
  const char* last = text.data() + text.size();
  const auto [end, ec] = whole ? std::from_chars(first, last, integer) : std::from_chars(first, last, value);
  if (whole) value = static_cast<double>(integer);
  const bool in = ec == std::errc() && end == last && std::isfinite(value) &&
                  (lo_excluded ? value > lo : value >= lo) && value <= hi;
  if (in) return {};
  const std::string kind = whole ? "a whole number" : "a number";
  const std::string wanted =
      std::isinf(hi) ? fmt::format("{} {} {:g}", kind, lo_excluded ? "greater than" : "of at least", lo)
                     : fmt::format("{} from {:g} to {:g}", kind, lo, hi);
  return fmt::format("needs {}, not '{}'", wanted, text);
}

std::string choice_problem(const std::string& text, const std::vector<std::string>& choices,
                           const std::string& noun) {
  std::string list;
  for (const std::string& choice : choices) {
    if (text == choice) return {};
    list += (list.empty() ? "" : "|") + choice;
  }
  return fmt::format("'{}' is not {}; use one of {}", text, noun, list);
}

}  // namespace app
