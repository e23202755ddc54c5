// Infill: the straight lines that fill the inside of a layer's walls (issue 4, "Toolpaths").
//
// Inputs: the area to fill (mm, outer loops CCW, holes CW; the caller has already grown it
//         into the innermost wall by the infill overlap), the bead width w (mm), angles in
//         degrees from +X, the layer's index (angles alternate between even and odd layers).
// Outputs: open two-point paths (one per piece of line inside the area), unordered: the
//         travel order (travel_order.h) picks their order and direction.
// Empty area, w <= 0 or density <= 0 give no paths.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "geometry/polygon.h"
#include "geometry/toolpaths.h"

namespace geometry {

enum class InfillPattern {
  rectilinear,  // parallel lines, the angle turning 90 degrees every layer
  grid,         // two crossing sets of lines in every layer (density split between them)
};

std::string_view infill_pattern_name(InfillPattern pattern);  // "rectilinear", "grid"
std::optional<InfillPattern> parse_infill_pattern(std::string_view name);

// Lines `spacing` mm apart across the direction `angle`, on a grid fixed in the part's frame
// (a line passes through the origin), so the lines of layers with the same angle stack.
std::vector<ExtrusionPath> hatch(const Region& area, double spacing, double angle,
                                 PathRole role, double width);

// Sparse infill at `density` percent (0..100) of the area: total line length is about
// area * density / (100 * w). Rectilinear: one set of lines w*100/density apart, at `angle` on
// even layers and angle + 90 on odd ones. Grid: both directions on every layer, each set twice
// as far apart. Role sparse_infill.
std::vector<ExtrusionPath> sparse_infill(const Region& area, double width, double density,
                                         InfillPattern pattern, double angle,
                                         std::size_t layer_index);

// Solid infill (skins): lines at `angle` on even layers, angle + 90 on odd ones, their spacing
// stretched from w so that a whole number of lines spans the area (a strip exactly n beads
// wide gets n lines edge to edge); then a centre line (of its own width, see thin_walls.h)
// along every strip the lines leave bare, where an edge of the area runs along the lines.
// All paths get the given role (bottom_skin, top_skin, solid_infill).
std::vector<ExtrusionPath> solid_infill(const Region& area, double width, double angle,
                                        std::size_t layer_index, PathRole role);

}  // namespace geometry
