// A job's checking pass over its G-code file and the printer's connect, at once: the first
// line waits for the longer of the two, not for both (mahost print and mahost resume).
#pragma once

#include <future>
#include <type_traits>
#include <utility>

namespace host {

// Runs `check` (reading and checking the file, printer::read_gcode_file) on a thread of its
// own while `connect` (opening the port and connecting the printer) runs on this one, and
// returns what check returns. A check that throws is what this throws, whatever connect did:
// only connect's own lines (M110, M115) went to the printer, nothing of the file. Else what
// connect threw.
template <typename Check, typename Connect>
std::invoke_result_t<Check> check_while_connecting(Check&& check, Connect&& connect) {
  std::future<std::invoke_result_t<Check>> checked = std::async(std::launch::async, std::forward<Check>(check));
  try {
    std::forward<Connect>(connect)();
  } catch (...) {
    checked.get();  // the file's refusal is the news, else what connect threw
    throw;
  }
  return checked.get();
}

}  // namespace host
