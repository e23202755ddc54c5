// Skins: which part of a layer's infill area is solid (top and bottom skins) and which
// sparse.
//
// A point of layer i needs solid infill unless the regions of the N layers above and of the
// N layers below all cover it (N = top_layers, bottom_layers); layers beyond either end of
// the stack cover nothing, so the first N and last N layers are solid.
// Skins can also be asked for as a thickness in mm (top_thickness, bottom_thickness), for
// stacks of layers of different thicknesses: N thin layers under a top surface would leave
// it thinner than N thick ones. Then a layer is solid under a top surface if its top is
// less than top_thickness below the surface, so the solid layers under it add up to at least
// top_thickness (and over a bottom surface alike); where both are given, the window is
// the larger of the two. On uniform layers of thickness t a thickness of N t is N layers.
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
// Tried and dropped: solid infill under the walls of the layer above (each core also inside
// the next layer's region shrunk by the walls' width, as PrusaSlicer's "ensure vertical
// shell thickness"), for the walls of a receding top (a dome's) that rest on less than half
// their width. The ring each layer then gets is itself over the sparse infill of the layer
// below it, one step further in, down to the top skins: unsupported extrusion by
// bench_unsupported (compare_supports.sh's settings, best) without that infill and with it,
// 64.5 and 80.1 mm on a sphere, 208 and 291 mm on the bunny; it costs 2.5% and 2.8% more
// filament, 6% and 7% more print time.
#pragma once

#include <optional>
#include <vector>

#include "geometry/core/polygon.h"
#include "geometry/slicing/layer_stack.h"

namespace geometry {

std::vector<std::optional<Region>> sparse_cores(const std::vector<Region>& regions,
                                                int top_layers, int bottom_layers);

// The same on layers of any thicknesses (layers[i] the bounds of regions[i]; as many layers as
// regions), with skins at least top_thickness and bottom_thickness mm thick as well as
// top_layers and bottom_layers layers. nullopt for every layer when all four are 0.
struct SkinDepth {
  int top_layers = 0, bottom_layers = 0;
  double top_thickness = 0, bottom_thickness = 0;  // mm
};
// With `wanted` (a flag per layer, as ToolpathOptions::planned: layers past its end, and all
// when it is empty, are wanted), only the wanted layers' cores are made, each the same as
// without it; the others are left an empty Region (a plan of a sample of the layers). The
// intersections are then only those the wanted windows need.
std::vector<std::optional<Region>> sparse_cores(const std::vector<Region>& regions,
                                                const std::vector<Layer>& layers,
                                                const SkinDepth& depth,
                                                const std::vector<char>& wanted = {});

struct Skins {
  Region bottom, top, solid, sparse;
};

Skins split_skins(const Region& area, const Region* core, const Region* below,
                  const Region* above, double width);

}  // namespace geometry
