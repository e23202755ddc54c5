// Explicit layer boundaries (`--boundaries FILE|z1,z2,...` on slice, print, analyze, advise):
// the layers of a part from the layer tops a user or another slicer chose
// (printer/layer_tops.h reads them).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "geometry/slicing/layer_stack.h"

namespace app {

struct BoundaryLayers {
  std::vector<geometry::Layer> layers;
  std::size_t above_part = 0;  // tops dropped: their layers start at or above the part's top
  double uncovered = 0;        // mm of the part above the last layer (0: all of it is covered)
  // What was left out, one line each: "--boundaries FILE: the layers end at 30 mm, 0.150 mm
  // below the part's top: that much of it is left out", "... 2 layer tops above ... left out".
  std::vector<std::string> notes;
};

// The layers of a part `part_height` mm tall (its bottom at z = 0) from the --boundaries
// argument. Layers that would start at or above the part's top are dropped (they would be
// empty). A stack may end below the part's top (a peer rounds its last layer down where we
// round up, or leaves out a tip too small to print) by less than `max_uncovered` mm (slice
// and print: the printer's thickest layer; analyze: any, it judges what the boundaries
// cover), reported in `uncovered` and `notes`; more is refused with ConfigError.
BoundaryLayers boundary_layers(const std::string& argument, double part_height,
                               double max_uncovered);

// "334 layers of 0.15 mm", or for a variable stack "212 layers, 0.15 to 0.4 mm thick".
std::string describe_layers(const std::vector<geometry::Layer>& layers);

}  // namespace app
