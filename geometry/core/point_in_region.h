// Is a point inside a region: the non-zero winding rule, a point on a loop counting as
// inside. For loops in mm (polygon.h), and for Clipper paths on their nanometre grid.
// Empty region or loop: outside.
#pragma once

#include "geometry/core/clipper.h"
#include "geometry/core/polygon.h"

namespace geometry {

// Winding number of one closed loop around p (0 outside); a point on the loop gives 1 or -1
// (the loop's orientation).
int winding_number(const Loop& loop, Vec2 p);

// Is p inside `region` (non-zero winding)? Points on a loop count as inside.
bool point_in_region(const Region& region, Vec2 p);

namespace clipper {

// The same for paths: non-zero winding of their loops round p, a point on a path inside.
bool point_in_region(const Paths& region, const IntPoint& p);

}  // namespace clipper

}  // namespace geometry
