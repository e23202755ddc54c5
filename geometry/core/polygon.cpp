#include "geometry/core/polygon.h"

#include <algorithm>
#include <cmath>

namespace geometry {

double signed_area(const Loop& loop) {
  double twice = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    twice += cross(loop[i], loop[(i + 1) % n]);
  }
  return twice / 2.0;
}

double area(const Region& region) {
  double total = 0;
  for (const Loop& loop : region.loops) total += signed_area(loop);
  return total;
}

double perimeter(const Loop& loop) {
  double length = 0;
  for (std::size_t i = 0, n = loop.size(); i < n && n > 1; ++i) {
    const Vec2 d = loop[(i + 1) % n] - loop[i];
    length += std::hypot(d.x, d.y);
  }
  return length;
}

double polyline_length(const std::vector<Vec2>& points) {
  double length = 0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    const Vec2 d = points[i] - points[i - 1];
    length += std::hypot(d.x, d.y);
  }
  return length;
}

double perimeter(const Region& region) {
  double length = 0;
  for (const Loop& loop : region.loops) length += perimeter(loop);
  return length;
}

double perimeter_bound(const Loop& loop) {
  double bound = 0;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    const Vec2 d = loop[i + 1 == n ? 0 : i + 1] - loop[i];
    bound += std::abs(d.x) + std::abs(d.y);
  }
  return bound;
}

Box2 bounding_box(std::span<const Vec2> points) {
  Box2 box;
  for (Vec2 p : points) box.add(p);
  return box;
}

AreaMoments moments_of_loop(const Loop& loop, Vec2 origin) {
  AreaMoments m;
  for (std::size_t i = 0, n = loop.size(); i < n; ++i) {
    add_edge_moments(m, loop[i] - origin, loop[(i + 1) % n] - origin);
  }
  return m;
}

}  // namespace geometry
