#include "geometry/core/point_in_region.h"

namespace geometry {

int winding_number(const Loop& loop, Vec2 p) {
  int w = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Vec2 a = loop[i], b = loop[i + 1 == n ? 0 : i + 1];
    // Wholly above or below p: the edge neither crosses p's ray nor holds p.
    if ((a.y < p.y && b.y < p.y) || (a.y > p.y && b.y > p.y)) continue;
    const double side = cross(b - a, p - a);
    if (side == 0 && distance_to_segment(p, a, b) == 0) {
      return signed_area(loop) >= 0 ? 1 : -1;
    }
    if (a.y <= p.y) {
      if (b.y > p.y && side > 0) ++w;
    } else if (b.y <= p.y && side < 0) {
      --w;
    }
  }
  return w;
}

bool point_in_region(const Region& region, Vec2 p) {
  int w = 0;
  for (const Loop& loop : region.loops) w += winding_number(loop, p);
  return w != 0;
}

namespace clipper {

bool point_in_region(const Paths& region, const IntPoint& p) {
  int winding = 0;
  for (const Path& loop : region) {
    const int at = ClipperLib::PointInPolygon(p, loop);
    if (at == -1) return true;
    if (at == 1) winding += ClipperLib::Orientation(loop) ? 1 : -1;
  }
  return winding != 0;
}

}  // namespace clipper

}  // namespace geometry
