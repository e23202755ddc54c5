// Infill: the straight lines that fill the inside of a layer's walls.
//
// Inputs: the area to fill (mm, outer loops CCW, holes CW; the caller has already grown it
//         into the innermost wall by the infill overlap), the bead width w (mm), angles in
//         degrees from +X, the layer's index (angles alternate between even and odd layers).
// Outputs: open paths, unordered: the travel order (travel_order.h) picks their order and
//         direction. Separate lines are two-point paths, one per piece of line inside the
//         area. Connected lines (zigzag.h) run in the area shrunk by half a bead, joined end
//         to end by connectors along its edge, and a line end joined to nothing reaches on
//         by half a bead: the beads still fill the area out to its edge.
// Empty area, w <= 0 or density <= 0 give no paths.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"

namespace geometry {

enum class InfillPattern {
  rectilinear,  // parallel lines, the angle turning 90 degrees every layer
  grid,         // two crossing sets of lines in every layer (density split between them)
};

// Whether neighbouring lines are joined into zig-zags along the edge of the area (one path,
// no travel between them) or printed as separate lines.
enum class InfillLines { separate, connected };

std::string_view infill_pattern_name(InfillPattern pattern);  // "rectilinear", "grid"
std::optional<InfillPattern> parse_infill_pattern(std::string_view name);

// Lines `spacing` mm apart across the direction `angle`, on a grid fixed in the part's frame
// (a line passes through the origin), so the lines of layers with the same angle stack.
std::vector<ExtrusionPath> hatch(const Region& area, double spacing, double angle,
                                 PathRole role, double width);

// Sparse infill at `density` percent (0..100) of the area: total line length is about
// area * density / (100 * w). Rectilinear: one set of lines w*100/density apart, at `angle` on
// even layers and angle + 90 on odd ones. Grid: both directions on every layer, each set twice
// as far apart. Role sparse_infill. Connected lines are joined by connectors up to three
// spacings long (a wall meeting the lines at 20 degrees or more); a stretch of edge longer
// than that runs nearly along the lines, and tracing it would only double the wall there.
std::vector<ExtrusionPath> sparse_infill(const Region& area, double width, double density,
                                         InfillPattern pattern, double angle,
                                         std::size_t layer_index,
                                         InfillLines lines = InfillLines::connected);

// Lines under the edge of the skin above: where the layer above passes from solid infill to
// sparse (the edge of its sparse core, `core_above`) over this layer's sparse area `sparse`,
// a line along that edge (role sparse_infill, `width` wide), so that the skin's line ends
// there rest on it instead of hanging between this layer's sparse lines (CuraEngine's "skin
// edge support"). The edge inside `sparse` shrunk by half a bead, and where it runs on along
// the area's edge (into the band the shrinking leaves out) for up to a spacing of the layer
// below's sparse lines (density, pattern, angle, layer_index - 1 as sparse_infill lays them:
// their ends lie along the area's edge), so that its ends rest on something; the rest of a
// run along the area's edge is left out (it would double the wall), and so is a piece with
// less than two beads of its length inside the shrunk area. Pieces shorter than a bead are
// dropped. A whole loop is cut open where it crosses a sparse line of the layer
// below, so that it starts and ends on one (a loop started over the gap between them hangs
// there), and ends half a bead before it (its round ends then meet).
// Measured (compare_supports.sh's settings, best; unsupported extrusion by bench_unsupported,
// print time by the motion model), unsupported extrusion without these lines and with them:
// sphere 37.6 and 0.0 mm, dome 50.2 and 4.1, steps 34.3 and 8.0, bunny 175.9 and 75.2, vase
// 3.2 and 0.6; they add 0.8% to 1.2% to the print time.
std::vector<ExtrusionPath> skin_edge_lines(const Region& sparse, const Region& core_above,
                                           double width, double density, InfillPattern pattern,
                                           double angle, std::size_t layer_index);

// Solid infill (skins): lines at `angle` on even layers, angle + 90 on odd ones, spaced so
// that a whole number of lines spans the area across them (n = extent / w rounded, at least
// 1) and as wide as their spacing: a strip exactly n beads wide gets n lines edge to edge,
// and beads neither overlap nor leave gaps between them. Connected lines are joined by
// connectors up to two spacings long (an edge at 30 degrees or more to the lines; one closer
// to the lines is filled by the gap fill below). Then a centre line (of its own width, see
// thin_walls.h) along every strip the lines leave bare: where an edge of the area runs along
// the lines between two of them, at a corner too sharp for a bead, along unjoined ends.
// An island of the area nowhere 1.5 beads wide (a ring of skin inside a receding top's
// walls) gets no lines across: it is laid along its centre line as a thin wall (a ring in one
// closed path, as wide as it is), which crosses the sparse lines below where dashes across it
// would each end over the gaps between them. In solid infill (role solid_infill: inside the
// part, covered above and below), centre lines shorter than a bead (dabs in the notches of
// the zig-zag's turns) are left out: no one sees them, they hold nothing up, and on the
// lowest layer of a skin they hang between the sparse lines below.
// All paths get the given role (bottom_skin, top_skin, solid_infill).
std::vector<ExtrusionPath> solid_infill(const Region& area, double width, double angle,
                                        std::size_t layer_index, PathRole role,
                                        InfillLines lines = InfillLines::connected);

// Solid infill of an area made of pieces with different roles (bottom skin, top skin, solid
// infill, sparse infill at 100%): one set of lines spans them all as above, cut where they
// pass from one piece into another, so that the pieces' beads meet edge to edge instead of
// each piece's lines ending where they happen to. Each path takes the role of the piece it
// lies in (bare strips: the piece at their middle). Pieces must not overlap: a line where
// they do is laid once for each.
struct SolidPiece {
  Region area;
  PathRole role = PathRole::solid_infill;
};
std::vector<ExtrusionPath> solid_infill(const std::vector<SolidPiece>& pieces, double width,
                                        double angle, std::size_t layer_index,
                                        InfillLines lines = InfillLines::connected);

}  // namespace geometry
