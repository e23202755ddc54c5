#include "geometry/contour/ma/samples.h"

#include <algorithm>
#include <cmath>

namespace geometry::ma {

std::vector<Sample> sample_boundary_pair(const std::vector<const Loop*>& loops,
                                         const MaOptions& options) {
  std::size_t vertices = 0;
  double total = 0;  // the loops' length, or a bound on it while that keeps under the cap
  for (const Loop* loop : loops) {
    vertices += loop->size();
    total += perimeter_bound(*loop);
  }
  const std::size_t cap = std::max<std::size_t>(options.max_points, 16);
  // Over the cap even with vertices alone: keep every stride-th vertex.
  const std::size_t stride = vertices > cap ? (vertices + cap - 1) / cap : 1;
  double spacing = options.spacing > 0 ? options.spacing : kDefaultSpacing;
  if (stride == 1 && vertices + total / spacing > cap) {
    total = 0;
    for (const Loop* loop : loops) total += perimeter(*loop);
  }
  if (stride == 1 && vertices + total / spacing > cap) {
    spacing = total / static_cast<double>(cap - vertices + 1);
  }
  std::vector<Sample> samples;
  samples.reserve(std::min(cap + loops.size(), vertices + static_cast<std::size_t>(total / spacing) + 1));
  for (std::uint32_t l = 0; l < loops.size(); ++l) {
    const Loop& loop = *loops[l];
    const std::size_t n = loop.size();
    for (std::size_t j = 0; j < n; j += stride) {
      const Vec2 a = loop[j], b = loop[(j + 1) % n];
      samples.push_back({a, l, static_cast<std::uint32_t>(j)});
      if (stride > 1) continue;
      const int pieces = static_cast<int>(std::ceil(length(b - a) / spacing));
      for (int k = 1; k < pieces; ++k) {
        samples.push_back({a + (static_cast<double>(k) / pieces) * (b - a), l,
                           static_cast<std::uint32_t>(j)});
      }
    }
  }
  return samples;
}

}  // namespace geometry::ma
