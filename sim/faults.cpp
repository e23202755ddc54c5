#include "sim/faults.h"

#include <charconv>
#include <cmath>
#include <string>

#include <fmt/core.h>

#include "base/text.h"
#include "printer/error.h"

namespace sim {

namespace {

using base::trim;

constexpr std::string_view kKeys =
    "corrupt, drop-ok, drop-blocking-ok, dup-ok, resend, delay, disconnect-at-line, "
    "disconnect-at-time, late-ok-at-line, halt-at-line, freeze-at-line, runaway-at-line, from-line, seed";

[[noreturn]] void bad(std::string_view key, std::string_view value, std::string_view what) {
  throw printer::ConfigError(
      fmt::format("fault spec '{}={}': {}", key, value, what));
}

// A number in full (no trailing text); nullopt otherwise.
std::optional<double> number(std::string_view text) {
  double value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

double probability(std::string_view key, std::string_view value) {
  const auto p = number(value);
  if (!p || *p < 0 || *p > 1) bad(key, value, "give a probability from 0 to 1, e.g. 0.01");
  return *p;
}

// "50ms", "60s", "2min" -> seconds.
double duration(std::string_view key, std::string_view value) {
  struct Unit {
    std::string_view suffix;
    double seconds;
  };
  for (const Unit unit : {Unit{"ms", 1e-3}, Unit{"min", 60}, Unit{"s", 1}}) {
    if (value.size() > unit.suffix.size() && value.ends_with(unit.suffix)) {
      const auto n = number(value.substr(0, value.size() - unit.suffix.size()));
      if (!n || *n < 0) break;
      return *n * unit.seconds;
    }
  }
  bad(key, value, "give a time of 0 or more with its unit, e.g. 50ms, 60s or 2min");
}

std::uint64_t count(std::string_view key, std::string_view value, std::uint64_t least) {
  std::uint64_t n = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
  if (ec != std::errc() || end != value.data() + value.size() || n < least) {
    bad(key, value, fmt::format("give a whole number of {} or more", least));
  }
  return n;
}

std::string seconds_text(double s) {
  if (s != 0 && s < 1) return fmt::format("{:g}ms", s * 1e3);
  return fmt::format("{:g}s", s);
}

}  // namespace

bool FaultSpec::any() const {
  return corrupt > 0 || drop_ok > 0 || drop_blocking_ok > 0 || dup_ok > 0 || resend > 0 || delay > 0 ||
         disconnect_at_line || disconnect_at_time || late_ok_at_line || halt_at_line || freeze_at_line || runaway_at_line;
}

FaultSpec parse_fault_spec(std::string_view spec) {
  FaultSpec faults;
  while (!spec.empty()) {
    const auto comma = spec.find(',');
    const std::string_view item = trim(spec.substr(0, comma));
    spec = comma == std::string_view::npos ? std::string_view{} : spec.substr(comma + 1);
    if (item.empty()) continue;
    const auto equals = item.find('=');
    if (equals == std::string_view::npos) {
      throw printer::ConfigError(fmt::format(
          "fault spec '{}': write key=value, e.g. corrupt=0.01 (keys: {})", item, kKeys));
    }
    const std::string_view key = trim(item.substr(0, equals));
    const std::string_view value = trim(item.substr(equals + 1));
    if (key == "corrupt") {
      faults.corrupt = probability(key, value);
    } else if (key == "drop-ok") {
      faults.drop_ok = probability(key, value);
    } else if (key == "drop-blocking-ok") {
      faults.drop_blocking_ok = count(key, value, 0);
    } else if (key == "dup-ok") {
      faults.dup_ok = probability(key, value);
    } else if (key == "resend") {
      faults.resend = probability(key, value);
    } else if (key == "delay") {
      faults.delay = duration(key, value);
    } else if (key == "disconnect-at-line") {
      faults.disconnect_at_line = count(key, value, 1);
    } else if (key == "disconnect-at-time") {
      faults.disconnect_at_time = duration(key, value);
    } else if (key == "late-ok-at-line") {
      faults.late_ok_at_line = count(key, value, 1);
    } else if (key == "halt-at-line") {
      faults.halt_at_line = count(key, value, 1);
    } else if (key == "freeze-at-line") {
      faults.freeze_at_line = count(key, value, 1);
    } else if (key == "runaway-at-line") {
      faults.runaway_at_line = count(key, value, 1);
    } else if (key == "from-line") {
      faults.from_line = static_cast<long>(count(key, value, 0));
    } else if (key == "seed") {
      faults.seed = count(key, value, 0);
    } else {
      throw printer::ConfigError(
          fmt::format("fault spec: unknown fault '{}' (known: {})", key, kKeys));
    }
  }
  return faults;
}

std::string to_string(const FaultSpec& f) {
  std::string out;
  const auto add = [&](const std::string& item) {
    if (!out.empty()) out += ',';
    out += item;
  };
  if (f.corrupt > 0) add(fmt::format("corrupt={:g}", f.corrupt));
  if (f.drop_ok > 0) add(fmt::format("drop-ok={:g}", f.drop_ok));
  if (f.drop_blocking_ok > 0) add(fmt::format("drop-blocking-ok={}", f.drop_blocking_ok));
  if (f.dup_ok > 0) add(fmt::format("dup-ok={:g}", f.dup_ok));
  if (f.resend > 0) add(fmt::format("resend={:g}", f.resend));
  if (f.delay > 0) add("delay=" + seconds_text(f.delay));
  if (f.disconnect_at_line) add(fmt::format("disconnect-at-line={}", *f.disconnect_at_line));
  if (f.disconnect_at_time) add("disconnect-at-time=" + seconds_text(*f.disconnect_at_time));
  if (f.late_ok_at_line) add(fmt::format("late-ok-at-line={}", *f.late_ok_at_line));
  if (f.halt_at_line) add(fmt::format("halt-at-line={}", *f.halt_at_line));
  if (f.freeze_at_line) add(fmt::format("freeze-at-line={}", *f.freeze_at_line));
  if (f.runaway_at_line) add(fmt::format("runaway-at-line={}", *f.runaway_at_line));
  if (f.from_line) add(fmt::format("from-line={}", *f.from_line));
  if (f.any()) add(fmt::format("seed={}", f.seed));
  return out;
}

}  // namespace sim
