#include "sim/gcode_deposition.h"

#include "printer/gcode_line.h"

namespace sim {

DepositionRecord deposition_from_gcode(std::string_view program) {
  DepositionRecord record;
  double x = 0, y = 0, z = 0, e = 0, feedrate = 0, flow = 100;
  bool relative = false, relative_e = false;
  while (!program.empty()) {
    const std::size_t end = program.find('\n');
    const std::string_view line = program.substr(0, end);
    program.remove_prefix(end == std::string_view::npos ? program.size() : end + 1);
    const printer::GcodeCommand c = printer::parse_gcode_line(line);
    if (c.empty()) continue;
    if (c.letter == 'G' && (c.code == 0 || c.code == 1)) {
      const double x0 = x, y0 = y, e0 = e;
      if (auto v = c.get('X')) x = relative ? x + *v : *v;
      if (auto v = c.get('Y')) y = relative ? y + *v : *v;
      if (auto v = c.get('Z')) z = relative ? z + *v : *v;
      if (auto v = c.get('E')) e = relative_e ? e + *v : *v;
      if (auto f = c.get('F'); f && *f > 0) feedrate = *f / 60;
      const double fed = (e - e0) * flow / 100;
      if (fed > 0 && (x != x0 || y != y0)) record.add(z, {x0, y0}, {x, y}, fed, feedrate);
    } else if (c.letter == 'G') {
      switch (c.code) {
        case 28: {
          const bool all = !c.has('X') && !c.has('Y') && !c.has('Z');
          if (all || c.has('X')) x = 0;
          if (all || c.has('Y')) y = 0;
          if (all || c.has('Z')) z = 0;
          break;
        }
        case 90: relative = relative_e = false; break;
        case 91: relative = relative_e = true; break;
        case 92:
          if (auto v = c.get('X')) x = *v;
          if (auto v = c.get('Y')) y = *v;
          if (auto v = c.get('Z')) z = *v;
          if (auto v = c.get('E')) e = *v;
          break;
        default: break;
      }
    } else if (c.letter == 'M') {
      if (c.code == 82) relative_e = false;
      if (c.code == 83) relative_e = true;
      if (c.code == 221) {
        if (auto s = c.get('S'); s && *s > 0) flow = *s;
      }
    }
  }
  return record;
}

}  // namespace sim
