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
  t.queue_depth = 1;
  t.planner_depth = 7;
  t.ok_after_resend = true;  // mendel.c: a line that drew "rs" still sets ack_waiting
  return t;
}

DialectTraits repetier_traits() {
  DialectTraits t;
  t.ok_at = OkAt::queued;
  t.queue_depth = 1;
  t.planner_depth = 24;
  t.reports_while_heating = true;
  t.says_wait_when_idle = true;
  t.ok_after_resend = true;  // gcode.cpp requestResend: "Resend:<n>" then "ok"
  return t;
}

// Teacup keeps temperatures in quarter degrees and prints "%u.%u" of the whole degrees and
// 25 times the quarters (temp.c single_temp_print): 20.0, 20.25, 20.50, 20.75.
std::string quarter_degrees(double celsius) {
  const long quarters = std::lround(std::max(celsius, 0.0) * 4);
  return fmt::format("{}.{}", quarters / 4, (quarters % 4) * 25);
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
      return {"start", "ok"};  // mendel.c init(): serial_writestr_P(PSTR("start\nok\n"))
    case Dialect::repetier:
      // Printer.cpp setup(): Com::tStart; HAL.cpp showStartReason() for a DTR reset.
      return {"start", "Info:External Reset", "Free RAM:3420"};
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
    case Dialect::teacup:  // gcode_process.c, M115
      return "FIRMWARE_NAME:Teacup FIRMWARE_URL:http://github.com/traumflug/Teacup_Firmware/ "
             "PROTOCOL_VERSION:1.0 MACHINE_TYPE:Mendel EXTRUDER_COUNT:1 TEMP_SENSOR_COUNT:2 "
             "HEATER_COUNT:2";
    case Dialect::repetier:  // Communication.cpp, Com::tFirmware
      return "FIRMWARE_NAME:Repetier_1.0.3 COMPILED:Aug  3 2022 "
             "FIRMWARE_URL:https://github.com/repetier/Repetier-Firmware/ PROTOCOL_VERSION:1.0 "
             "MACHINE_TYPE:Mendel EXTRUDER_COUNT:1 REPETIER_PROTOCOL:3";
  }
  return "";
}

printer::GcodeRules gcode_rules(Dialect dialect) {
  printer::GcodeRules rules;
  rules.e_relative_while_g91 = dialect != Dialect::marlin;
  rules.g92_bare_axis_is_zero = dialect == Dialect::teacup;
  return rules;
}

bool knows(Dialect dialect, const printer::GcodeCommand& c) {
  if (dialect == Dialect::marlin) return true;  // the firmware's own switch decides
  if (dialect == Dialect::teacup) {
    // gcode_process.c process_gcode_command, in the default configuration (no SD,
    // BED_LEVELING, EECONFIG or DEBUG).
    if (c.letter == 'G') {
      switch (c.code) {
        case 0: case 1: case 4: case 20: case 21: case 28: case 90: case 91: case 92: case 161:
        case 162:
          return true;
        default:
          return false;
      }
    }
    if (c.letter == 'M') {
      switch (c.code) {
        case 0: case 2: case 3: case 5: case 6: case 7: case 82: case 83: case 84: case 101:
        case 103: case 104: case 105: case 106: case 110: case 112: case 114: case 115:
        case 116: case 119: case 140: case 155: case 220: case 221:
          return true;
        default:
          return false;
      }
    }
    return c.letter == 'T';
  }
  // Repetier: Commands.cpp processGCode / processMCode; M110 and M112 are taken when the line
  // is read (gcode.cpp checkAndPushCommand).
  if (c.letter == 'G') {
    switch (c.code) {
      case 0: case 1: case 2: case 3: case 4: case 10: case 11: case 20: case 21: case 28:
      case 29: case 30: case 31: case 32: case 33: case 90: case 91: case 92: case 100:
      case 131: case 132: case 133: case 134: case 135: case 201: case 202: case 203: case 204:
      case 205:
        return true;
      default:
        return false;
    }
  }
  if (c.letter == 'M') {
    switch (c.code) {
      case 3: case 4: case 5: case 17: case 18: case 20: case 21: case 22: case 23: case 24:
      case 25: case 26: case 27: case 28: case 29: case 30: case 32: case 36: case 42: case 73:
      case 80: case 81: case 82: case 83: case 84: case 85: case 92: case 99: case 104:
      case 105: case 106: case 107: case 108: case 109: case 110: case 111: case 112: case 114:
      case 115: case 116: case 117: case 118: case 119: case 140: case 155: case 190: case 201:
      case 202: case 203: case 204: case 205: case 206: case 207: case 209: case 220:
      case 221: case 226: case 280: case 281: case 290: case 300: case 302: case 303: case 400:
      case 401: case 402: case 500: case 501: case 502: case 600: case 999:
        return true;
      default:
        return false;
    }
  }
  return c.letter == 'T';
}

std::string unknown_reply(Dialect dialect, std::string_view text, const printer::GcodeCommand& c,
                          std::optional<long> line_number) {
  switch (dialect) {
    case Dialect::marlin:
      return fmt::format("echo:Unknown command: \"{}\"", text);
    case Dialect::teacup:  // gcode_process.c: "E: Bad G-code %d" / "E: Bad M-code %d"
      if (c.letter == 'G') return fmt::format("E: Bad G-code {}", c.code);
      return fmt::format("E: Bad M-code {}", c.code);
    case Dialect::repetier: {
      // Commands.cpp: Com::tUnknownCommand and GCode::printCommand: "N<n> M<m>  S<s>".
      std::string reply = "Unknown command:";
      if (line_number) reply += fmt::format("N{} ", *line_number);
      if (c.letter != 0) reply += fmt::format("{}{} ", c.letter, c.code);
      for (const char word : {'X', 'Y', 'Z'}) {
        if (const auto v = c.get(word)) reply += fmt::format(" {}{:.2f}", word, *v);
      }
      if (const auto e = c.get('E')) reply += fmt::format(" E{:.4f}", *e);
      if (const auto f = c.get('F')) reply += fmt::format(" F{:.2f}", *f);
      for (const char word : {'S', 'P'}) {
        if (const auto v = c.get(word)) reply += fmt::format(" {}{}", word, std::lround(*v));
      }
      return reply;
    }
  }
  return "";
}

std::string position_reply(Dialect dialect, HeadPosition p, double feedrate, const double (&steps)[3]) {
  switch (dialect) {
    case Dialect::marlin:
      return fmt::format("X:{:.2f} Y:{:.2f} Z:{:.2f} E:{:.2f} Count X:{} Y:{} Z:{}", p.x, p.y, p.z,
                         p.e, std::lround(p.x * steps[0]), std::lround(p.y * steps[1]),
                         std::lround(p.z * steps[2]));
    case Dialect::teacup:  // gcode_process.c M114: "X:%lq,Y:%lq,Z:%lq,E:%lq,F:%lu"
      return fmt::format("X:{:.3f},Y:{:.3f},Z:{:.3f},E:{:.3f},F:{:.0f}", p.x, p.y, p.z, p.e,
                         feedrate * 60);
    case Dialect::repetier: {  // Commands.cpp printCurrentPosition: times 0.03937 after G20
      const double unit = p.inches ? 0.03937 : 1;
      return fmt::format("X:{:.2f} Y:{:.2f} Z:{:.3f} E:{:.4f}", p.x * unit, p.y * unit, p.z * unit,
                         p.e * unit);
    }
  }
  return "";
}

std::string teacup_temperatures(const HeaterReadings& r) {
  return fmt::format("T:{}/{} B:{}/{}", quarter_degrees(r.hotend), quarter_degrees(r.hotend_target),
                     quarter_degrees(r.bed), quarter_degrees(r.bed_target));
}

std::string repetier_temperatures(const HeaterReadings& r) {
  return fmt::format("T:{:.2f} /{:.0f} B:{:.2f} /{:.0f} B@:{} @:{}", r.hotend, r.hotend_target, r.bed,
                     r.bed_target, r.bed_power, r.hotend_power);
}

}  // namespace sim
