// Reading a written G-code program back as a printer would lay it: per layer, the beads of
// filament (segment x width) rebuilt from the moves alone, for coverage and extrusion tests.
//
// The program is read by printer/gcode_interpreter.h's rules (Marlin's: modes, units, G92,
// G28, firmware retraction). Layers start at ";LAYER:<n>" comments; a layer's height is its Z minus the last
// layer's Z (its Z for the first). An extruding move (E grows while X/Y move) is a bead whose
// width comes from the bead model inverted: the filament it used over its length at the
// layer's height. Consecutive extruding moves form a chain; the chain's polygon is its centre
// line widened by half the width each side with round joins (closed chains as loops, open
// chains with square-cut ends), which is "segment x width" with the corners filled as the
// nozzle fills them. Where a chain's width changes (E rounding on short moves is enough), its
// pieces meet in a round joint. Units: mm.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/core/polygon.h"

namespace test_support {

struct BeadSettings {
  double filament_diameter = 1.75;
  double flow = 1.0;
};

struct Bead {
  geometry::Vec2 from, to;
  double width = 0;     // from the bead model
  double filament = 0;  // mm of filament this move used
  double length() const;
};

struct PrintedLayer {
  long number = -1;      // from ";LAYER:<n>"
  double z = 0;          // nozzle height while extruding
  double height = 0;     // z minus the previous layer's z
  std::vector<std::vector<Bead>> chains;  // consecutive extruding moves
  std::vector<std::string> chain_types;   // each chain's feature: the ";TYPE:" before it
  std::vector<std::string> types;         // ";TYPE:" comments, in order
  double filament = 0;
};

struct PrintedProgram {
  std::map<std::string, std::string> header;  // ";KEY:value" comments before the first layer
  std::vector<PrintedLayer> layers;
  // Every position a move reached, after the first G28 (the start G-code included).
  geometry::Vec2 min_xy{1e300, 1e300}, max_xy{-1e300, -1e300};
  double min_z = 1e300, max_z = -1e300;
  std::size_t moves = 0;
  std::size_t retractions = 0;   // moves that only pull filament back
  double filament = 0;           // extruded in layers' beads, mm
  std::vector<std::string> problems;  // anything a printer would not lay as planned
};

PrintedProgram read_printed_program(std::string_view gcode, const BeadSettings& settings = {});

// The union of a layer's beads as a Region (non-zero fill, outer CCW, holes CW); with `keep`,
// of the chains whose feature it keeps only.
geometry::Region bead_region(const PrintedLayer& layer);
geometry::Region bead_region(const PrintedLayer& layer,
                             const std::function<bool(const std::string& type)>& keep);

// How beads cover a region: the share of the region's area under beads, and the area of
// beads outside it as a share of the region's area.
struct Coverage {
  double covered = 0;  // area(beads ∩ region) / area(region)
  double outside = 0;  // area(beads \ region) / area(region)
};
Coverage coverage(const geometry::Region& beads, const geometry::Region& region);

}  // namespace test_support
