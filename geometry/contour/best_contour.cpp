#include "geometry/contour/best_contour.h"

#include <array>
#include <optional>
#include <vector>

#include "geometry/contour/ma_contour.h"
#include "geometry/contour/optimal_height.h"
#include "geometry/contour/section_contours.h"
#include "geometry/core/boundary_grid.h"
#include "geometry/metrics/missed_features.h"
#include "geometry/metrics/volume_deviation.h"
#include "geometry/slab/slab_columns.h"

namespace geometry {

BestChoice best_choice(const ContourInput& input) {
  // The candidates in the order ties are first looked at.
  constexpr std::array<std::string_view, 3> kNames{"mid", "optimal-height", "ma"};
  constexpr std::array<ContourFunction, 3> kCandidates{mid_strategy, optimal_height_strategy,
                                                       ma_strategy};
  std::optional<LayerReference> own;
  if (!input.reference) {
    MetricOptions metrics;
    metrics.volumes = false;
    own = layer_reference(input.stack, input.layer, metrics);
  }
  const LayerReference& reference = own ? *own : *input.reference;
  const ContourInput candidate_input{input.stack, input.layer, input.options, &reference};
  DistanceOptions distance_options;
  distance_options.reverse = false;

  BestChoice choice{};
  std::array<ContourResult, 3> results;
  // ΔV only where a tie needs it, with the slab's columns built then if the reference has none.
  std::array<double, 3> deviation{-1, -1, -1};
  const SlabColumns* columns = reference.volumes ? &reference.columns : nullptr;
  SlabColumns built;
  const auto volume_of = [&](std::size_t k) {
    if (deviation[k] < 0) {
      if (!columns) {
        built = slab_columns(reference.slab, input.stack.lower(input.layer));
        columns = &built;
      }
      deviation[k] = volume_deviation(*columns, results[k].region, BoundaryGrid(results[k].region));
    }
    return deviation[k];
  };
  std::size_t best = 0;
  for (std::size_t k = 0; k < kCandidates.size(); ++k) {
    results[k] = kCandidates[k](candidate_input);
    const BoundaryGrid walls(results[k].region);
    const std::vector<BoundaryPair> missed = missed_features(reference.islands, results[k].region);
    choice.candidate_distance[k] =
        distance_error(reference.surface, walls, missed, distance_options).forward;
    if (k == 0) continue;
    const double d = choice.candidate_distance[k], b = choice.candidate_distance[best];
    if (d < b - kDistanceTie || (d <= b + kDistanceTie && volume_of(k) < volume_of(best))) {
      best = k;
    }
  }
  choice.chosen = kNames[best];
  choice.distance = choice.candidate_distance[best];
  choice.result = std::move(results[best]);
  return choice;
}

ContourResult best_strategy(const ContourInput& input) { return best_choice(input).result; }

}  // namespace geometry
