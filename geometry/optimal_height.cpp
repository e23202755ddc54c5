#include "geometry/optimal_height.h"

#include <algorithm>
#include <cmath>

#include "geometry/slab.h"
#include "geometry/volume_deviation.h"

namespace geometry {

namespace {

// ∫ over a polygon of w0 + wx (x - o.x) + wy (y - o.y), and its area.
struct Integrals {
  double area = 0, integral = 0;
};
Integrals integrals(const std::vector<Vec2>& polygon, const ColumnFacet& w) {
  if (polygon.size() < 3) return {};
  const AreaMoments m = moments_of_loop(polygon, w.outline[0]);
  return {m.area, w.w0 * m.area + w.wx * m.mx + w.wy * m.my};
}

// The part of facet f where z_f <= h, i.e. w_f >= z_hi - h.
std::vector<Vec2> below(const ColumnFacet& f, double depth) {
  return clip_to_half_plane(f.outline, f.outline[0], f.w0 - depth, f.wx, f.wy);
}

}  // namespace

SectionDeviation::SectionDeviation(const SlabColumns& columns)
    : columns_(&columns), lower_grid_(columns.lower) {
  const double t = columns.thickness();
  const std::vector<std::vector<int>> overlapping = overlapping_facets(columns);
  partners_.resize(columns.facets.size());
  for (std::size_t a = 0; a < overlapping.size(); ++a) {
    for (int b : overlapping[a]) {
      partners_[a].push_back(b);
      partners_[b].push_back(static_cast<int>(a));
    }
  }
  occupied_lower_ = t * columns.lower_area;
  facets_.resize(columns.facets.size());
  for (std::size_t i = 0; i < columns.facets.size(); ++i) {
    const ColumnFacet& f = columns.facets[i];
    Facet& facet = facets_[i];
    double w_min = f.w0, w_max = f.w0;
    for (Vec2 p : f.outline) {
      const double w = f.w0 + f.wx * (p.x - f.outline[0].x) + f.wy * (p.y - f.outline[0].y);
      w_min = std::min(w_min, w);
      w_max = std::max(w_max, w);
    }
    facet.z_min = columns.z_hi - w_max;
    facet.z_max = columns.z_hi - w_min;
    const Integrals whole = integrals(f.outline, f);
    facet.area = whole.area;
    facet.integral = whole.integral;
    const AreaMoments in_lower = moments_of_intersection(f.outline, f.outline[0], lower_grid_, columns.lower);
    facet.area_in_lower = in_lower.area;
    occupied_lower_ += f.sign * (f.w0 * in_lower.area + f.wx * in_lower.mx + f.wy * in_lower.my);
    // Inside or outside C(z_lo) to a billionth of its area (a facet with an edge on the lower
    // contour is either), else the lower contour crosses it (a fold).
    const double slack = 1e-9 * std::abs(whole.area) + 1e-15;
    facet.lower = std::abs(in_lower.area - whole.area) <= slack ? 1
                  : std::abs(in_lower.area) <= slack           ? 0
                                                                : -1;
    for (int g : partners_[i]) {
      const ColumnFacet& other = columns.facets[g];
      facet.folds += f.sign * other.sign * integrals(convex_intersection(f.outline, other.outline), other).integral;
    }
  }
}

double SectionDeviation::operator()(double h) const {
  const SlabColumns& columns = *columns_;
  const double t = columns.thickness();
  double area = columns.lower_area, occupied = occupied_lower_;
  for (std::size_t i = 0; i < facets_.size(); ++i) {
    const Facet& facet = facets_[i];
    if (facet.z_min > h) continue;
    const ColumnFacet& f = columns.facets[i];
    if (facet.z_max <= h) {
      area += f.sign * facet.area;
      occupied += t * f.sign * facet.area_in_lower + facet.integral + facet.folds;
      continue;
    }
    const std::vector<Vec2> part = below(f, columns.z_hi - h);
    if (part.size() < 3) continue;
    const Integrals own = integrals(part, f);
    area += f.sign * own.area;
    const double in_lower =
        facet.lower == 1 ? own.area
        : facet.lower == 0 ? 0.0
                           : moments_of_intersection(part, part[0], lower_grid_, columns.lower).area;
    occupied += t * f.sign * in_lower + own.integral;
    for (int g : partners_[i]) {
      const ColumnFacet& other = columns.facets[g];
      occupied += f.sign * other.sign * integrals(convex_intersection(part, other.outline), other).integral;
    }
  }
  return std::max(columns.volume + t * area - 2 * occupied, 0.0);
}

OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const SlabColumns& columns, const OptimalHeightOptions& options) {
  OptimalHeight best;
  if (layer >= stack.size()) return best;
  const Layer bounds = stack.layers()[layer];
  const SectionDeviation deviation_at(columns);
  // At z_hi the section from above differs from the sum's (from below) only by faces lying in
  // that plane, which need a vertex there; if there is one, it is built, not summed.
  const bool face_on_top = !stack.vertex_heights_between(bounds.z_hi, bounds.z_hi).empty();
  const auto try_height = [&](double h) {
    const double deviation = h < bounds.z_hi || !face_on_top
                                 ? deviation_at(std::min(h, bounds.z_hi))
                                 : volume_deviation(columns, stack.cross_section(h));
    ++best.evaluations;
    if (best.evaluations == 1 || deviation < best.volume_deviation) {
      best.height = h;
      best.volume_deviation = deviation;
    }
    return deviation;
  };
  if (!(bounds.thickness() > 0)) {
    best.height = bounds.z_lo;
    best.section = stack.cross_section(bounds.z_lo);
    best.volume_deviation = volume_deviation(columns, best.section);
    best.evaluations = 1;
    return best;
  }
  const int samples = std::max(options.coarse_samples, 3);
  const double step = bounds.thickness() / (samples - 1);
  std::vector<double> deviation(samples);
  int best_sample = 0;
  for (int k = 0; k < samples; ++k) {
    deviation[k] = try_height(k + 1 == samples ? bounds.z_hi : bounds.z_lo + k * step);
    if (deviation[k] < deviation[best_sample]) best_sample = k;
  }
  // Golden section inside the bracket of the best sample.
  double a = bounds.z_lo + std::max(best_sample - 1, 0) * step;
  double b = std::min(bounds.z_lo + (best_sample + 1) * step, bounds.z_hi);
  constexpr double kInvPhi = 0.6180339887498949;
  double c = b - kInvPhi * (b - a), d = a + kInvPhi * (b - a);
  double fc = try_height(c), fd = try_height(d);
  const double tolerance = std::max(options.tolerance, 1e-9);
  while (b - a > tolerance) {
    if (fc <= fd) {
      b = d;
      d = c;
      fd = fc;
      c = b - kInvPhi * (b - a);
      fc = try_height(c);
    } else {
      a = c;
      c = d;
      fc = fd;
      d = a + kInvPhi * (b - a);
      fd = try_height(d);
    }
  }
  best.section = stack.cross_section(best.height);
  return best;
}

OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const OptimalHeightOptions& options) {
  if (layer >= stack.size()) return {};
  const SlabColumns columns = slab_columns(slab_of(stack, layer), stack.lower(layer));
  return optimal_height(stack, layer, columns, options);
}

}  // namespace geometry
