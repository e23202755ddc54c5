// Skins: which part of a layer's infill area is solid and which sparse (issue 4,
// "Toolpaths": top and bottom skins).
//
// A point of layer i needs solid infill unless the regions of the N layers above and of the
// N layers below all cover it (N = top_layers, bottom_layers); layers beyond either end of
// the stack cover nothing, so the first N and last N layers are solid.
//
// sparse_cores: per layer, the intersection of regions[i-bottom .. i+top] (layer i's own
//   region included, which changes nothing inside it): where sparse infill may go. nullopt
//   when top_layers and bottom_layers are both 0 (no skins: everything may be sparse).
//   Regions in mm; empty input gives an empty vector. Costs log2(top + bottom + 1) + 1
//   intersections per layer.
// split_skins: one island's infill area (mm) split into
//   bottom: solid, and not over the layer below (`below`, nullptr when bottom_layers = 0);
//   top:    solid, not bottom, and not under the layer above (`above`, nullptr when
//           top_layers = 0);
//   solid:  the rest of the solid part (inside a skin's N layers, covered on both sides);
//   sparse: the area inside `core` (all of it when core is nullptr).
//   Solid pieces narrower than half a bead (the edge of a near-vertical wall moving by a few
//   microns between layers) are left to sparse infill, and bottom or top slivers to solid.
#pragma once

#include <optional>
#include <vector>

#include "geometry/core/polygon.h"

namespace geometry {

std::vector<std::optional<Region>> sparse_cores(const std::vector<Region>& regions,
                                                int top_layers, int bottom_layers);

struct Skins {
  Region bottom, top, solid, sparse;
};

Skins split_skins(const Region& area, const Region* core, const Region* below,
                  const Region* above, double width);

}  // namespace geometry
