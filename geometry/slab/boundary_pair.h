// Boundary pairs of a slab's footprint (paper §3.3 step 1, Fig. 12-14).
//
// Input: the footprint of a slab (slab.h: the union of its faces' projections, grown by a
// 2 um margin), a valid Region in mm.
// Output: one BoundaryPair per island of the footprint: its outermost boundary (CCW) and its
// innermost boundaries (CW, the holes of the island). An island nested in a hole of another
// is a pair of its own. A cap, a feature that begins or ends inside the slab, is an island
// whose free faces (the parts of the plane just beside its loops, outside the footprint) are
// all solid or all empty: typically a pair with no inner boundary.
//
// A point beside a loop, outside the footprint, lies on no face of the slab, so the vertical
// line through it is inside the solid or outside it over the whole slab: any cross-section of
// the slab tells which. solid_beside reads that off a cross-section.
// Empty footprint: no pairs.
#pragma once

#include <vector>

#include "geometry/core/clipper.h"
#include "geometry/core/polygon.h"

namespace geometry {

struct BoundaryPair {
  Loop outer;               // CCW, the island's outermost boundary
  std::vector<Loop> inner;  // CW, its innermost boundaries, one per hole
};

std::vector<BoundaryPair> boundary_pairs(const Region& footprint);

// The same from the footprint's nesting as Clipper built it (slab.cpp), without a union.
std::vector<BoundaryPair> boundary_pairs(const ClipperLib::PolyTree& footprint);

// The pair's loops in the order the contour code numbers them: outer first, then inner.
std::vector<const Loop*> loops_of(const BoundaryPair& pair);

// For each loop (loops_of order): is the free face just outside the island beside it (for
// the outer loop) or inside the hole it bounds (inner loops) solid in `section`, a
// cross-section at any height strictly inside the slab? Decided by a majority of up to five
// of the loop's vertices, which lie at least the footprint margin away from the surface.
std::vector<char> solid_beside(const BoundaryPair& pair, const Region& section);

}  // namespace geometry
