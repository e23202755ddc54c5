#include "geometry/mesh/mesh.h"

#include <algorithm>
#include <cmath>

namespace geometry {

Box3 bounding_box(const Mesh& mesh) {
  if (mesh.faces.empty()) return {};
  const Vec3& first = mesh.vertices[mesh.faces.front()[0]];
  Box3 box{first, first};
  for (const auto& face : mesh.faces) {
    for (std::uint32_t index : face) {
      const Vec3& p = mesh.vertices[index];
      box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
      box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
    }
  }
  return box;
}

double signed_volume(const Mesh& mesh) {
  // Sum of tetrahedra against the first vertex keeps the terms small for parts far from origin.
  if (mesh.faces.empty()) return 0;
  const Vec3 origin = mesh.vertices[mesh.faces.front()[0]];
  double six_volume = 0;
  for (const auto& face : mesh.faces) {
    const Vec3 a = mesh.vertices[face[0]] - origin;
    const Vec3 b = mesh.vertices[face[1]] - origin;
    const Vec3 c = mesh.vertices[face[2]] - origin;
    six_volume += dot(a, cross(b, c));
  }
  return six_volume / 6.0;
}

double surface_area(const Mesh& mesh) {
  double twice_area = 0;
  for (const auto& face : mesh.faces) {
    const Vec3 n = cross(mesh.vertices[face[1]] - mesh.vertices[face[0]],
                         mesh.vertices[face[2]] - mesh.vertices[face[0]]);
    twice_area += std::sqrt(dot(n, n));
  }
  return twice_area / 2.0;
}

}  // namespace geometry
