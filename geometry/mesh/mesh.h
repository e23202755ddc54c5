// Plain value types for triangle meshes, in millimetres.
//
// A Mesh is indexed: faces hold three vertex indices. After repair (see repair.h) its faces
// are oriented counter-clockwise seen from outside, so the right-hand normal points out.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace geometry {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// One facet as read from a file: three corners, no shared vertices.
struct Triangle {
  std::array<Vec3, 3> v;
};

struct Mesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> faces;
};

struct Box3 {
  Vec3 min, max;
};

// Axis-aligned bounds of the vertices a face uses. Empty mesh: min = max = origin.
Box3 bounding_box(const Mesh& mesh);

// Signed volume by the divergence theorem (positive for outward-oriented closed meshes), mm^3.
double signed_volume(const Mesh& mesh);

// Total surface area, mm^2.
double surface_area(const Mesh& mesh);

}  // namespace geometry
