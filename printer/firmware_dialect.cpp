#include "printer/firmware_dialect.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <iterator>

#include <fmt/core.h>

namespace printer {

namespace {

FirmwareDialect make_unknown() {
  FirmwareDialect d;
  d.firmware = Firmware::unknown;
  d.display = "an unrecognised firmware";
  return d;
}

FirmwareDialect make_marlin() {
  FirmwareDialect d;
  d.firmware = Firmware::marlin;
  d.name = "marlin";
  d.display = "Marlin";
  d.ok_means = OkMeans::executed;
  d.temperatures = TemperatureReply::on_ok;
  d.probe = LostOkProbe::skipped_number;
  d.has_m73 = true;
  d.emergency_m108_m410 = true;
  d.planner_depth = 15;
  return d;
}

FirmwareDialect make_teacup() {
  FirmwareDialect d;
  d.firmware = Firmware::teacup;
  d.name = "teacup";
  d.display = "Teacup";
  d.ok_means = OkMeans::executed;
  d.temperatures = TemperatureReply::before_ok;
  d.ok_after_resend = true;
  d.checks_line_numbers = false;
  d.probe = LostOkProbe::wrong_checksum;
  d.has_m400 = false;
  d.has_m107 = false;
  d.waits_with_m116 = true;
  d.autoreport_usable = false;
  d.planner_depth = 7;
  return d;
}

FirmwareDialect make_repetier() {
  FirmwareDialect d;
  d.firmware = Firmware::repetier;
  d.name = "repetier";
  d.display = "Repetier";
  d.ok_means = OkMeans::received;
  d.temperatures = TemperatureReply::after_ok;
  d.ok_after_resend = true;
  d.probe = LostOkProbe::same_line_again;
  d.has_m73 = true;
  d.planner_depth = 25;
  return d;
}

bool starts_with_nocase(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(s[i])) !=
        std::tolower(static_cast<unsigned char>(prefix[i]))) {
      return false;
    }
  }
  return true;
}

}  // namespace

const FirmwareDialect& dialect_of(Firmware firmware) {
  static const std::array<FirmwareDialect, 4> dialects{make_unknown(), make_marlin(),
                                                       make_teacup(), make_repetier()};
  return dialects[static_cast<std::size_t>(firmware)];
}

std::optional<Firmware> parse_firmware(std::string_view name) {
  for (const Firmware f : {Firmware::marlin, Firmware::teacup, Firmware::repetier}) {
    if (dialect_of(f).name == name) return f;
  }
  return std::nullopt;
}

std::string firmware_names() { return "marlin, teacup, repetier"; }

Firmware recognise_firmware(std::string_view name) {
  while (!name.empty() && name.front() == ' ') name.remove_prefix(1);
  if (starts_with_nocase(name, "Marlin") || starts_with_nocase(name, "Prusa-Firmware")) {
    return Firmware::marlin;
  }
  if (starts_with_nocase(name, "Teacup") || starts_with_nocase(name, "FiveD_on_Arduino")) {
    return Firmware::teacup;
  }
  if (starts_with_nocase(name, "Repetier")) return Firmware::repetier;
  return Firmware::unknown;
}

bool waits_for_moves(Firmware firmware, const GcodeCommand& c) {
  if (c.is('G', 4) || c.is('G', 28)) return true;
  switch (firmware) {
    case Firmware::teacup:  // gcode_process.c: queue_wait()
      return c.is('G', 92) || c.is('G', 161) || c.is('G', 162) || c.is('M', 0) || c.is('M', 2) ||
             c.is('M', 84);
    case Firmware::repetier:  // Commands.cpp: waitUntilEndOfAllMoves()
      return c.is('M', 400) || c.is('M', 109) || c.is('M', 190) || c.is('M', 116);
    case Firmware::marlin:  // planner.synchronize()
    case Firmware::unknown:
      return c.is('M', 400);
  }
  return false;
}

FirmwareCommand for_firmware(Firmware firmware, std::string_view command) {
  FirmwareCommand out;
  const GcodeCommand c = parse_gcode_line(command);
  if (firmware != Firmware::teacup) {
    out.lines.emplace_back(command);
    return out;
  }
  // Teacup's gcode_process.c process_gcode_command, in its default configuration.
  const auto s = c.get('S');
  if (c.is('M', 107)) {
    out.lines.emplace_back("M106 S0");
  } else if (c.is('M', 400)) {
    out.lines.emplace_back("G4 P0");
  } else if ((c.is('M', 109) || c.is('M', 190)) && s) {
    out.lines.push_back(fmt::format("{} S{:g}", c.code == 109 ? "M104" : "M140", *s));
    out.lines.emplace_back("M116");
  } else if (c.is('M', 18)) {
    out.lines.emplace_back("M84");
  } else {
    static constexpr int kG[] = {0, 1, 4, 20, 21, 28, 90, 91, 92, 161, 162};
    static constexpr int kM[] = {0,   2,   3,   5,   6,   7,   82,  83,  84,  101, 103, 104, 105,
                                 106, 110, 112, 114, 115, 116, 119, 140, 155, 220, 221};
    const auto has = [&](const auto& codes) {
      return std::find(std::begin(codes), std::end(codes), c.code) != std::end(codes);
    };
    const bool known = c.letter == 'T' || (c.letter == 'G' && has(kG)) || (c.letter == 'M' && has(kM));
    if (known) {
      out.lines.emplace_back(command);
    } else {
      out.missing = true;
    }
  }
  return out;
}

std::vector<std::string> heat_and_wait(Firmware firmware, double bed, double hotend) {
  std::vector<std::string> lines;
  if (bed > 0) lines.push_back(fmt::format("M140 S{:g}", bed));
  if (hotend > 0) lines.push_back(fmt::format("M104 S{:g}", hotend));
  if (dialect_of(firmware).waits_with_m116) {
    if (bed > 0 || hotend > 0) lines.emplace_back("M116");
    return lines;
  }
  if (bed > 0) lines.push_back(fmt::format("M190 S{:g}", bed));
  if (hotend > 0) lines.push_back(fmt::format("M109 S{:g}", hotend));
  return lines;
}

}  // namespace printer
