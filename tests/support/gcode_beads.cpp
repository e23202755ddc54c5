#include "support/gcode_beads.h"

#include <cmath>
#include <cstdlib>

#include <fmt/core.h>
#include "geometry/core/clipper.h"
#include "printer/bead_model.h"
#include "printer/gcode_interpreter.h"
#include "printer/gcode_line.h"

namespace test_support {

double Bead::length() const { return std::hypot(to.x - from.x, to.y - from.y); }

PrintedProgram read_printed_program(std::string_view gcode, const BeadSettings& settings) {
  PrintedProgram program;
  printer::GcodeState state;
  bool chain_open = false;
  std::size_t line_number = 0;

  auto reach = [&](const printer::AxisPosition& at) {
    if (!state.homed) return;
    program.min_xy = {std::min(program.min_xy.x, at.x), std::min(program.min_xy.y, at.y)};
    program.max_xy = {std::max(program.max_xy.x, at.x), std::max(program.max_xy.y, at.y)};
    program.min_z = std::min(program.min_z, at.z);
    program.max_z = std::max(program.max_z, at.z);
  };
  // One extruding move: a bead of the current layer (none before the first: the start
  // G-code's prime line).
  auto lay = [&](const printer::Motion& move) {
    if (program.layers.empty()) return;
    PrintedLayer& layer = program.layers.back();
    const double z = move.to.z, de = move.to.e - move.from.e;
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
    bead.from = {move.from.x, move.from.y};
    bead.to = {move.to.x, move.to.y};
    bead.filament = de;
    bead.width = printer::bead_width(de, bead.length(), layer.height, settings.filament_diameter,
                                     settings.flow);
    if (!chain_open) {
      layer.chains.emplace_back();
      layer.chain_types.push_back(state.type);
    }
    layer.chains.back().push_back(bead);
    chain_open = true;
    layer.filament += de;
    program.filament += de;
  };

  while (!gcode.empty()) {
    const std::size_t end = gcode.find('\n');
    const std::string_view line = gcode.substr(0, end);
    gcode.remove_prefix(end == std::string_view::npos ? gcode.size() : end + 1);
    ++line_number;
    const printer::GcodeCommand c = printer::parse_gcode_line(line);
    const printer::GcodeStep step = printer::interpret(state, c);

    if (c.empty()) {
      if (step.layer_started) {
        PrintedLayer layer;
        layer.number = state.layer;
        program.layers.push_back(layer);
        chain_open = false;
      } else if (step.type_started) {
        if (!program.layers.empty()) program.layers.back().types.push_back(state.type);
        chain_open = false;
      } else if (program.layers.empty()) {
        const std::string& comment = c.comment;
        const std::size_t colon = comment.find(':');
        if (colon != std::string::npos && colon > 0 && comment.find(' ') > colon) {
          program.header[comment.substr(0, colon)] = comment.substr(colon + 1);
        }
      }
      continue;
    }
    if (step.homed) reach(printer::machine_position(state));
    if (step.count == 0) chain_open = false;
    for (const printer::Motion& move : step.moves()) {
      ++program.moves;
      reach(move.to);
      const double de = move.to.e - move.from.e;
      const bool moves_xy = move.to.x != move.from.x || move.to.y != move.from.y;
      if (printer::lays_filament(move)) {
        lay(move);
        continue;
      }
      chain_open = false;
      if (!moves_xy && de < 0 && move.to.z == move.from.z) ++program.retractions;
      if (moves_xy && de < 0) {
        program.problems.push_back(fmt::format("line {}: moves while retracting", line_number));
      }
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
