// Plain value types for planar regions, in millimetres, and their basic measures.
//
// A Loop is a closed polygon: the edge from the last point back to the first is implied, and
// the first point is not repeated. A Region is a set of loops with the non-zero fill rule:
// outer boundaries counter-clockwise, holes clockwise, islands inside holes counter-clockwise
// again. An empty Region is the empty set; every function here accepts it.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

namespace geometry {

struct Vec2 {
  double x = 0, y = 0;
};

inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline bool operator==(Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }
// mm: coordinates on a bed, no overflow to guard (std::hypot's care costs in inner loops).
inline double length(Vec2 v) { return std::sqrt(v.x * v.x + v.y * v.y); }

using Loop = std::vector<Vec2>;

struct Region {
  std::vector<Loop> loops;
};

// Shoelace area: positive for counter-clockwise loops, mm^2.
double signed_area(const Loop& loop);

// Net area of a region (outer loops minus holes), mm^2.
double area(const Region& region);

// Length of all loops, holes included, mm.
double perimeter(const Loop& loop);
double perimeter(const Region& region);
// Length of an open polyline, first point to last (no closing edge), mm.
double polyline_length(const std::vector<Vec2>& points);
// At least the loop's perimeter, mm: the sum of |dx| + |dy| over its edges, without a square
// root, for tests that nearly every loop passes against the bound.
double perimeter_bound(const Loop& loop);

// The point of the segment [a, b] nearest p, as its parameter t in [0, 1] from a (0 when
// a == b), and as a point.
inline double nearest_parameter(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double length2 = dot(ab, ab);
  return length2 > 0 ? std::clamp(dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
}
inline Vec2 foot_on_segment(Vec2 p, Vec2 a, Vec2 b) {
  return a + nearest_parameter(p, a, b) * (b - a);
}

// Distance from a point to the segment [a, b], squared and not: in the units of the points
// (mm for Regions; the toolpaths also ask it of Clipper's nanometres). Inline: the medial
// axis' fairing and the distance grids ask it millions of times per model.
inline double squared_distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a, ap = p - a;
  const double length2 = dot(ab, ab);
  const double t = length2 > 0 ? std::clamp(dot(ap, ab) / length2, 0.0, 1.0) : 0.0;
  const Vec2 d = ap - t * ab;
  return dot(d, d);
}
inline double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  return std::sqrt(squared_distance_to_segment(p, a, b));
}

// An axis-aligned bounding box; the default one is empty (lo above hi) and grows by add.
struct Box2 {
  Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  void add(Vec2 p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
  }
  bool empty() const { return !(lo.x <= hi.x); }
};
Box2 bounding_box(std::span<const Vec2> points);

// Area moments of a polygon about an origin, from its boundary (Green's theorem): the
// integrals of 1, x and y over it (AreaMoments), and of x^2, y^2 and xy (SecondMoments), mm^2
// to mm^4. Each directed edge p -> q (coordinates relative to the origin) adds its share;
// a loop's shares sum to its moments, positive for a counter-clockwise loop.
struct AreaMoments {
  double area = 0, mx = 0, my = 0;
};
struct SecondMoments : AreaMoments {
  double mxx = 0, myy = 0, mxy = 0;
};
inline void add_edge_moments(AreaMoments& m, Vec2 p, Vec2 q) {
  const double c = cross(p, q);
  m.area += c / 2;
  m.mx += c * (p.x + q.x) / 6;
  m.my += c * (p.y + q.y) / 6;
}
inline void add_edge_moments(SecondMoments& m, Vec2 p, Vec2 q) {
  add_edge_moments(static_cast<AreaMoments&>(m), p, q);
  const double c = cross(p, q);
  m.mxx += (p.x * p.x + p.x * q.x + q.x * q.x) * c / 12;
  m.myy += (p.y * p.y + p.y * q.y + q.y * q.y) * c / 12;
  m.mxy += (p.x * q.y + 2 * p.x * p.y + 2 * q.x * q.y + q.x * p.y) * c / 24;
}
AreaMoments moments_of_loop(const Loop& loop, Vec2 origin);

}  // namespace geometry
