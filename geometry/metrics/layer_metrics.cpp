#include "geometry/metrics/layer_metrics.h"

#include <utility>

#include "geometry/core/boundary_grid.h"
#include "geometry/metrics/missed_features.h"
#include "geometry/metrics/volume_deviation.h"
#include "geometry/metrics/volume_limit.h"

namespace geometry {

LayerReference layer_reference(const LayerStack& stack, std::size_t layer,
                               const MetricOptions& options) {
  return layer_reference(stack, layer, slab_of(stack, layer), options);
}

LayerReference layer_reference(const LayerStack& stack, std::size_t layer, Slab slab,
                               const MetricOptions& options) {
  LayerReference reference;
  if (layer >= stack.size()) return reference;
  reference.layer = stack.layers()[layer];
  reference.slab = std::move(slab);
  reference.islands = slab_islands(reference.slab);
  if (options.volumes) {
    reference.volumes = true;
    reference.columns = slab_columns(reference.slab, stack.lower(layer));
    reference.volume_limit = volume_limit(reference.columns);
  }
  reference.surface = slab_surface(reference.slab, options.distance);
  return reference;
}

LayerMetrics layer_metrics(const LayerReference& reference, const Region& region,
                           const MetricOptions& options) {
  LayerMetrics metrics;
  metrics.z_lo = reference.layer.z_lo;
  metrics.thickness = reference.layer.thickness();
  metrics.area = area(region);
  const BoundaryGrid walls(region);
  if (options.volumes) metrics.volume_deviation = volume_deviation(reference.columns, region, walls);
  metrics.volume_limit = reference.volume_limit;
  const std::vector<BoundaryPair> missed = missed_features(reference.islands, region);
  metrics.missed_features = missed.size();
  const DistanceError distance =
      distance_error(reference.surface, walls, missed, options.distance);
  metrics.distance = distance.forward;
  metrics.reverse_distance = distance.reverse;
  metrics.hausdorff = distance.hausdorff;
  return metrics;
}

LayerMetrics layer_metrics(const LayerStack& stack, std::size_t layer, const Region& region,
                           const MetricOptions& options) {
  return layer_metrics(layer_reference(stack, layer, options), region, options);
}

}  // namespace geometry
