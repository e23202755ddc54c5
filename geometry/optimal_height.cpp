#include "geometry/optimal_height.h"

#include <algorithm>
#include <cmath>

#include "geometry/slab.h"
#include "geometry/volume_deviation.h"

namespace geometry {

OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const SlabColumns& columns, const OptimalHeightOptions& options) {
  OptimalHeight best;
  if (layer >= stack.size()) return best;
  const Layer bounds = stack.layers()[layer];
  const auto try_height = [&](double h) {
    Region section = stack.cross_section(h);
    const double deviation = volume_deviation(columns, section);
    ++best.evaluations;
    if (best.evaluations == 1 || deviation < best.volume_deviation) {
      best.height = h;
      best.volume_deviation = deviation;
      best.section = std::move(section);
    }
    return deviation;
  };
  if (!(bounds.thickness() > 0)) {
    try_height(bounds.z_lo);
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
  return best;
}

OptimalHeight optimal_height(const LayerStack& stack, std::size_t layer,
                             const OptimalHeightOptions& options) {
  if (layer >= stack.size()) return {};
  const SlabColumns columns = slab_columns(slab_of(stack, layer), stack.lower(layer));
  return optimal_height(stack, layer, columns, options);
}

}  // namespace geometry
