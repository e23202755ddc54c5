#include "printer/print_state.h"

#include <cmath>
#include <string>
#include <vector>

#include <fmt/core.h>

namespace printer {

void apply(PrintState& s, const GcodeCommand& c) {
  if (c.letter == 'G') {
    switch (c.code) {
      case 0: case 1: case 2: case 3: {
        if (const auto f = c.get('F')) s.feedrate = *f;
        auto axis = [&](char letter, double& value, bool relative) {
          if (const auto v = c.get(letter)) value = relative ? value + *v : *v;
        };
        axis('X', s.x, s.relative_xyz);
        axis('Y', s.y, s.relative_xyz);
        axis('Z', s.z, s.relative_xyz);
        if (const auto e = c.get('E')) {
          const double before = s.e;
          s.e = s.relative_e ? s.e + *e : *e;
          s.filament_fed += s.e - before;  // retractions count back: the net feed
        }
        break;
      }
      case 28: {
        const bool all = !c.has('X') && !c.has('Y') && !c.has('Z');
        if (all || c.has('X')) s.x = 0;
        if (all || c.has('Y')) s.y = 0;
        if (all || c.has('Z')) s.z = 0;
        break;
      }
      case 90: s.relative_xyz = false; s.relative_e = false; break;
      case 91: s.relative_xyz = true; s.relative_e = true; break;
      case 92: {
        const bool none = !c.has('X') && !c.has('Y') && !c.has('Z') && !c.has('E');
        if (none) {
          s.x = s.y = s.z = s.e = 0;
        } else {
          if (const auto v = c.get('X')) s.x = *v;
          if (const auto v = c.get('Y')) s.y = *v;
          if (const auto v = c.get('Z')) s.z = *v;
          if (const auto v = c.get('E')) s.e = *v;
        }
        break;
      }
      default: break;
    }
    return;
  }
  if (c.letter == 'M') {
    switch (c.code) {
      case 82: s.relative_e = false; break;
      case 83: s.relative_e = true; break;
      case 104: case 109:
        if (const auto t = c.get('S')) {
          s.hotend_target = *t;
          s.hotend_target_set = true;
        }
        break;
      case 140: case 190:
        if (const auto t = c.get('S')) {
          s.bed_target = *t;
          s.bed_target_set = true;
        }
        break;
      case 106: s.fan = static_cast<int>(std::lround(c.get('S').value_or(255))); break;
      case 107: s.fan = 0; break;
      default: break;
    }
  }
}

void apply(PrintState& state, std::string_view command) { apply(state, parse_gcode_line(command)); }

std::vector<std::string> restore_modes(const PrintState& state) {
  std::vector<std::string> commands;
  commands.push_back(state.relative_xyz ? "G91" : "G90");
  commands.push_back(state.relative_e ? "M83" : "M82");
  if (state.feedrate > 0) commands.push_back(fmt::format("G1 F{}", state.feedrate));
  return commands;
}

}  // namespace printer
