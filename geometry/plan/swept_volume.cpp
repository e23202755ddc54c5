#include "geometry/plan/swept_volume.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace geometry {

SweptVolume::SweptVolume(const Mesh& mesh) {
  for (const auto& face : mesh.faces) {
    const Vec3 a = mesh.vertices[face[0]], b = mesh.vertices[face[1]], c = mesh.vertices[face[2]];
    const double area = 0.5 * std::abs(cross(b - a, c - a).z);
    if (!(area > 0)) continue;  // vertical: nothing seen from above
    double z[3] = {a.z, b.z, c.z};
    std::sort(z, z + 3);
    facets_.push_back({z[0], z[1], z[2], area});
  }
  std::sort(facets_.begin(), facets_.end(), [](const Facet& f, const Facet& g) { return f.z2 < g.z2; });
  tops_.reserve(facets_.size());
  area_sum_.assign(1, 0);
  moment_sum_.assign(1, 0);
  std::vector<std::pair<double, double>> ranges;
  for (const Facet& f : facets_) {
    tops_.push_back(f.z2);
    area_sum_.push_back(area_sum_.back() + f.area);
    moment_sum_.push_back(moment_sum_.back() + f.area * (f.z0 + f.z1 + f.z2) / 3);
    ranges.push_back({f.z0, f.z2});
  }
  by_height_ = FacetsByHeight(std::move(ranges));
}

double SweptVolume::integral_below(double z) const {
  // Facets wholly below z: each adds its area times (z - its mean height).
  const std::size_t below = static_cast<std::size_t>(std::upper_bound(tops_.begin(), tops_.end(), z) - tops_.begin());
  double q = area_sum_[below] * z - moment_sum_[below];
  // Facets spanning z: the integral of their share below, a cubic in each of two pieces.
  by_height_.for_each(z, std::nextafter(z, INFINITY), [&](std::size_t k) {
    const Facet& f = facets_[k];
    if (!(z > f.z0 && z < f.z2)) return;
    const double span = f.z2 - f.z0;
    double share;
    if (z <= f.z1) {
      const double u = z - f.z0;
      share = u * u * u / (3 * span * (f.z1 - f.z0));
    } else {
      const double lower = (f.z1 - f.z0) * (f.z1 - f.z0) / (3 * span);
      const double v = f.z2 - f.z1, w = f.z2 - z;
      share = lower + (z - f.z1) - (v * v * v - w * w * w) / (3 * span * v);
    }
    q += f.area * share;
  });
  return q;
}

double SweptVolume::operator()(double z_lo, double z_hi) const {
  if (!(z_hi > z_lo)) return 0;
  const double u = integral_below(z_lo) + integral_below(z_hi) - 2 * integral_below(0.5 * (z_lo + z_hi));
  return std::max(0.0, u);
}

}  // namespace geometry
