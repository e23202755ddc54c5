// Plain value types for planar regions, in millimetres, and their basic measures.
//
// A Loop is a closed polygon: the edge from the last point back to the first is implied, and
// the first point is not repeated. A Region is a set of loops with the non-zero fill rule:
// outer boundaries counter-clockwise, holes clockwise, islands inside holes counter-clockwise
// again. An empty Region is the empty set; every function here accepts it.
#pragma once

#include <cmath>
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
// At least the loop's perimeter, mm: the sum of |dx| + |dy| over its edges, without a square
// root, for tests that nearly every loop passes against the bound.
double perimeter_bound(const Loop& loop);

// Distance from a point to the segment [a, b], mm.
double distance_to_segment(Vec2 p, Vec2 a, Vec2 b);

}  // namespace geometry
