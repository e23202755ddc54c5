// Checks of command-line values that more than one command takes, as CLI11 validators whose
// message says what is allowed (main.cpp prints it as one line, exit code 2).
#pragma once

#include <algorithm>
#include <charconv>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "printer/serial_link.h"

namespace host {

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
