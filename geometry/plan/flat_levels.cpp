#include "geometry/plan/flat_levels.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace geometry {

std::vector<FlatLevel> flat_levels(const Mesh& mesh, double min_area) {
  std::vector<std::pair<double, double>> flat;  // (height, area) of each horizontal facet
  for (const auto& face : mesh.faces) {
    const Vec3 a = mesh.vertices[face[0]], b = mesh.vertices[face[1]], c = mesh.vertices[face[2]];
    const double low = std::min({a.z, b.z, c.z}), high = std::max({a.z, b.z, c.z});
    if (!(high - low <= kFlatHeightTolerance)) continue;
    const Vec3 n = cross(b - a, c - a);
    const double area = 0.5 * std::abs(n.z);
    if (area > 0) flat.push_back({(low + high) / 2, area});
  }
  std::sort(flat.begin(), flat.end());
  std::vector<FlatLevel> levels;
  for (std::size_t i = 0; i < flat.size();) {
    // One level: the facets within the tolerance above the lowest of them, at the height of
    // the largest (an exact 8.00 stays 8.00, not an average of rounded heights).
    double area = 0, largest = 0, z = flat[i].first;
    std::size_t j = i;
    for (; j < flat.size() && flat[j].first - flat[i].first <= kFlatHeightTolerance; ++j) {
      area += flat[j].second;
      if (flat[j].second > largest) largest = flat[j].second, z = flat[j].first;
    }
    if (area >= min_area) levels.push_back({z, area});
    i = j;
  }
  return levels;
}

}  // namespace geometry
