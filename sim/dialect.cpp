#include "sim/dialect.h"

#include <array>
#include <cmath>

#include <fmt/core.h>

namespace sim {

namespace {

DialectTraits marlin_traits() {
  DialectTraits t;
  t.busy_keepalive = true;
  t.emergency_parser = true;
  t.reports_while_heating = true;
  t.wait_report_field = true;
  t.position_after_homing = true;
  return t;
}

DialectTraits teacup_traits() {
  DialectTraits t;
  t.ok_at = OkAt::start;
  t.output_on_ok_line = true;
  t.one_line_at_a_time = true;
  t.takes_skipped_numbers = true;
  t.requires_checksum = false;
  t.ok_after_resend = false;
  return t;
}

DialectTraits repetier_traits() {
  DialectTraits t;
  t.ok_at = OkAt::queued;
  t.requires_checksum = false;
  t.reports_while_heating = true;
  t.says_wait_when_idle = true;
  t.skips_after_resend = true;
  t.ok_after_resend = true;
  return t;
}

}  // namespace

std::optional<Dialect> parse_dialect(std::string_view name) {
  for (const Dialect d : {Dialect::marlin, Dialect::teacup, Dialect::repetier}) {
    if (to_string(d) == name) return d;
  }
  return std::nullopt;
}

std::string_view to_string(Dialect dialect) {
  switch (dialect) {
    case Dialect::marlin: return "marlin";
    case Dialect::teacup: return "teacup";
    case Dialect::repetier: return "repetier";
  }
  return "marlin";
}

std::string dialect_names() { return "marlin, teacup, repetier"; }

const DialectTraits& traits(Dialect dialect) {
  static const std::array<DialectTraits, 3> all{marlin_traits(), teacup_traits(), repetier_traits()};
  return all[static_cast<std::size_t>(dialect)];
}

std::vector<std::string> boot_banner(Dialect dialect, std::string_view marlin_version) {
  switch (dialect) {
    case Dialect::marlin:
      return {"start", fmt::format("echo:Marlin {}", marlin_version),
              "echo: Last Updated: 2021-12-25 | Author: (mahost simulated printer)"};
    case Dialect::teacup:
      return {"Start", "ok"};  // mendel.c: serial_writestr_P(PSTR("Start\nok\n"))
    case Dialect::repetier:
      return {"start", "External Reset", "Free RAM:3420"};
  }
  return {};
}

std::string firmware_report(Dialect dialect, std::string_view marlin_version) {
  switch (dialect) {
    case Dialect::marlin:
      return fmt::format(
          "FIRMWARE_NAME:Marlin {} (mahost simulated printer) "
          "SOURCE_CODE_URL:github.com/MarlinFirmware/Marlin PROTOCOL_VERSION:1.0 "
          "MACHINE_TYPE:mahost sim EXTRUDER_COUNT:1 UUID:cede2a2f-41a2-4748-9b12-c55c62f367ff",
          marlin_version);
    case Dialect::teacup:
      return "FIRMWARE_NAME:Teacup FIRMWARE_URL:http://github.com/traumflug/Teacup_Firmware/ "
             "PROTOCOL_VERSION:1.0 MACHINE_TYPE:Mendel EXTRUDER_COUNT:1 TEMP_SENSOR_COUNT:2 "
             "HEATER_COUNT:2";
    case Dialect::repetier:
      return "FIRMWARE_NAME:Repetier_1.0.3 FIRMWARE_URL:https://github.com/repetier/Repetier-Firmware/ "
             "PROTOCOL_VERSION:1.0 MACHINE_TYPE:Mendel EXTRUDER_COUNT:1 REPETIER_PROTOCOL:3";
  }
  return "";
}

bool knows(Dialect dialect, const printer::GcodeCommand& c) {
  if (dialect == Dialect::marlin) return true;  // the firmware's own switch decides
  if (dialect == Dialect::teacup) {
    if (c.letter == 'G') {
      switch (c.code) {
        case 0: case 1: case 4: case 20: case 21: case 28: case 90: case 91: case 92:
          return true;
        default:
          return false;
      }
    }
    if (c.letter == 'M') {
      switch (c.code) {
        case 0: case 2: case 82: case 83: case 84: case 104: case 105: case 106: case 110:
        case 112: case 114: case 115: case 116: case 140:
          return true;
        default:
          return false;
      }
    }
    return c.letter == 'T';
  }
  // Repetier: Marlin's commands but these; and it has M116.
  if (c.letter == 'M') {
    switch (c.code) {
      case 73: case 108: case 113: case 155: case 410: case 999:
        return false;
      default:
        return true;
    }
  }
  return true;
}

std::string unknown_reply(Dialect dialect, std::string_view text, const printer::GcodeCommand& c) {
  switch (dialect) {
    case Dialect::marlin:
      return fmt::format("echo:Unknown command: \"{}\"", text);
    case Dialect::teacup:
      if (c.letter == 'G') return fmt::format("E: Bad G-code {}", c.code);
      return fmt::format("E: Bad M-code {}", c.code);
    case Dialect::repetier:
      return fmt::format("Unknown command:{}", text);
  }
  return "";
}

std::vector<std::string> resend_request(Dialect dialect, std::string_view marlin_error,
                                        long expected, int checksum) {
  switch (dialect) {
    case Dialect::marlin:
      return {fmt::format("Error:{}{}", marlin_error, expected - 1), fmt::format("Resend: {}", expected)};
    case Dialect::teacup:
      if (marlin_error.starts_with("Line Number")) {
        return {fmt::format("rs N{} Expected line number {}", expected, expected)};
      }
      return {fmt::format("rs N{} Expected checksum {}", expected, checksum)};
    case Dialect::repetier:
      return {fmt::format("Resend:{}", expected)};
  }
  return {};
}

std::string position_reply(Dialect dialect, HeadPosition p, double feedrate, const double (&steps)[3]) {
  switch (dialect) {
    case Dialect::marlin:
      return fmt::format("X:{:.2f} Y:{:.2f} Z:{:.2f} E:{:.2f} Count X:{} Y:{} Z:{}", p.x, p.y, p.z,
                         p.e, std::lround(p.x * steps[0]), std::lround(p.y * steps[1]),
                         std::lround(p.z * steps[2]));
    case Dialect::teacup:
      return fmt::format("X:{:.3f},Y:{:.3f},Z:{:.3f},E:{:.3f},F:{:.0f}", p.x, p.y, p.z, p.e,
                         feedrate * 60);
    case Dialect::repetier:
      return fmt::format("X:{:.2f} Y:{:.2f} Z:{:.3f} E:{:.4f}", p.x, p.y, p.z, p.e);
  }
  return "";
}

std::string teacup_temperatures(double hotend, double bed) {
  return fmt::format("T:{:.1f} B:{:.1f}", hotend, bed);
}

}  // namespace sim
