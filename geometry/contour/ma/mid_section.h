// Where the medial axis does not apply, the mid section (paper §3.3 is silent here; see
// ma_contour.h): the cross-section at the layer's middle, the least volume deviation a column
// can have (DESIGN.md §3), decided island by island.
//   - a vertical wall's strip (lower contour = upper contour, a ring a few margins wide) is
//     that section inside it, exactly, without a triangulation;
//   - a cap (every free face of the island solid, or every one empty: a feature beginning or
//     ending inside the slab) has a medial-axis tree, not a loop: the mid section inside the
//     island, or the section half-way through the feature's own height if the middle misses
//     it, so the feature is kept. (Walls midway between a cap's outline and its apex would
//     halve the distance error of a symmetric dome, but on the bunny's 33 caps they made 6
//     layers' D worse, up to 0.7 mm: tilted features whose apex sits at their edge, and 1
//     better.)
//   - a floating feature (a face of the mid section inside a strip that holds none of the
//     island's loops: the surface crosses the middle on a closed curve the boundary pair
//     cannot show, a bump or tail tip beginning inside the slab, a dip, the patches of a
//     nearly flat surface whose height wobbles round the middle, the bunny's hole-filled
//     base) keeps that face of the mid section; the rest of the island keeps its axis.
// Paths here are Clipper's (nanometre grid), to be added with positive winding.
#pragma once

#include <functional>

#include "geometry/contour/ma_contour.h"
#include "geometry/core/clipper.h"
#include "geometry/core/polygon.h"
#include "geometry/slab/boundary_pair.h"
#include "geometry/slab/slab.h"

namespace geometry::ma {

// A vertical wall's strip: one outer loop, one hole, every point of the ring within four
// footprint margins of both.
bool is_wall(const BoundaryPair& pair);

// The section's part inside the island's outline, as paths to add with positive winding:
// where the island is solid all round (solid_outside), the outline reversed takes that solid
// away first. `section` on Clipper's grid (to_clipper of the Region).
ClipperLib::Paths section_in_island(const ClipperLib::Paths& section, const BoundaryPair& pair,
                                    bool solid_outside);

// A cap's contour: the mid section `middle` (on Clipper's grid) inside it, or the section
// half-way through the feature's height range inside the slab where it does not reach the
// middle.
ClipperLib::Paths cap_contour(const Slab& slab, const BoundaryPair& pair, bool solid_outside,
                              const ClipperLib::Paths& middle,
                              const std::function<Region(double z)>& cross_section);

// Whether add_floating_features can find a feature in the island (a quick test on the mid
// section's loops, without the union that nests them).
bool may_float(const BoundaryPair& pair, const Region& middle);

// The island's floating features: faces of the mid section (`middle`, nested by Clipper)
// added to `zones` as paths of winding 1 inside; counted in stats->features.
void add_floating_features(const BoundaryPair& pair, const ClipperLib::PolyTree& middle,
                           ClipperLib::Paths& zones, MaStats* stats);

// `region` with the mid section taking its place inside `zone`: (region \ zone) ∪ (mid ∩ zone),
// in one Clipper operation, so that the parts meet exactly along the zone's edges.
Region mid_inside(const ClipperLib::Paths& region, const ClipperLib::Paths& all_middle,
                  const ClipperLib::Paths& zone);

}  // namespace geometry::ma
