#include "geometry/plan/slab_bound.h"

#include <algorithm>
#include <cmath>

namespace geometry {

SlabSpreadEstimate::SlabSpreadEstimate(const Mesh& mesh) {
  double z_lo = INFINITY, z_hi = -INFINITY;
  for (const auto& face : mesh.faces) {
    const Vec3 a = mesh.vertices[face[0]], b = mesh.vertices[face[1]], c = mesh.vertices[face[2]];
    const Vec3 n = cross(b - a, c - a);
    const double horizontal = std::hypot(n.x, n.y), vertical = std::abs(n.z);
    const double low = std::min({a.z, b.z, c.z}), high = std::max({a.z, b.z, c.z});
    // Vertical facets spread nothing; horizontal ones (no height) are flat_levels.h's.
    if (!(high > low) || !(vertical > 0) || !(horizontal > 0)) continue;
    facets_.push_back({low, high, vertical / horizontal});
    z_lo = std::min(z_lo, low);
    z_hi = std::max(z_hi, high);
  }
  if (facets_.empty()) return;
  z_0_ = z_lo;
  const std::size_t buckets =
      static_cast<std::size_t>(std::ceil((z_hi - z_lo) / bucket_height_)) + 1;
  auto bucket = [&](double z) {
    return std::min(buckets - 1, static_cast<std::size_t>(std::max(0.0, (z - z_0_) / bucket_height_)));
  };
  bucket_begin_.assign(buckets + 1, 0);
  for (const Facet& f : facets_) {
    for (std::size_t b = bucket(f.z_min); b <= bucket(f.z_max); ++b) ++bucket_begin_[b + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) bucket_begin_[b + 1] += bucket_begin_[b];
  bucket_facets_.resize(bucket_begin_.back());
  std::vector<std::uint32_t> fill(bucket_begin_.begin(), bucket_begin_.end() - 1);
  for (std::uint32_t i = 0; i < facets_.size(); ++i) {
    for (std::size_t b = bucket(facets_[i].z_min); b <= bucket(facets_[i].z_max); ++b) {
      bucket_facets_[fill[b]++] = i;
    }
  }
}

double SlabSpreadEstimate::operator()(double z_lo, double z_hi) const {
  if (facets_.empty() || !(z_hi > z_lo)) return 0;
  const std::size_t buckets = bucket_begin_.size() - 1;
  const double first = std::floor((z_lo - z_0_) / bucket_height_);
  const double last = std::floor((z_hi - z_0_) / bucket_height_);
  if (last < 0 || first >= static_cast<double>(buckets)) return 0;
  double widest = 0;
  for (std::size_t b = static_cast<std::size_t>(std::max(first, 0.0)),
                   e = std::min(buckets - 1, static_cast<std::size_t>(last));
       b <= e; ++b) {
    for (std::uint32_t k = bucket_begin_[b]; k < bucket_begin_[b + 1]; ++k) {
      const Facet& f = facets_[bucket_facets_[k]];
      const double overlap = std::min(z_hi, f.z_max) - std::max(z_lo, f.z_min);
      if (overlap > 0) widest = std::max(widest, overlap * f.spread_per_mm);
    }
  }
  return 0.5 * widest;
}

}  // namespace geometry
