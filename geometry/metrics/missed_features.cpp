#include "geometry/metrics/missed_features.h"

#include <cmath>
#include <limits>

#include "geometry/core/clipper.h"
#include "geometry/core/point_in_region.h"

namespace geometry {

namespace {

// Winding number of an island's loops around p, and p's distance to them.
int winding_of(const BoundaryPair& island, Vec2 p, double& clearance) {
  int winding = 0;
  clearance = std::numeric_limits<double>::infinity();
  for (const Loop* loop : loops_of(island)) {
    winding += winding_number(*loop, p);
    for (std::size_t i = 0, n = loop->size(); i < n; ++i) {
      clearance = std::min(clearance, distance_to_segment(p, (*loop)[i], (*loop)[(i + 1) % n]));
    }
  }
  return winding;
}

}  // namespace

std::vector<BoundaryPair> missed_features(const std::vector<BoundaryPair>& islands,
                                          const Region& region) {
  std::vector<BoundaryPair> missed;
  const ClipperLib::Paths walls = to_clipper(region);
  for (const BoundaryPair& island : islands) {
    // Quick yes: a vertex of the region well inside the island means their insides overlap
    // around it (a region's loop has area on one side of every vertex). Otherwise Clipper.
    bool touched = false;
    for (const Loop& loop : region.loops) {
      if (loop.empty()) continue;
      double clearance = 0;
      if (winding_of(island, loop[0], clearance) != 0 && clearance > 1e-3) {
        touched = true;
        break;
      }
    }
    if (touched) continue;
    double overlap = 0;
    if (!walls.empty()) {
      ClipperLib::Paths island_paths{to_clipper(island.outer)};
      for (const Loop& hole : island.inner) island_paths.push_back(to_clipper(hole));
      overlap = clipper::area_mm2(clipper::intersection(island_paths, walls));
    }
    if (!(std::abs(overlap) > kTouchArea)) missed.push_back(island);
  }
  return missed;
}

std::vector<BoundaryPair> missed_features(const Region& footprint, const Region& region) {
  return missed_features(boundary_pairs(footprint), region);
}

}  // namespace geometry
