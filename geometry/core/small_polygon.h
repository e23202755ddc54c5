// A convex polygon of a few corners kept on the stack, cut by half-planes and intersected with
// another without allocating: the column integrals of a slab (slab_columns.h) and the
// optimal-height search (optimal_height.h) make such cuts millions of times a model, and a
// std::vector per cut cost them more than the arithmetic. The arithmetic is that of
// slab_columns.h's clip_to_half_plane and convex_intersection, operation for operation, so a
// result here is the same to the bit as theirs.
//
// A facet of a slab seen from above has at most 5 corners (a triangle cut by both planes);
// one cut adds at most one to a convex polygon, so an intersection of two facets has at most
// 10. A cut stops taking corners at kSmallCorners - 1 (rounding near a line can add more than
// convexity allows) and then reports that it did not finish.
// Units: whatever the caller's, mm here.
#pragma once

#include <vector>

#include "geometry/core/polygon.h"

namespace geometry {

inline constexpr int kSmallCorners = 16;

struct SmallPolygon {
  // Plain pairs, not Vec2: making a polygon leaves its unused corners unset.
  struct Corner {
    double x, y;
  };
  Corner at[kSmallCorners];
  int size = 0;
};

// The polygon's first kSmallCorners corners.
inline SmallPolygon small_polygon(const std::vector<Vec2>& polygon) {
  SmallPolygon out;
  for (Vec2 p : polygon) {
    if (out.size == kSmallCorners) break;
    out.at[out.size++] = {p.x, p.y};
  }
  return out;
}

// The part where f0 + fx (x - o.x) + fy (y - o.y) >= 0, into `out`; false when it stopped at
// kSmallCorners - 1 corners before the polygon's end.
inline bool cut_small(const SmallPolygon& polygon, Vec2 o, double f0, double fx, double fy,
                      SmallPolygon& out) {
  out.size = 0;
  const int n = polygon.size;
  if (n == 0) return true;
  const auto at = [&](SmallPolygon::Corner p) { return f0 + fx * (p.x - o.x) + fy * (p.y - o.y); };
  SmallPolygon::Corner a = polygon.at[0];
  double fa = at(a);
  int i = 0;
  for (; i < n && out.size < kSmallCorners - 1; ++i) {
    const SmallPolygon::Corner b = polygon.at[i + 1 == n ? 0 : i + 1];
    const double fb = at(b);
    if (fa >= 0) out.at[out.size++] = a;
    if ((fa >= 0) != (fb >= 0)) {
      const double s = fa / (fa - fb);
      out.at[out.size++] = {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y)};
    }
    a = b;
    fa = fb;
  }
  return i == n;
}

// The intersection with a convex counter-clockwise polygon `by`: cut by each of its edges'
// left half-planes in turn, until fewer than 3 corners are left. `complete` turns false where
// a cut did not finish.
inline SmallPolygon intersect_small(const SmallPolygon& polygon, const SmallPolygon& by,
                                    bool* complete = nullptr) {
  SmallPolygon buffer[2];
  const SmallPolygon* in = &polygon;
  bool finished = true;
  for (int k = 0, next = 0; k < by.size && in->size >= 3; ++k, next ^= 1) {
    const SmallPolygon::Corner p = by.at[k], q = by.at[k + 1 == by.size ? 0 : k + 1];
    finished = cut_small(*in, {p.x, p.y}, 0, -(q.y - p.y), q.x - p.x, buffer[next]) && finished;
    in = &buffer[next];
  }
  if (complete) *complete = finished;
  return *in;
}

// Signed area, as polygon.h's signed_area.
inline double small_signed_area(const SmallPolygon& polygon) {
  double twice = 0;
  for (int i = 0, n = polygon.size; i < n; ++i) {
    const SmallPolygon::Corner a = polygon.at[i], b = polygon.at[i + 1 == n ? 0 : i + 1];
    twice += cross(Vec2{a.x, a.y}, Vec2{b.x, b.y});
  }
  return twice / 2.0;
}

}  // namespace geometry
