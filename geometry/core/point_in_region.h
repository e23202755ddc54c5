// Is a point inside a region: the non-zero winding rule, a point on a loop counting as
// inside. For loops in mm (polygon.h), and for Clipper paths on their nanometre grid.
// Empty region or loop: outside.
#pragma once

#include <cstdint>
#include <vector>

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

// point_in_region for many points of one region: its edges sorted once into horizontal
// bands, so that a point meets only the edges that reach its height. The same answer for
// every point: an edge wholly above or below p changes nothing in ClipperLib::PointInPolygon,
// and what the others do (p on one, or the loop's crossings toggled) does not depend on
// their order. Holds a copy of the edges; an empty region contains nothing.
class PointsInRegion {
 public:
  explicit PointsInRegion(const Paths& region);
  bool contains(const IntPoint& p) const;

 private:
  struct Edge {
    IntPoint from, to;
    std::uint32_t loop;
  };
  std::vector<Edge> edges_;                // by band, and in each band by loop
  std::vector<std::uint32_t> band_start_;  // band b's edges: [band_start_[b], band_start_[b + 1])
  std::vector<int> winding_;               // each loop's winding round a point inside it
  ClipperLib::cInt y_low_ = 0, y_span_ = 1;  // the loops' lowest y, and the height they span + 1

  std::size_t band(ClipperLib::cInt y) const;
};

}  // namespace clipper

}  // namespace geometry
