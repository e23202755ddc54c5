#include "printer/firmware_dialect.h"

#include <array>
#include <cctype>

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
  return d;
}

FirmwareDialect make_teacup() {
  FirmwareDialect d;
  d.firmware = Firmware::teacup;
  d.name = "teacup";
  d.display = "Teacup";
  d.ok_means = OkMeans::received;
  d.temperatures = TemperatureReply::on_ok;
  d.ok_after_resend = false;
  d.probe = LostOkProbe::same_line_again;
  d.has_m400 = false;
  d.has_m107 = false;
  d.waits_with_m116 = true;
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
