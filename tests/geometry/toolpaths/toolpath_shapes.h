// Planar shapes with closed-form measures for the toolpath tests (mm).
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/core/polygon.h"
#include "geometry/toolpaths/toolpaths.h"

namespace toolpath_shapes {

using geometry::Loop;
using geometry::Region;
using geometry::Vec2;

inline Loop rectangle(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

inline Loop reversed(Loop loop) {
  std::reverse(loop.begin(), loop.end());
  return loop;
}

// Regular n-gon, CCW, vertex k at angle 2 pi k / n.
inline Loop circle(Vec2 centre, double radius, int sides = 256) {
  Loop loop;
  for (int k = 0; k < sides; ++k) {
    const double a = 2 * std::numbers::pi * k / sides;
    loop.push_back({centre.x + radius * std::cos(a), centre.y + radius * std::sin(a)});
  }
  return loop;
}

inline double length(const std::vector<Vec2>& points) {
  double total = 0;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const Vec2 d = points[i + 1] - points[i];
    total += std::hypot(d.x, d.y);
  }
  return total;
}

inline double length(const std::vector<geometry::ExtrusionPath>& paths) {
  double total = 0;
  for (const auto& p : paths) total += length(p.points);
  return total;
}

inline bool is_closed(const geometry::ExtrusionPath& path) {
  return path.points.size() > 2 && path.points.front() == path.points.back();
}

// The loop of a closed path (without its repeated last point).
inline Loop loop_of(const geometry::ExtrusionPath& path) {
  Loop loop(path.points.begin(), path.points.end());
  if (is_closed(path)) loop.pop_back();
  return loop;
}

}  // namespace toolpath_shapes
