// Pockets of the medial-axis contour (paper §3.4, "non-contributing points").
//
// A contributing sample is a corner of a mixed triangle (axis.h) inside the footprint: its
// Voronoi cell has an edge on the contour. A pocket is a connected set of same-side triangles
// inside the footprint (joined across their shared, unconstrained edges) holding samples that
// contribute nothing, with the mixed triangles at its mouths: the bottom of a groove, a neck
// or septum where two parts of one side merge inside the slab (a saddle), the lobe of a bump,
// a sharp corner. The axis does not come near those samples, so their distance to the walls
// can exceed every contributing sample's (the paper's Θ); ma_contour.cpp decides where the
// mid section serves them better (refine_pockets).
//
// Inside the footprint: the faces a walk from the infinite face reaches after crossing an odd
// number of constrained (boundary) edges (CGAL's polygon-with-holes triangulation example).
#pragma once

#include <span>
#include <vector>

#include "geometry/contour/ma/samples.h"
#include "geometry/contour/ma/triangulation.h"
#include "geometry/core/clipper.h"
#include "geometry/core/polygon.h"

namespace geometry::ma {

struct Pocket {
  // Its faces and mouths, CCW, on the nanometre grid: three corners a triangle, as paths
  // only where the mid section takes the pocket (triangles()).
  std::vector<ClipperLib::IntPoint> triangle_corners;
  std::vector<Vec2> corners;          // the same corners, mm
  std::vector<Vec2> non_contributing; // its samples that contribute nothing, mm, each once

  // The triangles as paths, added to `paths`.
  void add_triangles(ClipperLib::Paths& paths) const;
};

struct IslandPockets {
  std::vector<Vec2> contributing;  // every contributing sample of the island, mm
  std::vector<Pocket> pockets;
};

// Per face: 1 if it lies inside the footprint (never an infinite face).
std::vector<char> faces_inside(const SampleTriangulation& triangulation);

IslandPockets island_pockets(const SampleTriangulation& triangulation,
                             const std::vector<char>& labels, std::span<const Sample> samples);

}  // namespace geometry::ma
