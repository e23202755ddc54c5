// The exact medial axis of a region: Boost.Polygon's Voronoi diagram of its edges (segment
// sites, exact predicates), the edges inside the region kept. The toolpaths' thin walls print
// along it (thin_walls.h).
//
// Sibling: contour/ma/ (ma_contour.h) builds the *sampled* medial axis of a slab's boundary
// pair, from the Delaunay triangulation of points on it (CGAL), as the paper does (§3.2.3).
// Both exist because they answer different questions. The contour needs the axis between two
// sets of loops labelled solid and empty (Observation 3.3.1: Voronoi edges between samples of
// different loops), closed loops only, with the triangulation's pockets for §3.4, and fairs
// it onto the exact axis of the loops afterwards; a segment diagram has no such labels and
// its parabolic arcs between a vertex and an edge would have to be sampled anyway. A thin
// wall needs the whole tree of the region's own axis with the inscribed radius at each node
// (the bead's width), exactly where the region is a few beads wide, from a few hundred edges
// per layer: the segment diagram gives both without sampling.
//
// Input: a region, mm (outer loops CCW, holes CW; near-duplicate points within 100 nm are
// merged first), no wider than 2^30 nm (1 m) either way (else: an empty axis).
// Output: a graph of axis points, each with its inscribed radius (its distance to the nearest
// edge), in nanometres from `origin` (the region's lower-left corner): the integer frame the
// diagram was built in. Its links are the primary Voronoi edges inside the region, except
//   - edges with an end farther than max_radius from the boundary (not a thin part);
//   - edges running into a corner (an end within 0.1 min_radius of the boundary), unless the
//     corner is sharper than 45 degrees (a tapering wall): then the edge is kept up to where
//     the radius falls to min_radius, and cut there.
// min_radius, max_radius in mm.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "geometry/core/polygon.h"

namespace geometry {

struct SegmentMedialAxis {
  Vec2 origin;                 // mm
  std::vector<Vec2> points;    // nm from origin
  std::vector<double> radius;  // nm, per point
  std::vector<std::pair<std::size_t, std::size_t>> links;  // between points
};

SegmentMedialAxis segment_medial_axis(const Region& region, double min_radius, double max_radius);

// Removes short leaf branches that stay inside the disc of the junction they hang from: they
// come from bumps of the boundary and add nothing a bead along the main line does not cover.
void prune_spurs(SegmentMedialAxis& axis);

// The axis as chains of point indices: between points that are not simple pass-throughs
// (ends, junctions), then the cycles left (first index = last).
std::vector<std::vector<std::size_t>> axis_chains(const SegmentMedialAxis& axis);

}  // namespace geometry
