// Checks of command-line values that more than one command takes, as CLI11 validators whose
// message says what is allowed (main.cpp prints it as one line, exit code 2).
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "app/value_check.h"
#include "printer/serial_link.h"

namespace host {

// A finite number within [lo, hi] (or above lo where `above_lo`; a whole one where `whole`),
// said as a user reads it ("needs a number from 0 to 50, not '-3'", "needs a whole number
// from 1 to 32, not '0'"): CLI11's own Range prints its bounds with six decimals and
// PositiveNumber a bound of 308 digits, and both let "inf" through.
inline CLI::Validator number_check(double lo, double hi, bool above_lo, bool whole,
                                   const std::string& unit) {
  return CLI::Validator(
      [=](std::string& text) { return app::number_problem(text, lo, hi, above_lo, whole); }, unit);
}
inline CLI::Validator positive_number(const std::string& unit = "> 0") {
  return number_check(0, INFINITY, true, false, unit);
}
inline CLI::Validator non_negative_number(const std::string& unit = ">= 0") {
  return number_check(0, INFINITY, false, false, unit);
}
inline CLI::Validator number_in(double lo, double hi, const std::string& unit = {}) {
  return number_check(lo, hi, false, false, unit.empty() ? fmt::format("{:g}-{:g}", lo, hi) : unit);
}
inline CLI::Validator whole_number_in(long lo, long hi) {
  return number_check(static_cast<double>(lo), static_cast<double>(hi), false, true,
                      fmt::format("{}-{}", lo, hi));
}

// --baud: one of the standard serial speeds (printer::standard_baud_rates).
inline CLI::Validator standard_baud_rate() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        int rate = 0;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), rate);
        const auto& rates = printer::standard_baud_rates();
        if (ec == std::errc() && end == value.data() + value.size() &&
            std::find(rates.begin(), rates.end(), rate) != rates.end()) {
          return "";
        }
        return fmt::format("{} is not a serial speed; give one of {} (Marlin boards: usually "
                           "115200 or 250000)",
                           value, printer::standard_baud_rates_text());
      },
      "RATE");
}

}  // namespace host
