// Blanks at the ends of a piece of text: the one trim of every text reader in mahost (ASCII
// STL, G-code lines and files, profiles and --set values, firmware replies, fault specs,
// control-socket requests).
#pragma once

#include <string_view>

namespace base {

// ASCII white space: space, tab, line feed, vertical tab, form feed, carriage return (what
// std::isspace takes in the C locale).
inline constexpr std::string_view kWhiteSpace = " \t\n\v\f\r";

// `s` without the characters of `blanks` at either end; "" when it holds nothing else.
constexpr std::string_view trim(std::string_view s, std::string_view blanks = kWhiteSpace) {
  const std::size_t first = s.find_first_not_of(blanks);
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(blanks) - first + 1);
}

}  // namespace base
