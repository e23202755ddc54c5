#include "geometry/plan/slab_bound.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace geometry {

FacetsByHeight::FacetsByHeight(std::vector<std::pair<double, double>> ranges, double bucket_height)
    : ranges_(std::move(ranges)), bucket_height_(bucket_height) {
  if (ranges_.empty()) return;
  double z_lo = INFINITY, z_hi = -INFINITY;
  for (const auto& [low, high] : ranges_) z_lo = std::min(z_lo, low), z_hi = std::max(z_hi, high);
  z_0_ = z_lo;
  const std::size_t buckets = static_cast<std::size_t>(std::ceil((z_hi - z_lo) / bucket_height_)) + 1;
  bucket_begin_.assign(buckets + 1, 0);
  for (const auto& [low, high] : ranges_) {
    for (std::size_t b = bucket_of(low); b <= bucket_of(high); ++b) ++bucket_begin_[b + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) bucket_begin_[b + 1] += bucket_begin_[b];
  bucket_facets_.resize(bucket_begin_.back());
  std::vector<std::uint32_t> fill(bucket_begin_.begin(), bucket_begin_.end() - 1);
  for (std::uint32_t k = 0; k < ranges_.size(); ++k) {
    for (std::size_t b = bucket_of(ranges_[k].first); b <= bucket_of(ranges_[k].second); ++b) {
      bucket_facets_[fill[b]++] = k;
    }
  }
}

std::size_t FacetsByHeight::bucket_of(double z) const {
  const std::size_t buckets = bucket_begin_.size() - 1;
  return std::min(buckets - 1, static_cast<std::size_t>(std::max(0.0, (z - z_0_) / bucket_height_)));
}

namespace {

struct SlopedFacet {
  double low, high;
  double heights[3];  // its corners'
  Vec3 normal;        // cross(b - a, c - a): twice the area, outward for a consistent mesh
};

// Every facet with some height and some slope (neither vertical nor horizontal).
std::vector<SlopedFacet> sloped_facets(const Mesh& mesh) {
  std::vector<SlopedFacet> sloped;
  for (const auto& face : mesh.faces) {
    const Vec3 a = mesh.vertices[face[0]], b = mesh.vertices[face[1]], c = mesh.vertices[face[2]];
    const Vec3 n = cross(b - a, c - a);
    const double low = std::min({a.z, b.z, c.z}), high = std::max({a.z, b.z, c.z});
    // Vertical facets overhang nothing; horizontal ones (no height) are flat_levels.h's.
    if (!(high > low) || !(std::abs(n.z) > 0) || !(std::hypot(n.x, n.y) > 0)) continue;
    sloped.push_back({low, high, {a.z, b.z, c.z}, n});
  }
  return sloped;
}

}  // namespace

ThickOverhangEstimate::ThickOverhangEstimate(const Mesh& mesh, double overhang_angle_degrees,
                                             double bead_width)
    : half_bead_(bead_width / 2) {
  const double most = std::tan(std::clamp(overhang_angle_degrees, 0.0, 89.9) * std::numbers::pi / 180);
  std::vector<std::pair<double, double>> ranges;
  for (const SlopedFacet& f : sloped_facets(mesh)) {
    if (f.normal.z >= 0) continue;  // facing up: the layer below carries it
    const double lean = -f.normal.z / std::hypot(f.normal.x, f.normal.y);
    if (lean > most) continue;      // supported at any thickness
    Facet facet{lean, -0.5 * f.normal.z, {f.heights[0], f.heights[1], f.heights[2]}};
    std::sort(std::begin(facet.z), std::end(facet.z));
    facets_.push_back(facet);
    ranges.emplace_back(f.low, f.high);
  }
  by_height_ = FacetsByHeight(std::move(ranges));
}

// A plane triangle's part below h grows as (h - z0)^2 up to its middle corner and is the
// whole less (z2 - h)^2 above it, each scaled to meet the whole at the corners.
double ThickOverhangEstimate::Facet::area_below(double h) const {
  if (h <= z[0]) return 0;
  if (h >= z[2]) return area;
  if (h <= z[1]) return area * (h - z[0]) * (h - z[0]) / ((z[2] - z[0]) * (z[1] - z[0]));
  return area * (1 - (z[2] - h) * (z[2] - h) / ((z[2] - z[0]) * (z[2] - z[1])));
}

double ThickOverhangEstimate::operator()(double z_lo, double z_hi) const {
  const double t = z_hi - z_lo;
  double area = 0;
  by_height_.for_each(z_lo, z_hi, [&](std::size_t k) {
    const Facet& f = facets_[k];
    const double step = t * f.lean;
    if (step <= half_bead_) return;
    area += (f.area_below(z_hi) - f.area_below(z_lo)) * (1 - half_bead_ / step);
  });
  return area;
}

}  // namespace geometry
