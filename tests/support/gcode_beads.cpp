#include "support/gcode_beads.h"

#include <cmath>
#include <cstdlib>

#include <fmt/core.h>
#include "geometry/core/clipper.h"
#include "printer/bead_model.h"
#include "printer/gcode_line.h"

namespace test_support {

double Bead::length() const { return std::hypot(to.x - from.x, to.y - from.y); }

PrintedProgram read_printed_program(std::string_view gcode, const BeadSettings& settings) {
  PrintedProgram program;
  double x = 0, y = 0, z = 0, e = 0;
  bool relative_xyz = false, relative_e = false, homed = false;
  bool chain_open = false;
  std::string type;
  std::size_t line_number = 0;

  auto reach = [&]() {
    if (!homed) return;
    program.min_xy = {std::min(program.min_xy.x, x), std::min(program.min_xy.y, y)};
    program.max_xy = {std::max(program.max_xy.x, x), std::max(program.max_xy.y, y)};
    program.min_z = std::min(program.min_z, z);
    program.max_z = std::max(program.max_z, z);
  };

  while (!gcode.empty()) {
    const std::size_t end = gcode.find('\n');
    const std::string_view line = gcode.substr(0, end);
    gcode.remove_prefix(end == std::string_view::npos ? gcode.size() : end + 1);
    ++line_number;
    const printer::GcodeCommand c = printer::parse_gcode_line(line);

    if (c.empty()) {
      const std::string& comment = c.comment;
      if (comment.starts_with("LAYER:")) {
        PrintedLayer layer;
        layer.number = std::strtol(comment.c_str() + 6, nullptr, 10);
        program.layers.push_back(layer);
        chain_open = false;
      } else if (comment.starts_with("TYPE:")) {
        type = comment.substr(5);
        if (!program.layers.empty()) program.layers.back().types.push_back(type);
        chain_open = false;
      } else if (program.layers.empty()) {
        const std::size_t colon = comment.find(':');
        if (colon != std::string::npos && colon > 0 && comment.find(' ') > colon) {
          program.header[comment.substr(0, colon)] = comment.substr(colon + 1);
        }
      }
      continue;
    }
    if (c.letter == 'G' && (c.code == 0 || c.code == 1)) {
      const double x0 = x, y0 = y, e0 = e;
      if (auto v = c.get('X')) x = relative_xyz ? x + *v : *v;
      if (auto v = c.get('Y')) y = relative_xyz ? y + *v : *v;
      if (auto v = c.get('Z')) z = relative_xyz ? z + *v : *v;
      if (auto v = c.get('E')) e = relative_e ? e + *v : *v;
      ++program.moves;
      reach();
      const double de = e - e0;
      const bool moves_xy = x != x0 || y != y0;
      if (moves_xy && de > 0) {
        if (program.layers.empty()) continue;  // the start G-code's prime line
        PrintedLayer& layer = program.layers.back();
        if (layer.chains.empty()) {
          // Measured from the last layer below that laid something.
          double below = 0;
          for (std::size_t i = program.layers.size() - 1; i-- > 0;) {
            if (program.layers[i].filament > 0) {
              below = program.layers[i].z;
              break;
            }
          }
          layer.z = z;
          layer.height = z - below;
        } else if (std::abs(z - layer.z) > 1e-9) {
          program.problems.push_back(fmt::format("line {}: layer {} extrudes at z = {} and at {}",
                                                 line_number, layer.number, layer.z, z));
        }
        Bead bead;
        bead.from = {x0, y0};
        bead.to = {x, y};
        bead.filament = de;
        bead.width = printer::bead_width(de, bead.length(), layer.height,
                                         settings.filament_diameter, settings.flow);
        if (!chain_open) {
          layer.chains.emplace_back();
          layer.chain_types.push_back(type);
        }
        layer.chains.back().push_back(bead);
        chain_open = true;
        layer.filament += de;
        program.filament += de;
      } else {
        chain_open = false;
        if (!moves_xy && de < 0 && c.get('Z') == std::nullopt) ++program.retractions;
        if (moves_xy && de < 0) {
          program.problems.push_back(fmt::format("line {}: moves while retracting", line_number));
        }
      }
      continue;
    }
    chain_open = false;
    if (c.letter == 'G') {
      switch (c.code) {
        case 28: {
          const bool all = !c.has('X') && !c.has('Y') && !c.has('Z');
          if (all || c.has('X')) x = 0;
          if (all || c.has('Y')) y = 0;
          if (all || c.has('Z')) z = 0;
          homed = true;
          reach();
          break;
        }
        case 90: relative_xyz = relative_e = false; break;
        case 91: relative_xyz = relative_e = true; break;
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
    }
  }
  return program;
}

namespace {

// A disc of radius r about c, as a polygon within 2 um of the circle.
ClipperLib::Path disc(geometry::Vec2 c, double r) {
  const int sides = std::max(8, static_cast<int>(std::ceil(M_PI / std::acos(1 - 0.002 / r))));
  ClipperLib::Path path;
  for (int i = 0; i < sides; ++i) {
    const double a = 2 * M_PI * i / sides;
    path.push_back(geometry::to_clipper({c.x + r * std::cos(a), c.y + r * std::sin(a)}));
  }
  return path;
}

}  // namespace

geometry::Region bead_region(const PrintedLayer& layer) {
  return bead_region(layer, [](const std::string&) { return true; });
}

geometry::Region bead_region(const PrintedLayer& layer,
                             const std::function<bool(const std::string& type)>& keep) {
  ClipperLib::Paths all;
  for (std::size_t c = 0; c < layer.chains.size(); ++c) {
    if (!keep(layer.chain_types[c])) continue;
    const std::vector<Bead>& chain = layer.chains[c];
    // A chain of one width, split where the width changes by more than 1 um.
    std::size_t start = 0;
    while (start < chain.size()) {
      std::size_t stop = start + 1;
      while (stop < chain.size() && std::abs(chain[stop].width - chain[start].width) < 1e-3) ++stop;
      ClipperLib::Path path;
      path.push_back(geometry::to_clipper(chain[start].from));
      double width = 0, length = 0;
      for (std::size_t i = start; i < stop; ++i) {
        path.push_back(geometry::to_clipper(chain[i].to));
        width += chain[i].width * chain[i].length();
        length += chain[i].length();
      }
      width = length > 0 ? width / length : chain[start].width;
      const bool closed = path.size() > 3 && path.front() == path.back();
      if (closed) path.pop_back();
      const ClipperLib::Paths widened = geometry::clipper::library_offset(
          {path}, width / 2, ClipperLib::jtRound,
          closed ? ClipperLib::etClosedLine : ClipperLib::etOpenButt, 0.002);
      all.insert(all.end(), widened.begin(), widened.end());
      if (stop < chain.size()) {
        // The chain goes on at another width: the nozzle passes through this point, so the
        // pieces meet in a round joint, not in two square cuts with a wedge between them.
        const double joint = std::min(chain[stop - 1].width, chain[stop].width) / 2;
        all.push_back(disc(chain[stop].from, joint));
      }
      start = stop;
    }
  }
  ClipperLib::PolyTree tree;
  return geometry::from_clipper(geometry::clipper::union_nonzero_tree(all, tree));
}

Coverage coverage(const geometry::Region& beads, const geometry::Region& region) {
  const double region_area = geometry::area(region);
  if (!(region_area > 0)) return {};
  const ClipperLib::Paths laid = geometry::to_clipper(beads), target = geometry::to_clipper(region);
  return {geometry::clipper::area_mm2(geometry::clipper::intersection(laid, target)) / region_area,
          geometry::clipper::area_mm2(geometry::clipper::difference(laid, target)) / region_area};
}

}  // namespace test_support
