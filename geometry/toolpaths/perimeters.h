// Perimeters: the wall loops of one island of a layer, and what they leave for infill.
//
// Input:  an island (mm): one outer loop CCW with the holes directly inside it, CW (a whole
//         Region works too); the bead width w (mm, > 0); the number of loops N (>= 0).
// Output: walls[k], the centre lines of loop k as closed paths (last point = first): loop 0
//         offset w/2 inward from the region's edge (role outer_wall, holes' loops included),
//         loop k offset w/2 + k*w (role inner_wall). Outer loops CCW, hole loops CW; seams
//         are chosen later (travel_order.h).
//         thin_walls: the gap fill (role thin_wall, their own width) of the strips where the
//         region or the space inside a loop is too narrow for the next loop (under 2 w: a
//         loop there would lay its two sides on top of each other), and of what a loop's
//         round bead leaves in corners sharper than it can follow: a centre line w/4 to
//         1.5 w wide, or where the strip is 1.5 to 2 w wide two beads side by side, each
//         half its width (thin_walls.h). So a wall narrower than two beads is still printed,
//         without beads laid on top of each other.
//         infill_area: what is left inside the innermost loop's bead (offset N*w inward from
//         the edge), where skins and infill go; infill reaches into it by its own overlap.
// Loops are offset with mitred corners (sharp corners stay sharp) by Clipper. Empty input,
// N = 0 or w <= 0 give no walls (and with N = 0 the whole island is infill_area).
#pragma once

#include <vector>

#include "geometry/core/clipper.h"
#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"

namespace geometry {

struct Perimeters {
  std::vector<std::vector<ExtrusionPath>> walls;  // walls[0] = outer wall loops
  std::vector<ExtrusionPath> thin_walls;
  Region infill_area;
};

Perimeters perimeters(const Region& island, double width, int count);

// The same for an island already clean: Clipper paths (clipper.h) of one outer loop
// and its holes as a Clipper union gives them (clipper.h: islands).
Perimeters perimeters(const ClipperLib::Paths& island, double width, int count);

}  // namespace geometry
