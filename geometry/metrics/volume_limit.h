// The volume limit of a layer: the least volume deviation any extruded layer can have
// (DESIGN.md §3; the yardstick for paper §3.1's search). A prism R x [z_lo, z_hi] fills every
// column of R completely and leaves every other column empty, so column (x, y) costs
// t - occ(x, y) if it is in R and occ(x, y) if not (slab_columns.h). The best R fills a column
// iff the model fills at least half of it, and
//   limit = ∫ min(occ, t - occ) dx dy   over the slab's footprint, mm^3.
// No strategy can beat it: ΔV(R) - limit = 2 ∫ over the columns R gets "wrong" of
// |occ - t/2| >= 0.
//
// How it is computed, exactly: where a column meets one facet of the slab's surface, occ is
// that facet's height above z_lo (up-facing) or depth below z_hi (down-facing), so
// min(occ, t - occ) is the facet's own distance to the nearer slab plane; its integral over
// the facet splits at the line where the facet crosses the mid-plane. Columns that meet two
// or more facets lie where an up-facing and a down-facing facet overlap seen from above (a
// fold of the surface inside the slab: an equator, a lip); there the correction is summed by
// inclusion-exclusion over the sets of overlapping facets, each set's common part a convex
// polygon (facets are convex) on which the facets' vertical order is fixed, so occ is linear
// there and min(occ, t - occ) is integrated piecewise. Exact up to floating point (Clipper
// cells on a 1 pm grid agree to 1e-9 on every bunny layer, and take 3-6 times as long).
// A consequence worth knowing: away from folds the best region is exactly the mid-plane
// section, so mid-plane slicing reaches the limit on every layer without folds.
//
// Input: the slab's columns. Output: mm^3, >= 0. Empty slab: 0.
#pragma once

#include "geometry/slab/slab_columns.h"

namespace geometry {

double volume_limit(const SlabColumns& columns);

}  // namespace geometry
