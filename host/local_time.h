// The wall clock's local time as text, for log lines and file names.
#pragma once

#include <ctime>
#include <string>

namespace host {

// Now, formatted by strftime's `format` ("%H:%M:%S" gives "14:03:27").
inline std::string local_time(const char* format = "%H:%M:%S") {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char text[64];
  return std::strftime(text, sizeof text, format, &tm) > 0 ? text : "";
}

}  // namespace host
